//! Typed decoding through generated structs against the reader's generic field access,
//! on the two largest topics of a log, with the ratio measured in the same run.
//!
//! ```text
//! cargo bench -p ulog-benches                      # the corpus's sample.ulg
//! ULOG_BENCH_FILE=big.ulg cargo bench -p ulog-benches
//! cargo bench -p ulog-benches -- --test            # each benchmark once (CI)
//! ```
//!
//! Big logs: `python3 ../shared/tools/make_big.py BASE.ulg REPEATS OUT.ulg`.
//!
//! Per topic, three ways to go through every row:
//! - `generic`: `Topic::fields()` resolved once, then every field of every row read
//!   with `FieldReader::read` and summed as `f64` (what dynamic readers do);
//! - `typed`: every row decoded into the generated struct (`TypedRows::iter`), the
//!   plan made once;
//! - `typed+visit`: the same, then every field summed as `f64` through
//!   `ULogMessage::visit_fields`, the same work as `generic` in the end.
//!
//! The bindings come from `ulog_module!` on the corpus's `sample.ulg` (without the
//! corpus, on the examples' reference log, and the input is the bundled sample log).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput};
use ulog_core::typed::BindingVisitor;
use ulog_core::{Topic, ULog, ULogMessage};

#[cfg(has_corpus)]
ulog_core::ulog_module!(mod schema = "../../shared/corpus/files/sample.ulg");
#[cfg(not(has_corpus))]
ulog_core::ulog_module!(mod schema = "../examples/data/reference.ulg");

/// Total time and iterations per benchmark id, as criterion ran them.
type Timings = RefCell<BTreeMap<String, (Duration, u64)>>;

fn load() -> (String, Vec<u8>) {
    if let Some(path) = std::env::var_os("ULOG_BENCH_FILE") {
        let bytes = std::fs::read(&path)
            .unwrap_or_else(|e| panic!("ULOG_BENCH_FILE {}: {e}", path.to_string_lossy()));
        return (path.to_string_lossy().into_owned(), bytes);
    }
    if cfg!(has_corpus) {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/corpus/files/sample.ulg"
        );
        return (
            "corpus sample.ulg".to_owned(),
            std::fs::read(path).expect("sample.ulg"),
        );
    }
    (
        "ulog_core::testing::sample_log()".to_owned(),
        ulog_core::testing::sample_log(),
    )
}

/// Generic access: every column of every row, summed.
fn generic_sum(topic: &Topic<'_, '_>) -> f64 {
    let columns = topic.fields().expect("fields");
    let mut sum = 0.0;
    for payload in topic.payloads() {
        for c in &columns {
            if let Some(v) = c.read(payload).and_then(|v| v.as_f64()) {
                sum += v;
            }
        }
    }
    sum
}

/// Finds the bindings that read the chosen topics and benchmarks each.
struct Bench<'c, 'l, 'a> {
    criterion: &'c mut Criterion,
    log: &'l ULog<'a>,
    /// (name, multi_id) of the chosen topics.
    topics: Vec<(String, u8)>,
    timings: &'c Timings,
    done: Vec<String>,
}

