//! [`FlightAnalysis::json`]: the one JSON form of an analysis, which `ulog analyze
//! --json` prints and Python's `ulog_rs.analyze` returns.

use std::fmt::Write as _;

use super::FlightAnalysis;
use crate::json_text::push_string;

/// A JSON object or array being written.
struct Out {
    s: String,
    /// Whether the innermost object or array has a member yet.
    first: Vec<bool>,
}

impl Out {
    fn sep(&mut self) {
        if let Some(first) = self.first.last_mut() {
            if !*first {
                self.s.push(',');
            }
            *first = false;
        }
    }
    fn open(&mut self, key: Option<&str>, c: char) {
        self.key(key);
        self.s.push(c);
        self.first.push(true);
    }
    fn close(&mut self, c: char) {
        self.first.pop();
        self.s.push(c);
    }
    fn key(&mut self, key: Option<&str>) {
        self.sep();
        if let Some(k) = key {
            push_string(&mut self.s, k.chars());
            self.s.push(':');
        }
    }
    fn raw(&mut self, key: &str, v: &str) {
        self.key(Some(key));
        self.s.push_str(v);
    }
    fn text(&mut self, key: &str, v: &str) {
        self.key(Some(key));
        push_string(&mut self.s, v.chars());
    }
    fn num(&mut self, key: &str, v: Option<f64>) {
        match v.filter(|v| v.is_finite()) {
            Some(v) => {
                self.key(Some(key));
                let _ = write!(self.s, "{v}");
            }
            None => self.raw(key, "null"),
        }
    }
    fn int(&mut self, key: &str, v: Option<u64>) {
        match v {
            Some(v) => {
                self.key(Some(key));
                let _ = write!(self.s, "{v}");
            }
            None => self.raw(key, "null"),
        }
    }
}

