//! "Did you mean" suggestions for topic and field names.

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

/// The candidate closest to `name`, if it is close enough to be a likely typo (or
/// contains `name`).
pub(crate) fn closest<'c>(name: &str, candidates: impl Iterator<Item = &'c str>) -> Option<String> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = if c.contains(name) && !name.is_empty() {
            1
        } else {
            distance(name, c)
        };
        if best.map_or(true, |(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    best.filter(|&(d, _)| d <= (name.len() / 3).max(2))
        .map(|(_, c)| c.to_owned())
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
}
