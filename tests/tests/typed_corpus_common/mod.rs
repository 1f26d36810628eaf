//! The check shared by the `typed_corpus_N` tests: bindings generated at compile time
//! from a corpus log (`ulog_module!`, see `build.rs`) decode every row of every topic
//! of that log, through `ULog::read_instances`, to the values in pyulog's CSV files,
//! with the rules of `tests/corpus.rs` (`cell_matches`; extra rows only where we
//! recover data pyulog skips, `recovered_stretches`).
//!
//! Each binding is visited by type (`visit_bindings`), and its values are listed by
//! column path with `ULogMessage::visit_fields`, so one generic function checks every
//! struct of every log.

#![allow(dead_code)]

use std::collections::BTreeSet;

use ulog_core::typed::{BindingVisitor, TypedErrorKind, ViewVisitor, WireImage};
use ulog_core::{LogFile, Topic, ULog, ULogMessage, Value};
use ulog_tests::{cell_matches, corpus_dir as corpus, recovered_stretches};

/// Checks each topic instance of one log with the bindings generated from it.
pub struct Checker<'l, 'a> {
    stem: &'l str,
    log: &'l ULog<'a>,
    recovered: Vec<(u64, u64)>,
    /// Subscriptions checked (by the offset of their `A` message).
    checked: BTreeSet<u64>,
    /// Values compared.
    pub values: usize,
    /// Rows we keep that pyulog drops (inside recovered stretches).
    pub extra_rows: usize,
    /// With view bindings: rows borrowed in place.
    pub borrowed: usize,
    /// With view bindings: topic instances with rows that could not be borrowed, and
    /// why (they are decoded by copy instead).
    pub not_borrowed: Vec<(String, usize, String)>,
}

impl BindingVisitor for Checker<'_, '_> {
    fn visit<T: ULogMessage>(&mut self) {
        // Only this part is generic; the comparison is not, to keep the ~2000
        // instantiations small.
        let log = self.log;
        let instances = match log.read_instances::<T>() {
            Ok(instances) => instances,
            // A format the log defines but never subscribes: no instance to read.
            Err(e)
                if matches!(e.kind(), TypedErrorKind::NotFound { .. })
                    && log.topic_instances(T::NAME).is_empty() =>
            {
                return;
            }
            Err(e) => panic!("{}: `{}`: {e}", self.stem, T::NAME),
        };
        for rows in instances {
            let rows = rows.unwrap_or_else(|e| panic!("{}: `{}`: {e}", self.stem, T::NAME));
            if rows.is_empty() {
                continue;
            }
            self.compare(rows.topic(), &mut |i, f| match rows.get(i) {
                Some(Ok(m)) => {
                    m.visit_fields(f);
                    true
                }
                Some(Err(e)) => panic!("`{}` row {i}: {e}", T::NAME),
                None => false,
            });
        }
    }
}

impl ViewVisitor for Checker<'_, '_> {
    fn visit<T: ULogMessage + WireImage>(&mut self) {
        let log = self.log;
        let Ok(instances) = log.read_instances::<T>() else {
            assert!(log.topic_instances(T::NAME).is_empty(), "`{}`", T::NAME);
            return;
        };
        for rows in instances {
            let rows = rows.unwrap_or_else(|e| panic!("{}: `{}`: {e}", self.stem, T::NAME));
            if rows.is_empty() {
                continue;
            }
            // Refused once for all rows, or borrowed row by row.
            let views: Vec<_> = match rows.views() {
                Ok(views) => views.collect(),
                Err(e) => {
                    self.not_borrowed
                        .push((T::NAME.to_owned(), rows.len(), e.to_string()));
                    Vec::new()
                }
            };
            let mut why = None;
            for (i, v) in views.iter().enumerate() {
                match v {
                    Ok(v) => {
                        // Borrowed in place: the view is the payload's memory.
                        let payload = rows.topic().payload(i).unwrap();
                        assert!(std::ptr::eq(*v as *const T as *const u8, payload.as_ptr()));
                        self.borrowed += 1;
                    }
                    Err(e) => {
                        why.get_or_insert_with(|| (0, e.to_string())).0 += 1;
                    }
                }
            }
            if let Some((n, text)) = why {
                self.not_borrowed.push((T::NAME.to_owned(), n, text));
            }
            // Every value, borrowed or (where it cannot be) copied, against pyulog's.
            self.compare(
                rows.topic(),
                &mut |i, f| match (views.get(i), rows.get(i)) {
                    (Some(Ok(v)), _) => {
                        v.visit_fields(f);
                        true
                    }
                    (_, Some(m)) => {
                        m.unwrap_or_else(|e| panic!("`{}` row {i}: {e}", T::NAME))
                            .visit_fields(f);
                        true
                    }
                    (_, None) => false,
                },
            );
        }
    }
}

/// Decodes row `i` of a topic and visits its fields; `false` past the last row.
type Decode<'d> = dyn FnMut(usize, &mut dyn FnMut(&str, Value<'_>)) -> bool + 'd;