impl FlightAnalysis {
    /// The analysis as one JSON object (one line): `diagnostics` (each `{id,
    /// severity, timestamp_us, end_timestamp_us, summary, evidence}`, Flight Review
    /// v2's form), `flight` (span, armed and airborne time, takeoff, modes, events),
    /// `stats`, `battery`, `gps`, `vibration` (with the spectra's dominant
    /// frequencies), `step_response`, `notes` and `damaged_stretches`. Floats that are
    /// not finite are `null`.
    ///
    /// ```
    /// let bytes = ulog_core::testing::sample_log();
    /// let flight = ulog_core::analysis::analyze(&bytes, &Default::default())?;
    /// let json = flight.json();
    /// assert!(json.starts_with(r#"{"diagnostics":[]"#));
    /// # Ok::<(), ulog_core::ReadError>(())
    /// ```
    pub fn json(&self) -> String {
        let mut o = Out {
            s: String::new(),
            first: Vec::new(),
        };
        o.open(None, '{');
        o.open(Some("diagnostics"), '[');
        for d in &self.diagnostics {
            o.open(None, '{');
            o.text("id", d.id);
            o.text("severity", d.severity.as_str());
            o.int("timestamp_us", Some(d.timestamp_us));
            o.int("end_timestamp_us", d.end_timestamp_us);
            o.text("summary", &d.summary);
            o.raw("evidence", &d.evidence.json());
            o.close('}');
        }
        o.close(']');

        let t = &self.timeline;
        o.open(Some("flight"), '{');
        o.int("start_us", self.span_us.map(|s| s.0));
        o.int("end_us", self.span_us.map(|s| s.1));
        o.num("armed_s", Some(t.armed_s));
        o.num("airborne_s", Some(t.airborne_s));
        o.int("takeoff_us", t.takeoff_us());
        o.open(Some("modes"), '[');
        for m in &t.modes {
            o.open(None, '{');
            o.int("mode", Some(u64::from(m.mode)));
            o.text("name", &m.name);
            o.int("start_us", Some(m.start_us));
            o.int("end_us", Some(m.end_us));
            o.close('}');
        }
        o.close(']');
        o.open(Some("events"), '[');
        for (time, kind) in &t.events {
            o.open(None, '{');
            o.int("timestamp_us", Some(*time));
            o.text("kind", kind.as_str());
            o.close('}');
        }
        o.close(']');
        o.close('}');

        let s = &self.stats;
        o.open(Some("stats"), '{');
        for (k, v) in [
            ("total_distance_m", s.total_distance_m),
            ("flown_distance_m", s.flown_distance_m),
            ("max_altitude_diff_m", s.max_altitude_diff_m),
            ("max_altitude_above_start_m", s.max_altitude_above_start_m),
            ("max_speed_m_s", s.max_speed_m_s),
            ("max_horizontal_speed_m_s", s.max_horizontal_speed_m_s),
            ("max_speed_up_m_s", s.max_speed_up_m_s),
            ("max_speed_down_m_s", s.max_speed_down_m_s),
            ("avg_speed_m_s", s.avg_speed_m_s),
            ("max_tilt_deg", s.max_tilt_deg),
            ("max_rotation_speed_deg_s", s.max_rotation_speed_deg_s),
        ] {
            o.num(k, Some(v));
        }
        o.close('}');

        let b = &self.battery;
        o.open(Some("battery"), '{');
        o.num("min_voltage_v", b.min_voltage_v);
        o.num("avg_current_a", b.avg_current_a);
        o.num("max_current_a", b.max_current_a);
        o.num("discharged_mah", b.discharged_mah);
        o.close('}');

        match &self.gps {
            Some(g) => {
                o.open(Some("gps"), '{');
                o.text("topic", &g.topic);
                o.int("min_satellites", g.min_satellites.map(u64::from));
                o.int("max_satellites", g.max_satellites.map(u64::from));
                o.num("max_hdop", g.max_hdop.map(f64::from));
                o.num("max_eph_m", g.max_eph_m.map(f64::from));
                o.num("max_epv_m", g.max_epv_m.map(f64::from));
                o.open(Some("fix_types_seen"), '[');
                for f in &g.fix_types_seen {
                    o.key(None);
                    let _ = write!(o.s, "{f}");
                }
                o.close(']');
                o.close('}');
            }
            None => o.raw("gps", "null"),
        }

        let v = &self.vibration;
        o.open(Some("vibration"), '{');
        o.num("accel_vibe_mean", v.accel_vibe_mean);
        o.num("accel_vibe_max", v.accel_vibe_max);
        o.text("status", v.status);
        o.open(Some("spectra"), '[');
        for a in &self.spectra {
            o.open(None, '{');
            o.text("topic", a.topic);
            o.text("signal", &a.signal);
            o.num("rate_hz", Some(a.rate_hz));
            o.int("segments", Some(a.segments as u64));
            o.open(Some("dominant"), '[');
            for p in &a.dominant {
                o.open(None, '{');
                o.num("frequency_hz", Some(p.frequency_hz));
                o.num("psd", Some(p.value));
                o.close('}');
            }
            o.close(']');
            o.close('}');
        }
        o.close(']');
        o.close('}');

        o.open(Some("step_response"), '[');
        for a in &self.step_responses {
            let m = a.metrics.as_ref();
            o.open(None, '{');
            o.text("axis", a.axis);
            o.num("rate_hz", Some(a.rate_hz));
            o.int("windows", Some(a.response.windows.len() as u64));
            o.num("rise_time_s", m.and_then(|m| m.rise_time_s));
            o.num("overshoot_percent", m.map(|m| m.overshoot_percent));
            o.num("settling_time_s", m.and_then(|m| m.settling_time_s));
            o.num("peak", m.map(|m| m.peak));
            o.close('}');
        }
        o.close(']');

        o.open(Some("notes"), '[');
        for n in &self.notes {
            o.key(None);
            push_string(&mut o.s, n.chars());
        }
        o.close(']');
        let damaged = self.findings.iter().filter(|f| f.is_damage()).count();
        o.int("damaged_stretches", Some(damaged as u64));
        o.close('}');
        o.s
    }
}
