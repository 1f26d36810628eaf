//! The points of one plot table (lines of one topic sharing their times), thinned as
//! they are read so that a long log never has all its rows in memory.
//!
//! The rule: the log's time span is cut into [`COLUMNS`] buckets (about the pixel
//! columns of a wide screen). A table of at most [`KEEP_WHOLE`] rows keeps every row,
//! so zooming in shows every sample. A longer one keeps, per bucket, the first and the
//! last row and the rows where each line has its lowest and its highest value (at most
//! 2 + 2 × lines rows per bucket): every spike and gap of the whole-flight view
//! survives, and the file stays small however long the log; zoomed in, such a table
//! shows that envelope, not every sample.

use serde::ser::{Serialize, SerializeStruct, Serializer};
use ulog_core::read::TimeSpan;

/// Buckets over the log's time span.
pub const COLUMNS: usize = 2000;
/// Tables with at most this many rows are kept whole.
pub const KEEP_WHOLE: usize = 8 * COLUMNS;

/// One table: times (seconds since the log's start) and one value per line per time
/// (NaN where a line has no value).
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// The lines' names.
    pub labels: Vec<String>,
    /// Seconds since the log's start, in time order.
    pub x: Vec<f64>,
    /// Per line, one value per time.
    pub y: Vec<Vec<f32>>,
    /// Whether rows were left out (the table's rows outnumbered [`KEEP_WHOLE`]).
    pub thinned: bool,
    /// One colour for every line of the table (a log's, on a page comparing logs);
    /// the lines then differ by dashes.
    pub color: Option<&'static str>,
}

impl Table {
    /// Whether no line has any finite value.
    pub fn is_blank(&self) -> bool {
        self.y.iter().all(|l| l.iter().all(|v| !v.is_finite()))
    }

    /// Leaves out the lines whose every value is zero or missing (unused outputs).
    pub fn drop_zero_lines(&mut self) {
        let keep: Vec<bool> = self
            .y
            .iter()
            .map(|l| l.iter().any(|v| v.is_finite() && *v != 0.0))
            .collect();
        let mut i = 0;
        self.labels.retain(|_| {
            i += 1;
            keep[i - 1]
        });
        let mut i = 0;
        self.y.retain(|_| {
            i += 1;
            keep[i - 1]
        });
    }
}

/// Times as numbers; values as numbers or `null` (NaN and infinities).
impl Serialize for Table {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        struct Values<'t>(&'t [f32]);
        impl Serialize for Values<'_> {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.collect_seq(self.0.iter().map(|v| v.is_finite().then_some(*v)))
            }
        }
        let mut st = s.serialize_struct("Table", 5)?;
        st.serialize_field("labels", &self.labels)?;
        st.serialize_field("x", &self.x)?;
        let y: Vec<Values<'_>> = self.y.iter().map(|l| Values(l)).collect();
        st.serialize_field("y", &y)?;
        st.serialize_field("thinned", &self.thinned)?;
        if let Some(c) = self.color {
            st.serialize_field("color", c)?;
        }
        st.end()
    }
}

/// Builds a [`Table`] from rows pushed in file order.
pub struct Builder {
    table: Table,
    lines: usize,
    thin: bool,
    span: TimeSpan,
    scale: f64,
    bucket: Option<usize>,
    /// Candidate rows of the current bucket: slot 0 the first, 1 the last, then the
    /// lowest and the highest of each line. Each: (row number, x, values).
    slots: Vec<Option<(u64, f64)>>,
    values: Vec<f32>,
    row: u64,
}

impl Builder {
    /// A builder for `labels`, of a topic with `rows` rows, in a log of span `span`.
    pub fn new(labels: Vec<String>, rows: usize, span: &TimeSpan) -> Builder {
        let lines = labels.len();
        let length = span.duration_us().max(1) as f64;
        let slots = 2 + 2 * lines;
        Builder {
            table: Table {
                y: vec![Vec::new(); lines],
                labels,
                x: Vec::new(),
                thinned: false,
                color: None,
            },
            lines,
            thin: rows > KEEP_WHOLE,
            span: span.clone(),
            scale: COLUMNS as f64 / length,
            bucket: None,
            slots: vec![None; slots],
            values: vec![f32::NAN; slots * lines],
            row: 0,
        }
    }

