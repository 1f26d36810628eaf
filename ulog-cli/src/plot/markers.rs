//! Events marked on the time axis: parameter changes, and logged messages of level
//! ERROR or worse.

use ulog_core::read::LogLevel;
use ulog_core::ULog;

use crate::pyfmt::value_text;

/// What a marker stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A parameter set during the flight (a parameter message after the header).
    Param,
    /// A logged (or tagged logged) message of level EMERGENCY, ALERT, CRITICAL or ERROR.
    Error,
}

/// One vertical line on the plot, with its label.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Seconds since log start.
    pub x: f64,
    /// Parameter change or error message.
    pub kind: Kind,
    /// `NAME=value` or the message text, at most [`MAX_LABEL`] characters.
    pub label: String,
}

/// The longest label drawn, in characters; longer ones end in `…`.
pub const MAX_LABEL: usize = 48;

/// Every parameter change of `log`, as `NAME=value`.
pub fn param_changes(log: &ULog<'_>, start_us: u64) -> Vec<Marker> {
    log.param_changes()
        .iter()
        .map(|p| Marker {
            x: seconds(p.timestamp, start_us),
            kind: Kind::Param,
            label: truncate(&format!("{}={}", p.kv.name(), value_text(&p.kv.value()))),
        })
        .collect()
}

/// Every logged message, tagged or not, of level ERROR or worse.
pub fn errors(log: &ULog<'_>, start_us: u64) -> Vec<Marker> {
    log.logged_messages()
        .iter()
        .filter(|m| m.level().is_some_and(|l| l <= LogLevel::Error))
        .map(|m| Marker {
            x: seconds(m.timestamp, start_us),
            kind: Kind::Error,
            label: truncate(m.text.until_nul().to_string_lossy().trim()),
        })
        .collect()
}

fn seconds(t: u64, start_us: u64) -> f64 {
    (t as f64 - start_us as f64) / 1e6
}

/// `s` cut to [`MAX_LABEL`] characters, with `…` when cut.
pub fn truncate(s: &str) -> String {
    if s.chars().count() <= MAX_LABEL {
        return s.to_owned();
    }
    let mut t: String = s.chars().take(MAX_LABEL - 1).collect();
    t.push('…');
    t
}

/// Markers of one kind closer than `within` seconds merged into one line whose label
/// lists them (`A=1, B=2`), so labels at the same moment do not overprint; sorted by time.
pub fn merge_close(mut markers: Vec<Marker>, within: f64) -> Vec<Marker> {
    markers.sort_by(|a, b| a.x.total_cmp(&b.x));
    let mut out: Vec<(Marker, Vec<String>)> = Vec::new();
    for m in markers {
        match out
            .iter_mut()
            .rev()
            .find(|(o, _)| o.kind == m.kind && m.x - o.x <= within)
        {
            Some((_, labels)) => {
                if !labels.contains(&m.label) {
                    labels.push(m.label)
                }
            }
            None => {
                let label = m.label.clone();
                out.push((m, vec![label]));
            }
        }
    }
    out.into_iter()
        .map(|(mut m, labels)| {
            m.label = truncate(&labels.join(", "));
            m
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(x: f64, kind: Kind, label: &str) -> Marker {
        Marker {
            x,
            kind,
            label: label.into(),
        }
    }

    #[test]
    fn labels_are_cut_with_an_ellipsis() {
        let long = "x".repeat(100);
        let t = truncate(&long);
        assert_eq!(t.chars().count(), MAX_LABEL);
        assert!(t.ends_with('…'));
        assert_eq!(truncate("short"), "short");
    }

    #[test]
    fn close_markers_of_one_kind_merge() {
        let merged = merge_close(
            vec![
                m(10.0, Kind::Param, "B=2"),
                m(1.0, Kind::Param, "A=1"),
                m(1.05, Kind::Param, "C=3"),
                m(1.0, Kind::Error, "boom"),
                m(1.02, Kind::Error, "boom"),
            ],
            0.1,
        );
        assert_eq!(
            merged,
            vec![
                m(1.0, Kind::Param, "A=1, C=3"),
                m(1.0, Kind::Error, "boom"),
                m(10.0, Kind::Param, "B=2"),
            ]
        );
    }

    #[test]
    fn errors_are_level_error_or_worse_tagged_or_not() {
        let mut b = ulog_core::testing::LogBuilder::new(1, 100);
        b.flag_bits([0; 8], [0; 8], [0; 3]);
        b.log(b'3', 2_000_100, "motor failure");
        b.log(b'4', 3_000_100, "just a warning");
        b.tagged_log(b'0', 7, 4_000_100, "emergency");
        let bytes = b.bytes();
        let log = ULog::parse(bytes).unwrap();
        let e = errors(&log, 100);
        assert_eq!(
            e,
            vec![
                m(2.0, Kind::Error, "motor failure"),
                m(4.0, Kind::Error, "emergency")
            ]
        );
    }
}