impl BindingVisitor for Bench<'_, '_, '_> {
    fn visit<T: ULogMessage>(&mut self) {
        let Some((_, multi_id)) = self.topics.iter().find(|(n, _)| n == T::NAME) else {
            return;
        };
        let rows = match self.log.read::<T>(*multi_id) {
            Ok(rows) => rows,
            Err(e) => {
                eprintln!("skipping `{}`: {e}", T::NAME);
                return;
            }
        };
        let topic = rows.topic();
        let bytes: usize = topic.payloads().map(<[u8]>::len).sum();
        let label = format!("{}/{}", T::NAME, multi_id);
        eprintln!(
            "{label}: {} rows, {} bytes, {} columns, {:?} plan",
            rows.len(),
            bytes,
            topic.fields().map_or(0, |c| c.len()),
            rows.plan().kind()
        );
        let timings = self.timings;
        let record = |id: String, elapsed: Duration, iters: u64| {
            let mut t = timings.borrow_mut();
            let e = t.entry(id).or_insert((Duration::ZERO, 0));
            e.0 += elapsed;
            e.1 += iters;
        };
        let mut group = self.criterion.benchmark_group(&label);
        group.throughput(Throughput::Bytes(bytes as u64));
        group.bench_function("generic", |b| {
            b.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    black_box(generic_sum(black_box(&topic)));
                }
                let elapsed = start.elapsed();
                record(format!("{label}/generic"), elapsed, iters);
                elapsed
            })
        });
        group.bench_function("typed", |b| {
            b.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    // The plan is made once per subscription, as a reader does.
                    let rows = black_box(&topic).read::<T>().expect("plan");
                    for row in rows.iter() {
                        black_box(row.expect("row"));
                    }
                }
                let elapsed = start.elapsed();
                record(format!("{label}/typed"), elapsed, iters);
                elapsed
            })
        });
        group.bench_function("typed+visit", |b| {
            b.iter_custom(|iters| {
                let start = Instant::now();
                for _ in 0..iters {
                    let rows = black_box(&topic).read::<T>().expect("plan");
                    let mut sum = 0.0;
                    for row in rows.iter() {
                        row.expect("row").visit_fields(&mut |_, v| {
                            if let Some(v) = v.as_f64() {
                                sum += v;
                            }
                        });
                    }
                    black_box(sum);
                }
                let elapsed = start.elapsed();
                record(format!("{label}/typed+visit"), elapsed, iters);
                elapsed
            })
        });
        group.finish();
        self.done.push(label);
    }
}

fn main() {
    let (name, bytes) = load();
    let log = ULog::parse(&bytes).expect("the input parses");
    // The two largest topics (by payload bytes) that the bindings can read.
    let mut readable: Vec<String> = Vec::new();
    struct Names<'v>(&'v mut Vec<String>);
    impl BindingVisitor for Names<'_> {
        fn visit<T: ULogMessage>(&mut self) {
            self.0.push(T::NAME.to_owned());
        }
    }
    schema::visit_bindings(&mut Names(&mut readable));
    let mut sizes: Vec<(usize, String, u8)> = log
        .topics()
        .filter(|t| readable.iter().any(|n| n == t.name()))
        .map(|t| {
            let size: usize = t.payloads().map(<[u8]>::len).sum();
            (size, t.name().to_owned(), t.multi_id())
        })
        .collect();
    sizes.sort_by_key(|s| std::cmp::Reverse(s.0));
    let topics: Vec<(String, u8)> = sizes.into_iter().take(2).map(|(_, n, m)| (n, m)).collect();
    println!("input: {name} ({} bytes); topics: {topics:?}", bytes.len());

    let timings = Timings::default();
    let mut criterion = Criterion::default().configure_from_args();
    let mut bench = Bench {
        criterion: &mut criterion,
        log: &log,
        topics,
        timings: &timings,
        done: Vec::new(),
    };
    schema::visit_bindings(&mut bench);
    let done = std::mem::take(&mut bench.done);
    criterion.final_summary();

    // The ratio from the same measurements criterion took (mean time per pass).
    let t = timings.borrow();
    let mean = |id: String| {
        t.get(&id)
            .map(|(d, n)| d.as_secs_f64() / (*n).max(1) as f64)
    };
    println!("\nratio (generic time / typed time), same run:");
    for label in done {
        let (Some(g), Some(ty), Some(tv)) = (
            mean(format!("{label}/generic")),
            mean(format!("{label}/typed")),
            mean(format!("{label}/typed+visit")),
        ) else {
            continue;
        };
        println!(
            "  {label:<32} generic {:>9.3} ms   typed {:>9.3} ms ({:>5.1}x)   typed+visit {:>9.3} ms ({:>5.1}x)",
            g * 1e3,
            ty * 1e3,
            g / ty,
            tv * 1e3,
            g / tv
        );
    }
}
