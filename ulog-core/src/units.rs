//! Units of PX4 fields, from their names: PX4 names a field by what it holds and
//! in what unit (`accelerometer_m_s2`, `voltage_v`, `baro_alt_meter`), and its
//! messages' documentation uses the same words. [`unit_of`] applies the rule; `ulog
//! plot` labels its axes with it, `ulog dump` prints values with it, and the Parquet
//! export writes it beside each column (`ulog.unit.<field>`).
//!
//! ```
//! use ulog_core::units::unit_of;
//! assert_eq!(unit_of("sensor_combined", "accelerometer_m_s2[2]"), Some("m/s²"));
//! assert_eq!(unit_of("vehicle_local_position", "vz"), Some("m/s"));
//! assert_eq!(unit_of("esc_status", "esc[3].esc_voltage"), Some("V"));
//! assert_eq!(unit_of("vehicle_attitude", "q[0]"), None);
//! ```
//!
//! The rule, on the last component of the field path with any `[i]` index removed
//! (`esc[2].esc_voltage` → `esc_voltage`), letters compared without case:
//!
//! 1. A few whole names: `gyro_rad` is rad/s (PX4 logs rates under that name);
//!    `rollspeed`, `pitchspeed`, `yawspeed` rad/s; `roll`, `pitch`, `yaw` rad/s in rate
//!    topics (`*rates*`, `*angular_velocity*`); `roll`, `pitch`, `yaw`, `heading`,
//!    `roll_body`, `pitch_body`, `yaw_body` rad in attitude and position topics
//!    (`*attitude*`, `*local_position*`, `*global_position*`, `*odometry*`, `*gps*`,
//!    `*gnss*`; elsewhere they are stick inputs or test ratios); `temperature` °C; and
//!    in position and odometry topics (`*local_position*`, `*odometry*`,
//!    `*position_setpoint*`): `x`, `y`, `z`, `dist_bottom`, `eph`, `epv` m; `vx`, `vy`,
//!    `vz`, `evh`, `evv` m/s; `ax`, `ay`, `az` m/s².
//! 2. Otherwise the name's `_`-separated suffix: `_m_s2` and `_m_s_s` m/s², `_m_s` m/s,
//!    `_rad_s` rad/s, `_deg_s` deg/s, `_kb_s` kB/s; then the last word alone:
//!    `m`/`meter`/`meters` m, `rad` rad, `deg` deg, `v`/`voltage` V, `a` A (and
//!    `current` as the whole name: `seq_current` is an index), `c`/`celcius`/`celsius`
//!    °C, `hpa` hPa, `pa` Pa, `mbar` mbar, `ga`/`gauss` Ga, `us`/`usec` µs, `ms` ms,
//!    `s`/`sec` s, `hz` Hz, `mah` mAh, `w` W, `rpm` rpm, `percent` %, `kg` kg. A
//!    one-letter word (and `us`, `ms`, `hz`, …) is a unit only after another word: PX4
//!    has fields named `a`, `v`, `s`; and none after `per` (`noise_per_ms` is a count
//!    per millisecond).
//! 3. Anything else has no unit: `None` (the name does not say; not "dimensionless").

/// The unit of field `path` (a column name as `ulog csv` writes it: `q[0]`,
/// `esc[2].esc_rpm`, or a field name) of topic `topic`, if its name says it.
pub fn unit_of(topic: &str, path: &str) -> Option<&'static str> {
    let last = path.rsplit('.').next().unwrap_or(path);
    let name = match last.find('[') {
        Some(i) => &last[..i],
        None => last,
    };
    let name = name.to_ascii_lowercase();
    if let Some(u) = by_whole_name(topic, &name) {
        return Some(u);
    }
    let words: Vec<&str> = name.split('_').filter(|w| !w.is_empty()).collect();
    if words.len() >= 2 {
        let pair = (words[words.len() - 2], words[words.len() - 1]);
        let triple = (words.len() >= 3).then(|| words[words.len() - 3]);
        let u = match pair {
            ("m", "s2") => Some("m/s²"),

            ("s", "s") if triple == Some("m") => Some("m/s²"),
            ("kb", "s") => Some("kB/s"),
            ("m", "s") => Some("m/s"),
            ("rad", "s") => Some("rad/s"),
            ("deg", "s") => Some("deg/s"),
            _ => None,
        };
        if u.is_some() {
            return u;
        }
    }
    // `noise_per_ms`, `counts_per_s`: a rate of something the name does not say.
    if words.len() >= 2 && words[words.len() - 2] == "per" {
        return None;
    }
    // A one-word name is only a unit when it says so in full (`voltage`, not `v`).
    let last_word = *words.last()?;
    let short_ok = words.len() >= 2;
    Some(match last_word {
        "m" if short_ok => "m",
        "meter" | "meters" => "m",
        "rad" if short_ok => "rad",
        "deg" if short_ok => "deg",
        "v" if short_ok => "V",
        "voltage" => "V",
        "a" if short_ok => "A",
        // After other words it names which (`seq_current`), not a current.
        "current" if !short_ok => "A",
        "c" if short_ok => "°C",
        "celcius" | "celsius" => "°C",
        "hpa" => "hPa",
        "pa" if short_ok => "Pa",
        "mbar" => "mbar",
        "ga" if short_ok => "Ga",
        "gauss" => "Ga",
        "us" | "usec" if short_ok => "µs",
        "ms" if short_ok => "ms",
        "s" | "sec" if short_ok => "s",
        "hz" if short_ok => "Hz",
        "mah" => "mAh",
        "w" if short_ok => "W",
        "rpm" => "rpm",
        "percent" => "%",
        "kg" if short_ok => "kg",
        _ => return None,
    })
}