impl<'l, 'a> Checker<'l, 'a> {
    fn compare(&mut self, topic: Topic<'_, 'a>, decode: &mut Decode<'_>) {
        let stem = self.stem;
        self.checked.insert(topic.subscription().offset());
        let csv = corpus().join(format!(
            "expected/{stem}/csv/{stem}_{}_{}.csv",
            topic.name().replace('/', "_"),
            topic.multi_id()
        ));
        let text =
            std::fs::read_to_string(&csv).unwrap_or_else(|e| panic!("{}: {e}", csv.display()));
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().expect("CSV header").split(',').collect();

        // The binding's columns, in visit order, and where each is in the CSV.
        let mut paths: Vec<String> = Vec::new();
        decode(0, &mut |path, _| paths.push(path.to_owned()));
        let columns: Vec<usize> = paths
            .iter()
            .map(|p| {
                header.iter().position(|h| h == p).unwrap_or_else(|| {
                    panic!("{}: binding column `{p}` not in the CSV", csv.display())
                })
            })
            .collect();
        let mut sorted = paths.clone();
        sorted.sort();
        let mut expected: Vec<&str> = header.clone();
        expected.sort();
        assert_eq!(sorted, expected, "{}: columns", csv.display());

        let offsets = topic.message_offsets();
        let timestamps = topic.timestamps();
        let recovered = &self.recovered;
        let in_recovered = |o: u64| recovered.iter().any(|&(a, b)| a <= o && o < b);
        let mut ours = 0usize;
        let mut extra = 0usize;
        let mut values = 0usize;
        for (row, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            assert_eq!(cells.len(), header.len(), "{}: row {row}", csv.display());
            loop {
                let mut k = 0;
                let mut same = true;
                let found = decode(ours, &mut |_, value| {
                    same &= cell_matches(cells[columns[k]], &value);
                    k += 1;
                });
                assert!(found, "{}: row {row}: we have fewer rows", csv.display());
                if same {
                    values += k;
                    ours += 1;
                    break;
                }
                let o = offsets.get(ours).unwrap();
                if !in_recovered(o) {
                    let mut typed = Vec::new();
                    decode(ours, &mut |path, value| {
                        typed.push(format!("{path}={value}"))
                    });
                    panic!(
                        "{}: row {row}: pyulog {line:?}, typed {typed:?} (offset {o})",
                        csv.display()
                    );
                }
                if ours + 1 < timestamps.len() {
                    assert!(
                        timestamps[ours] <= timestamps[ours + 1],
                        "{}: recovered row {ours} out of order",
                        csv.display()
                    );
                }
                extra += 1;
                ours += 1;
            }
        }
        while ours < topic.len() {
            assert!(
                in_recovered(offsets.get(ours).unwrap()),
                "{}: we have more rows than pyulog",
                csv.display()
            );
            extra += 1;
            ours += 1;
        }
        self.values += values;
        self.extra_rows += extra;
    }
}

/// Checks every log of a shard: `visit_log(stem, checker)` visits the bindings
/// generated from log `stem`. Every topic instance with data must have been decoded
/// by a binding, and every CSV file used.
pub fn check_logs(stems: &[&str], visit_log: fn(&str, &mut Checker<'_, '_>)) {
    check_logs_with(stems, |stem, checker| {
        visit_log(stem, checker);
        true
    });
}

/// [`check_logs`] through a function that may decline a log (`false`: no bindings for
/// it, counted and said).
pub fn check_logs_with(
    stems: &[&str],
    mut visit_log: impl FnMut(&str, &mut Checker<'_, '_>) -> bool,
) -> Vec<Totals> {
    let mut total = 0;
    let mut all = Vec::new();
    for stem in stems {
        let path = corpus().join(format!("files/{stem}.ulg"));
        let file = LogFile::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let log = file.parse().unwrap_or_else(|e| panic!("{stem}: {e}"));
        let mut checker = Checker {
            stem,
            log: &log,
            recovered: recovered_stretches(&log),
            checked: BTreeSet::new(),
            values: 0,
            extra_rows: 0,
            borrowed: 0,
            not_borrowed: Vec::new(),
        };
        if !visit_log(stem, &mut checker) {
            continue;
        }
        let with_data: Vec<_> = log.topics().filter(|t| !t.is_empty()).collect();
        for t in &with_data {
            assert!(
                checker.checked.contains(&t.subscription().offset()),
                "{stem}: topic {}/{} has no generated binding",
                t.name(),
                t.multi_id()
            );
        }
        let csv_count = std::fs::read_dir(corpus().join(format!("expected/{stem}/csv")))
            .map(|d| d.count())
            .unwrap_or(0);
        assert_eq!(
            csv_count,
            checker.checked.len(),
            "{stem}: one CSV per topic instance"
        );
        eprintln!(
            "{stem}: {} topic instances, {} values match pyulog ({} recovered rows kept)",
            checker.checked.len(),
            checker.values,
            checker.extra_rows
        );
        total += checker.values;
        all.push(Totals {
            stem: stem.to_string(),
            rows: with_data.iter().map(|t| t.len()).sum(),
            borrowed: checker.borrowed,
            not_borrowed: checker.not_borrowed,
        });
    }
    eprintln!("compared {total} values");
    all
}

/// What [`check_logs_with`] found in one log.
pub struct Totals {
    /// The log's file stem.
    pub stem: String,
    /// Data rows of every topic instance.
    pub rows: usize,
    /// Rows borrowed by view bindings.
    pub borrowed: usize,
    /// Topics (name, rows, first reason) whose rows views could not borrow.
    pub not_borrowed: Vec<(String, usize, String)>,
}
