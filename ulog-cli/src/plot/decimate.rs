//! Fewer points for long series, without losing what a reader of the plot would see.
//!
//! The x range is cut into one bucket per pixel column of the plot. Of the points in a
//! bucket, at most four are kept: the first, the last, the lowest and the highest, in
//! time order. A line through them covers the same pixels as a line through all points
//! (spikes survive, gaps stay gaps), and an SVG stays small however long the log.

/// Points of `points` (sorted by x) kept for a plot `columns` pixels wide over
/// `x0..=x1`; all of them when there are no more than four per column.
pub fn decimate(points: &[(f64, f64)], x0: f64, x1: f64, columns: usize) -> Vec<(f64, f64)> {
    let columns = columns.max(1);
    let span = x1 - x0;
    if points.len() <= 4 * columns || span.is_nan() || span <= 0.0 {
        return points.to_vec();
    }
    let scale = columns as f64 / span;
    let bucket = |x: f64| (((x - x0) * scale) as usize).min(columns - 1);
    let mut out = Vec::with_capacity(4 * columns);
    let mut start = 0;
    while start < points.len() {
        let b = bucket(points[start].0);
        let mut end = start + 1;
        while end < points.len() && bucket(points[end].0) == b {
            end += 1;
        }
        let run = &points[start..end];
        let (mut lo, mut hi) = (0, 0);
        for (i, p) in run.iter().enumerate() {
            if p.1 < run[lo].1 {
                lo = i;
            }
            if p.1 > run[hi].1 {
                hi = i;
            }
        }
        let mut keep = [0, lo, hi, run.len() - 1];
        keep.sort_unstable();
        let mut last = None;
        for i in keep {
            if last != Some(i) {
                out.push(run[i]);
                last = Some(i);
            }
        }
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::decimate;

    #[test]
    fn short_series_are_kept_whole() {
        let p: Vec<(f64, f64)> = (0..40).map(|i| (i as f64, (i * i) as f64)).collect();
        assert_eq!(decimate(&p, 0.0, 39.0, 10), p);
    }

    #[test]
    fn at_most_four_points_per_column_and_spikes_survive() {
        let mut p: Vec<(f64, f64)> = (0..100_000).map(|i| (i as f64 / 1000.0, 1.0)).collect();
        p[54_321].1 = 50.0;
        p[77_777].1 = -20.0;
        let d = decimate(&p, 0.0, 100.0, 200);
        assert!(d.len() <= 4 * 200, "{} points", d.len());
        assert!(
            d.len() >= 2 * 200,
            "every column keeps its ends: {}",
            d.len()
        );
        assert!(d.contains(&p[54_321]) && d.contains(&p[77_777]));
        assert_eq!(d.first(), p.first());
        assert_eq!(d.last(), p.last());
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0), "time order kept");
    }
}