fn by_whole_name(topic: &str, name: &str) -> Option<&'static str> {
    let within = |topics: &[&str]| topics.iter().any(|t| topic.contains(t));
    let spatial = within(&["local_position", "odometry", "position_setpoint"]);
    // Angles are angles in attitude and position topics; in rate topics they name
    // rates, in others (stick inputs, test ratios) something else.
    let rates = within(&["rates", "angular_velocity"]);
    let angles = !rates
        && within(&[
            "attitude",
            "local_position",
            "global_position",
            "odometry",
            "gps",
            "gnss",
        ]);
    Some(match name {
        "gyro_rad" => "rad/s",
        "rollspeed" | "pitchspeed" | "yawspeed" => "rad/s",
        "roll" | "pitch" | "yaw" if rates => "rad/s",
        "roll" | "pitch" | "yaw" | "heading" | "roll_body" | "pitch_body" | "yaw_body"
            if angles =>
        {
            "rad"
        }
        "temperature" => "°C",
        "x" | "y" | "z" | "dist_bottom" | "eph" | "epv" if spatial => "m",
        "vx" | "vy" | "vz" | "evh" | "evv" if spatial => "m/s",
        "ax" | "ay" | "az" if spatial => "m/s²",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::unit_of;

    #[test]
    fn common_px4_fields() {
        let cases = [
            ("vehicle_local_position", "z", Some("m")),
            ("vehicle_local_position", "vx", Some("m/s")),
            ("vehicle_local_position", "ax", Some("m/s²")),
            ("vehicle_odometry", "x", Some("m")),
            ("sensor_mag", "x", None),
            ("sensor_combined", "gyro_rad[2]", Some("rad/s")),
            ("sensor_combined", "accelerometer_m_s2[0]", Some("m/s²")),
            ("sensor_combined", "magnetometer_ga[1]", Some("Ga")),
            ("sensor_combined", "baro_alt_meter", Some("m")),
            ("sensor_combined", "baro_temp_celcius", Some("°C")),
            ("battery_status", "voltage_v", Some("V")),
            ("battery_status", "voltage_filtered_v", Some("V")),
            ("battery_status", "current_a", Some("A")),
            ("battery_status", "discharged_mah", Some("mAh")),
            ("battery_status", "remaining", None),
            ("esc_status", "esc[2].esc_rpm", Some("rpm")),
            ("esc_status", "esc[2].esc_voltage", Some("V")),
            ("vehicle_attitude", "rollspeed", Some("rad/s")),
            ("vehicle_attitude", "q[0]", None),
            ("vehicle_attitude_setpoint", "yaw_body", Some("rad")),
            ("vehicle_air_data", "baro_pressure_pa", Some("Pa")),
            ("sensor_baro", "pressure_hpa", Some("hPa")),
            ("vehicle_gps_position", "vel_m_s", Some("m/s")),
            ("vehicle_gps_position", "time_utc_usec", Some("µs")),
            ("vehicle_rates_setpoint", "thrust_body[2]", None),
            ("vehicle_status", "arming_state", None),
            ("vehicle_gps_position", "noise_per_ms", None),
            ("logger_status", "write_rate_kb_s", Some("kB/s")),
            (
                "vehicle_imu_status",
                "accel_inconsistency_m_s_s",
                Some("m/s²"),
            ),
            ("mission_result", "seq_current", None),
            ("px4io_status", "alarm_acc_current", None),
            ("manual_control_setpoint", "roll", None),
            ("vehicle_rates_setpoint", "roll", Some("rad/s")),
            ("vehicle_attitude_setpoint", "roll_body", Some("rad")),
            ("estimator_innovation_test_ratios", "heading", None),
            ("vehicle_local_position", "heading", Some("rad")),
        ];
        for (topic, field, unit) in cases {
            assert_eq!(unit_of(topic, field), unit, "{topic}.{field}");
        }
    }

    #[test]
    fn one_letter_words_need_a_stem() {
        // `a`, `v`, `m`, `s` alone are not units (PX4 has fields named `a` or `v`).
        for f in ["a", "v", "m", "s", "c", "w"] {
            assert_eq!(unit_of("some_topic", f), None, "{f}");
        }
    }
}