    /// Adds the row of time `timestamp` (microseconds) with one value per line.
    pub fn push(&mut self, timestamp: u64, values: &[f32]) {
        debug_assert_eq!(values.len(), self.lines);
        // The log's span places rows made before logging began at its start and
        // leaves stray ones off the axis (`TimeSpan`), so that none stretches the
        // plots.
        let Some(timestamp) = self.span.axis_time(timestamp) else {
            return;
        };
        let x = self.span.seconds(timestamp);
        let row = self.row;
        self.row += 1;
        if !self.thin {
            self.table.x.push(x);
            for (line, v) in self.table.y.iter_mut().zip(values) {
                line.push(*v);
            }
            return;
        }
        let b = ((timestamp.saturating_sub(self.span.start()) as f64 * self.scale) as usize)
            .min(COLUMNS - 1);
        if self.bucket != Some(b) {
            self.flush();
            self.bucket = Some(b);
            self.set(0, row, x, values);
        }
        self.set(1, row, x, values);
        for (i, v) in values.iter().enumerate() {
            if !v.is_finite() {
                continue;
            }
            let lo = 2 + 2 * i;
            let (min, max) = (self.value(lo, i), self.value(lo + 1, i));
            if self.slots[lo].is_none() || !min.is_finite() || *v < min {
                self.set(lo, row, x, values);
            }
            if self.slots[lo + 1].is_none() || !max.is_finite() || *v > max {
                self.set(lo + 1, row, x, values);
            }
        }
    }

    fn value(&self, slot: usize, line: usize) -> f32 {
        self.values[slot * self.lines + line]
    }

    fn set(&mut self, slot: usize, row: u64, x: f64, values: &[f32]) {
        self.slots[slot] = Some((row, x));
        self.values[slot * self.lines..(slot + 1) * self.lines].copy_from_slice(values);
    }

    /// Moves the current bucket's distinct candidate rows, in row order, to the table.
    fn flush(&mut self) {
        let mut kept: Vec<(u64, usize)> = self
            .slots
            .iter()
            .enumerate()
            .filter_map(|(slot, s)| s.map(|(row, _)| (row, slot)))
            .collect();
        kept.sort_unstable();
        kept.dedup_by_key(|k| k.0);
        for (_, slot) in kept {
            let (_, x) = self.slots[slot].expect("a kept slot is set");
            self.table.x.push(x);
            for (i, line) in self.table.y.iter_mut().enumerate() {
                line.push(self.values[slot * self.lines + i]);
            }
        }
        self.slots.iter_mut().for_each(|s| *s = None);
    }

    /// The table, in time order.
    pub fn finish(mut self) -> Table {
        self.flush();
        let mut t = self.table;
        t.thinned = self.thin;
        // A topic's timestamps should rise, but a damaged or reordered log may break
        // that; the page needs them in order.
        if !t.x.windows(2).all(|w| w[0] <= w[1]) {
            let mut order: Vec<usize> = (0..t.x.len()).collect();
            order.sort_by(|&a, &b| t.x[a].total_cmp(&t.x[b]));
            t.x = order.iter().map(|&i| t.x[i]).collect();
            for line in &mut t.y {
                *line = order.iter().map(|&i| line[i]).collect();
            }
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_tables_are_kept_whole() {
        let mut b = Builder::new(vec!["a".into()], 10, &TimeSpan::new(1_000_000, 2_000_000));
        for i in 0..10u64 {
            b.push(1_000_000 + i * 100_000, &[i as f32]);
        }
        let t = b.finish();
        assert_eq!(t.x.len(), 10);
        assert!(!t.thinned);
        assert_eq!(t.x[1], 0.1);
        assert_eq!(t.y[0][9], 9.0);
    }

    #[test]
    fn long_tables_keep_each_buckets_ends_and_extremes() {
        let n = 200_000u64;
        let mut b = Builder::new(
            vec!["a".into(), "b".into()],
            n as usize,
            &TimeSpan::new(0, n - 1),
        );
        for i in 0..n {
            let a = if i == 123_457 { 50.0 } else { 1.0 };
            let c = if i == 7 { f32::NAN } else { -(i as f32) };
            b.push(i, &[a, c]);
        }
        let t = b.finish();
        assert!(t.thinned);
        assert!(t.x.len() <= COLUMNS * 6 && t.x.len() >= COLUMNS * 2);
        assert!(t.y[0].contains(&50.0), "the spike survives");
        assert_eq!(t.x[0], 0.0);
        assert_eq!(*t.x.last().unwrap(), (n - 1) as f64 / 1e6);
        assert!(t.x.windows(2).all(|w| w[0] < w[1]));
    }
}
