//! "Did you mean" suggestions: the names close to a name that is not there (a topic,
//! a field, a type), shared by the reader and the derive macros so that both suggest
//! alike.
//!
//! ```
//! let types = ["float", "double", "uint8_t"];
//! assert_eq!(ulog_format::suggest::closest("flaot", types.into_iter()).as_deref(), Some("float"));
//! assert_eq!(ulog_format::suggest::closest("battery", types.into_iter()), None);
//! ```

fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// How far `candidate` is from `name`: 1 when it contains `name` (a binding named
/// `local_position` for `vehicle_local_position`), else the edit distance; `None` when
/// it is too far to be a likely meaning.
fn closeness(name: &str, candidate: &str) -> Option<usize> {
    let d = if !name.is_empty() && candidate.contains(name) {
        1
    } else {
        distance(name, candidate)
    };
    (d <= (name.len() / 3).max(2)).then_some(d)
}

/// The candidate closest to `name`, if it is close enough to be a likely typo (or
/// contains `name`).
pub fn closest<'c>(name: &str, candidates: impl Iterator<Item = &'c str>) -> Option<String> {
    closest_n(name, candidates, 1).pop()
}

/// Up to `n` candidates close to `name`, closest first (ties in the candidates'
/// order), each once.
pub fn closest_n<'c>(
    name: &str,
    candidates: impl Iterator<Item = &'c str>,
    n: usize,
) -> Vec<String> {
    let mut found: Vec<(usize, &str)> = Vec::new();
    for c in candidates {
        if c == name || found.iter().any(|&(_, f)| f == c) {
            continue;
        }
        if let Some(d) = closeness(name, c) {
            found.push((d, c));
        }
    }
    found.sort_by_key(|&(d, _)| d);
    found
        .into_iter()
        .take(n)
        .map(|(_, c)| c.to_owned())
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn suggests_close_names_only() {
        let names = ["vehicle_attitude", "vehicle_status", "sensor_combined"];
        assert_eq!(
            super::closest("vehicle_atitude", names.into_iter()).as_deref(),
            Some("vehicle_attitude")
        );
        assert_eq!(super::closest("battery", names.into_iter()), None);
    }

    #[test]
    fn suggests_the_names_a_part_of_a_name_is_in() {
        let names = [
            "vehicle_local_position",
            "vehicle_local_position_setpoint",
            "vehicle_global_position",
            "vehicle_local_position",
        ];
        assert_eq!(
            super::closest_n("local_position", names.into_iter(), 3),
            ["vehicle_local_position", "vehicle_local_position_setpoint"]
        );
    }
}
