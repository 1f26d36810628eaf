//! "Did you mean" suggestions: the names close to a name that is not there (a topic,
//! a field, a type), shared by the reader and the derive macros so that both suggest
//! alike.
//!
//! ```
//! let types = ["float", "double", "uint8_t"];
//! assert_eq!(ulog_format::suggest::closest("flaot", types.into_iter()).as_deref(), Some("float"));
//! assert_eq!(ulog_format::suggest::closest("battery", types.into_iter()), None);
//! ```

/// The edit distance of `a` and `b` when it is at most `limit`, else `None`: the
/// table's rows never get smaller, so it stops at the first row whose every entry is
/// past the limit.
fn distance_within(a: &str, b: &str, limit: usize) -> Option<usize> {
    let b: Vec<char> = b.chars().collect();
    // Two rows of the table, swapped: no allocation per character (a name that is
    // not found is compared with every topic of the log, for every binding a
    // program tries).
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        if cur.iter().all(|&d| d > limit) {
            return None;
        }
        core::mem::swap(&mut prev, &mut cur);
    }
    Some(prev[b.len()]).filter(|&d| d <= limit)
}

/// How far `candidate` is from `name`: 1 when it contains `name` (a binding named
/// `local_position` for `vehicle_local_position`), else the edit distance; `None` when
/// it is too far to be a likely meaning.
fn closeness(name: &str, candidate: &str) -> Option<usize> {
    let limit = (name.len() / 3).max(2);
    if !name.is_empty() && candidate.contains(name) {
        return Some(1);
    }
    // The distance is at least the difference of the lengths: most candidates are
    // too far by that alone, without the table.
    let (n, c) = (name.chars().count(), candidate.chars().count());
    if n.abs_diff(c) > limit {
        return None;
    }
    distance_within(name, candidate, limit)
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
    use super::closeness;

    /// The edit distance by the whole table, as a reference.
    #[allow(clippy::needless_range_loop)]
    fn distance(a: &str, b: &str) -> usize {
        let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
        let mut t = vec![vec![0; b.len() + 1]; a.len() + 1];
        for (i, row) in t.iter_mut().enumerate() {
            row[0] = i;
        }
        for (j, cell) in t[0].iter_mut().enumerate() {
            *cell = j;
        }
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                t[i][j] = (t[i - 1][j - 1] + cost)
                    .min(t[i - 1][j] + 1)
                    .min(t[i][j - 1] + 1);
            }
        }
        t[a.len()][b.len()]
    }

    /// The shortcut by length gives what the whole table gives, on names of every
    /// length against each other (PX4 topics, typos, Unicode, empty).
    #[test]
    fn closeness_is_the_distance_within_the_limit() {
        let names = [
            "",
            "a",
            "gps",
            "sensor_gps",
            "vehicle_gps_position",
            "sensor_combined",
            "sensr_combined",
            "vehicle_attitude",
            "vehicle_atitude",
            "attitude",
            "battery_status",
            "batery_status",
            "estimator_status_flags",
            "cpuload",
            "cpu_load",
            "ßensor_gps",
            "sensor_gpš",
            "éééé",
            "eeee",
        ];
        for name in names {
            for c in names {
                let limit = (name.len() / 3).max(2);
                let d = if !name.is_empty() && c.contains(name) {
                    1
                } else {
                    distance(name, c)
                };
                assert_eq!(
                    closeness(name, c),
                    (d <= limit).then_some(d),
                    "{name:?} {c:?}"
                );
            }
        }
    }

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
