//! The one-pass alignment (`AlignStream`) against the indexed one (`ULog::align`): the
//! same steps and values wherever it reports nothing late or early, on every corpus
//! log and on written logs with a stale row, a silent topic and an unsubscription; and
//! what it holds.

use ulog_core::align::{
    AlignError, AlignOptions, AlignStream, Grid, Method, StreamError, StreamOptions, StreamSummary,
    Track,
};
use ulog_core::testing::LogBuilder;
use ulog_core::ULog;

const METHODS: [Method; 3] = [Method::Previous, Method::Nearest, Method::Linear];

/// Each step's time and each track's row bytes, by the indexed alignment.
type Table = Vec<(u64, Vec<Option<Vec<u8>>>)>;

fn indexed(log: &ULog<'_>, grid: &Grid, tracks: &[Track], options: &AlignOptions) -> Table {
    let steps = log.align(grid, options).unwrap();
    let columns: Vec<Vec<Option<Vec<u8>>>> = tracks
        .iter()
        .map(|t| {
            steps
                .rows(&t.topic, t.multi_id, t.method)
                .unwrap()
                .map(|r| r.map(|r| r.bytes().to_vec()))
                .collect()
        })
        .collect();
    steps
        .times()
        .iter()
        .enumerate()
        .map(|(i, &t)| (t, columns.iter().map(|c| c[i].clone()).collect()))
        .collect()
}

fn streamed(
    bytes: &[u8],
    grid: &Grid,
    tracks: &[Track],
    options: StreamOptions,
) -> (Table, StreamSummary) {
    let mut s = AlignStream::new(bytes, grid, tracks.to_vec(), options).unwrap();
    let mut out = Vec::new();
    while let Some(step) = s.next_step().unwrap() {
        let rows = step
            .rows
            .iter()
            .map(|r| r.as_ref().map(|r| r.bytes().to_vec()))
            .collect();
        out.push((step.time, rows));
    }
    (out, s.summary())
}

/// The steps where two tables differ (a step missing from one counts).
fn differing(a: &Table, b: &Table) -> usize {
    let n = a.len().max(b.len());
    (0..n).filter(|&i| a.get(i) != b.get(i)).count()
}

/// Whether the topic's rows are in time order in the file.
fn in_time_order(log: &ULog<'_>, name: &str, multi_id: u8) -> bool {
    let ts = log.topic(name, multi_id).unwrap().timestamps();
    ts.windows(2).all(|w| w[0] <= w[1])
}

#[test]
fn one_pass_equals_the_indexed_alignment_on_every_corpus_log() {
    let mut checked = 0;
    let mut exact_with_default_horizon = 0;
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        // Topic instances with a timestamp and rows, busiest first.
        let mut topics: Vec<(String, u8, usize)> = log
            .subscriptions()
            .iter()
            .filter(|s| s.timestamp_field().is_some() && s.layout().is_ok())
            .filter_map(|s| {
                let t = log.topic(s.name(), s.multi_id()).ok()?;
                (!t.is_empty()).then(|| (s.name().to_owned(), s.multi_id(), t.len()))
            })
            .collect();
        topics.sort_by(|a, b| b.2.cmp(&a.2).then(a.0.cmp(&b.0)));
        topics.dedup_by(|a, b| a.0 == b.0 && a.1 == b.1);
        if topics.len() < 2 {
            continue;
        }
        // The busiest two and the sparsest two, each by every method.
        let mut chosen: Vec<&(String, u8, usize)> = topics.iter().take(2).collect();
        chosen.extend(topics.iter().rev().take(2));
        chosen.dedup();
        let tracks: Vec<Track> = chosen
            .iter()
            .flat_map(|(n, m, _)| METHODS.map(|method| Track::new(n, *m, method)))
            .collect();
        // Steps on a busy topic that is not the busiest (fewer steps to check), then at
        // a rate.
        let (gn, gm, _) = &topics[1.min(topics.len() - 1)];
        let grid = Grid::topic(gn, *gm);
        let name = ulog_tests::stem(&path);
        let want = indexed(&log, &grid, &tracks, &AlignOptions::default());
        let wait = StreamOptions {
            horizon_us: u64::MAX,
            ..StreamOptions::default()
        };
        let (got, summary) = streamed(&bytes, &grid, &tracks, wait);
        assert!(
            summary.tracks.iter().all(|t| t.early_steps == 0),
            "{name}: no horizon, no early step"
        );
        let ordered = in_time_order(&log, gn, *gm)
            && chosen.iter().all(|(n, m, _)| in_time_order(&log, n, *m));
        if ordered {
            assert!(summary.is_exact(), "{name}: {summary:?}");
        }
        if summary.is_exact() {
            assert_eq!(got.len(), want.len(), "{name}: steps");
            assert_eq!(differing(&got, &want), 0, "{name}: values");
        }
        // The default horizon: what differs is at most what it reports.
        let (got, summary) = streamed(&bytes, &grid, &tracks, StreamOptions::default());
        let reported: u64 = summary
            .tracks
            .iter()
            .map(|t| t.late_rows + t.early_steps)
            .sum::<u64>()
            + summary.late_steps;
        if summary.is_exact() {
            exact_with_default_horizon += 1;
            assert_eq!(differing(&got, &want), 0, "{name}: default horizon");
        } else {
            assert!(reported > 0, "{name}");
        }
        // Memory: what lies within the horizon (and 2 s more) at most, when the rows
        // are in time order.
        if ordered {
            let window = StreamOptions::default().horizon_us + 2_000_000;
            let steps: Vec<u64> = want.iter().map(|s| s.0).collect();
            let rows: usize = tracks
                .iter()
                .map(|t| {
                    let mut ts = log.topic(&t.topic, t.multi_id).unwrap().timestamps();
                    ts.sort_unstable();
                    most_within(&ts, window) + 1
                })
                .sum();
            assert!(
                summary.held_rows_peak <= rows
                    && summary.pending_peak <= most_within(&steps, window),
                "{name}: held {} rows (bound {rows}), {} steps waiting",
                summary.held_rows_peak,
                summary.pending_peak,
            );
        }

        // A rate from the header's start: the same steps while both have them.
        if log.header().timestamp > 0 {
            let rate = Grid::Rate(37.0);
            let want = indexed(&log, &rate, &tracks, &AlignOptions::default());
            let (got, summary) = streamed(&bytes, &rate, &tracks, wait_forever());
            if summary.is_exact() {
                let n = got.len().min(want.len());
                assert!(n > 0, "{name}: rate steps");
                assert_eq!(got[..n], want[..n], "{name}: rate");
            }
        }
        checked += 1;
    }
    assert!(checked >= 1, "no corpus log checked");
    assert!(exact_with_default_horizon >= 1);
}

/// The most of `times` (sorted) within any span of `width` microseconds.
fn most_within(times: &[u64], width: u64) -> usize {
    let mut most = 0;
    let mut lo = 0;
    for (hi, &t) in times.iter().enumerate() {
        while t - times[lo] > width {
            lo += 1;
        }
        most = most.max(hi + 1 - lo);
    }
    most
}

fn wait_forever() -> StreamOptions {
    StreamOptions {
        horizon_us: u64::MAX,
        ..StreamOptions::default()
    }
}

fn row(t: u64, v: f32) -> Vec<u8> {
    [t.to_le_bytes().as_slice(), &v.to_le_bytes()].concat()
}

/// A log of `grid` at 100 Hz over `seconds`, `x` at 10 Hz except where `skip` says.
fn written(seconds: u64, skip: impl Fn(u64) -> bool) -> LogBuilder {
    let mut b = LogBuilder::new(1, 1_000);
    b.format("grid:uint64_t timestamp;float v;");
    b.format("x:uint64_t timestamp;float v;");
    b.subscribe(0, 0, "grid");
    b.subscribe(0, 1, "x");
    for k in 0..seconds * 100 {
        let t = 1_000 + k * 10_000;
        b.data(0, &row(t, k as f32));
        if k % 10 == 5 && !skip(t) {
            b.data(1, &row(t - 3_000, k as f32 * 0.5));
        }
    }
    b
}

fn tracks() -> Vec<Track> {
    METHODS.iter().map(|&m| Track::new("x", 0, m)).collect()
}

#[test]
fn a_stale_row_written_late_is_reported_with_its_offset() {
    let mut b = written(30, |_| false);
    let offset = b.bytes().len() as u64;
    // A row stamped 20 s back, written at the end (as PX4 writes a setpoint made long
    // before): the steps after its time were handed out already.
    b.data(1, &row(5_000_000, -1.0));
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let want = indexed(&log, &grid, &tracks(), &AlignOptions::default());
    let (got, summary) = streamed(&bytes, &grid, &tracks(), StreamOptions::default());
    for t in &summary.tracks {
        assert_eq!((t.late_rows, t.first_late_offset), (1, Some(offset)));
    }
    assert!(!summary.is_exact());
    // The indexed alignment sorts it in: the steps between it and the next row differ.
    let differ = differing(&got, &want);
    assert!((1..=10).contains(&differ), "{differ} steps differ");
}

#[test]
fn a_silent_topic_holds_nothing_up_beyond_the_horizon_and_what_differs_is_reported() {
    // `x` silent from 2 s to 32 s.
    let bytes = written(40, |t| (2_000_000..32_000_000).contains(&t)).into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let want = indexed(&log, &grid, &tracks(), &AlignOptions::default());

    // Waiting for the next row, however far: exact, but 30 s of steps wait.
    let (got, summary) = streamed(&bytes, &grid, &tracks(), wait_forever());
    assert!(summary.is_exact());
    assert_eq!(got, want);
    assert!(summary.pending_peak >= 2_900, "{summary:?}");

    // The default horizon (10 s): at most about 10 s of steps wait; the steps decided
    // before `x`'s next row came are counted for nearest and linear, and every step
    // that differs is among them.
    let (got, summary) = streamed(&bytes, &grid, &tracks(), StreamOptions::default());
    assert!(
        (1_000..=1_010).contains(&summary.pending_peak),
        "{summary:?}"
    );
    let [previous, nearest, linear] = &summary.tracks[..] else {
        panic!()
    };
    assert_eq!(previous.early_steps, 0);
    assert!(nearest.early_steps > 1_500 && nearest.early_steps == linear.early_steps);
    assert_eq!(got.len(), want.len());
    for (k, early) in [(0, 0), (1, nearest.early_steps), (2, linear.early_steps)] {
        let differ = got
            .iter()
            .zip(&want)
            .filter(|(g, w)| g.1[k] != w.1[k])
            .count() as u64;
        assert!(
            differ <= early,
            "track {k}: {differ} differ, {early} reported"
        );
    }
    // Linear over the gap is absent (after the last row as far as the pass knew).
    assert!(got
        .iter()
        .zip(&want)
        .any(|(g, w)| g.1[2].is_none() && w.1[2].is_some()));
}

#[test]
fn an_unsubscribed_topic_holds_nothing_up() {
    let mut b = LogBuilder::new(1, 1_000);
    b.format("grid:uint64_t timestamp;float v;");
    b.format("x:uint64_t timestamp;float v;");
    b.subscribe(0, 0, "grid");
    b.subscribe(0, 1, "x");
    for k in 0..2_000u64 {
        let t = 1_000 + k * 10_000;
        b.data(0, &row(t, k as f32));
        if k < 100 {
            b.data(1, &row(t, 1.0));
        }
        if k == 100 {
            b.unsubscribe(1);
        }
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let want = indexed(&log, &grid, &tracks(), &AlignOptions::default());
    let (got, summary) = streamed(&bytes, &grid, &tracks(), wait_forever());
    assert_eq!(got, want);
    assert!(summary.pending_peak <= 2, "{summary:?}");
}

#[test]
fn a_topic_the_log_lacks_and_a_grid_without_timestamp_are_errors() {
    let bytes = written(2, |_| false).into_bytes();
    let both = vec![
        Track::new("gird_x", 0, Method::Previous),
        Track::new("x", 3, Method::Previous),
    ];
    // No format of that name: the layouts, asked first, say so.
    let mut s = AlignStream::new(
        &bytes[..],
        &Grid::topic("grid", 0),
        both.clone(),
        StreamOptions::default(),
    )
    .unwrap();
    let e = s.layouts().unwrap_err();
    assert!(
        matches!(e, StreamError::Align(AlignError::Lookup(_))),
        "{e}"
    );
    assert!(e.to_string().contains("gird_x"), "{e}");
    // An instance never subscribed: the steps have it absent, and the end is an error
    // naming it.
    let mut s = AlignStream::new(
        &bytes[..],
        &Grid::topic("grid", 0),
        both[1..].to_vec(),
        StreamOptions::default(),
    )
    .unwrap();
    assert_eq!(s.layouts().unwrap().len(), 1);
    let mut steps = 0;
    let e = loop {
        match s.next_step() {
            Ok(Some(step)) => {
                assert_eq!(step.rows, [None]);
                steps += 1;
            }
            Ok(None) => panic!("no error"),
            Err(e) => break e,
        }
    };
    assert_eq!(steps, 200);
    assert!(
        matches!(e, StreamError::Align(AlignError::Lookup(_))),
        "{e}"
    );
    assert!(
        e.to_string().contains("`x`") && e.to_string().contains('3'),
        "{e}"
    );

    let mut b = LogBuilder::new(1, 1_000);
    b.format("plain:uint32_t v;");
    b.subscribe(0, 0, "plain");
    b.data(0, &7u32.to_le_bytes());
    let bytes = b.into_bytes();
    let mut s = AlignStream::new(
        &bytes[..],
        &Grid::topic("plain", 0),
        vec![],
        StreamOptions::default(),
    )
    .unwrap();
    let e = s.next_step().unwrap_err();
    assert!(
        matches!(&e, StreamError::Align(AlignError::NoTimestamp(t)) if t == "plain"),
        "{e}"
    );
    assert!(AlignStream::new(
        &bytes[..],
        &Grid::Rate(0.0),
        vec![],
        StreamOptions::default()
    )
    .is_err());
    // Not a ULog: the reader's error.
    let mut s = AlignStream::new(
        &b"not a log at all"[..],
        &Grid::Rate(1.0),
        vec![],
        StreamOptions::default(),
    )
    .unwrap();
    assert!(matches!(s.next_step(), Err(StreamError::Read(_))));
}

#[derive(ulog_core::ULogMessage, Debug, Clone, PartialEq)]
#[ulog(name = "sensor_combined")]
struct Imu {
    timestamp: u64,
    gyro_rad: [f32; 3],
}

#[derive(ulog_core::ULogMessage, Debug, Clone, PartialEq)]
#[ulog(name = "vehicle_attitude")]
struct Attitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ulog_core::align::Aligned, Debug, PartialEq)]
struct Step {
    imu: Option<Imu>,
    #[ulog(method = "linear")]
    attitude: Option<Attitude>,
    #[ulog(method = "nearest")]
    nearest: Option<Attitude>,
}

#[test]
fn a_derived_struct_in_one_pass_equals_the_indexed_one_on_every_corpus_log() {
    use ulog_core::align::AlignedStream;
    let mut checked = 0;
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        let grid = Grid::topic("sensor_combined", 0);
        let Ok(steps) = log.align(&grid, &AlignOptions::default()) else {
            continue;
        };
        let Ok(indexed) = steps.read::<Step>() else {
            continue;
        };
        let indexed: Vec<(u64, Step)> = indexed.collect();
        let mut one_pass =
            AlignedStream::<_, Step>::new(&bytes[..], &grid, wait_forever()).unwrap();
        let mut streamed = Vec::new();
        while let Some(step) = one_pass.next_step().unwrap() {
            streamed.push(step);
        }
        let name = ulog_tests::stem(&path);
        if one_pass.summary().is_exact() {
            assert_eq!(streamed.len(), indexed.len(), "{name}");
            assert!(streamed == indexed, "{name}");
            checked += 1;
        }
    }
    assert!(checked >= 1);
}

#[test]
fn every_field_of_a_struct_that_does_not_fit_is_named_at_once_in_one_pass() {
    #[derive(ulog_core::ULogMessage)]
    #[ulog(name = "x")]
    struct WrongType {
        timestamp: u64,
        v: u32,
    }
    #[derive(ulog_core::ULogMessage)]
    #[ulog(name = "absent")]
    struct Absent {
        timestamp: u64,
    }
    #[derive(ulog_core::align::Aligned)]
    #[allow(dead_code)] // never read: it does not fit
    struct Both {
        x: Option<WrongType>,
        absent: Option<Absent>,
    }
    let bytes = written(2, |_| false).into_bytes();
    let e = match ulog_core::align::AlignedStream::<_, Both>::new(
        &bytes[..],
        &Grid::topic("grid", 0),
        StreamOptions::default(),
    ) {
        Err(StreamError::Aligned(e)) => e,
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("fits"),
    };
    let fields: Vec<&str> = e.fields().iter().map(|(f, _)| f.field).collect();
    assert_eq!(fields, ["x", "absent"], "{e}");
    let text = e.to_string();
    assert!(text.contains("`v`") && text.contains("absent"), "{text}");
}

/// A log with `grid` and `x` (`float v`), written in the order given: `(msg_id, t)`.
fn in_order(rows: &[(u16, u64)], unsubscribe_after: Option<usize>) -> Vec<u8> {
    let mut b = LogBuilder::new(1, 1_000);
    b.format("grid:uint64_t timestamp;float v;");
    b.format("x:uint64_t timestamp;float v;");
    b.subscribe(0, 0, "grid");
    b.subscribe(0, 1, "x");
    for (i, &(id, t)) in rows.iter().enumerate() {
        b.data(id, &row(t, t as f32));
        if unsubscribe_after == Some(i) {
            // x ends, and is subscribed again under another msg_id.
            b.unsubscribe(1);
            b.subscribe(0, 2, "x");
        }
    }
    b.into_bytes()
}

#[test]
fn a_row_that_comes_back_in_time_after_a_step_it_would_change_is_reported() {
    // x at 0.1 s and 0.4 s, a step at 0.25 s, then x at 0.3 s: nearest and linear at
    // the step would take it (the indexed alignment does).
    let bytes = in_order(
        &[(1, 100_000), (1, 400_000), (0, 250_000), (1, 300_000)],
        None,
    );
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let want = indexed(&log, &grid, &tracks(), &AlignOptions::default());
    let (got, summary) = streamed(&bytes, &grid, &tracks(), StreamOptions::default());
    assert_ne!(got, want);
    assert!(!summary.is_exact());
    assert!(
        summary.tracks.iter().skip(1).all(|t| t.late_rows == 1),
        "{summary:?}"
    );
}

#[test]
fn a_topic_subscribed_again_is_waited_for() {
    // x at 0.1 s, unsubscribed and subscribed again, a step at 0.25 s, x at 0.26 s.
    let rows = [(1, 100_000), (0, 250_000), (2, 260_000)];
    let bytes = in_order(&rows, Some(0));
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let want = indexed(&log, &grid, &tracks(), &AlignOptions::default());
    let (got, summary) = streamed(&bytes, &grid, &tracks(), StreamOptions::default());
    assert!(summary.is_exact(), "{summary:?}");
    assert_eq!(got, want);
}

#[test]
fn rows_outside_the_window_and_after_the_steps_are_not_held() {
    let bytes = written(200, |_| false).into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let grid = Grid::topic("grid", 0);
    let bound = 3 * (12 * 10 + 2); // three tracks of x (10 Hz), 12 s each, at most
                                   // A window late in the log, and one early: the same steps as the indexed
                                   // alignment's, few rows held.
    for (start, end) in [(Some(190_000_000), None), (None, Some(1_000_000))] {
        let since_boot = AlignOptions::default()
            .window_us(start.map(|s: u64| s + 1_000), end.map(|e: u64| e + 1_000));
        let want = indexed(&log, &grid, &tracks(), &since_boot);
        let options = StreamOptions {
            align: since_boot,
            ..StreamOptions::default()
        };
        let (got, summary) = streamed(&bytes, &grid, &tracks(), options);
        assert_eq!(got, want, "{start:?} {end:?}");
        assert!(
            summary.held_rows_peak <= bound,
            "{start:?} {end:?}: {summary:?}"
        );
    }
    // The grid's rows end at 10 s, x's at 5 s, a third topic logs on to 200 s: the
    // last steps are decided by the horizon, and the third topic's rows let go.
    let mut b = LogBuilder::new(1, 1_000);
    b.format("grid:uint64_t timestamp;float v;");
    b.format("x:uint64_t timestamp;float v;");
    b.format("y:uint64_t timestamp;float v;");
    b.subscribe(0, 0, "grid");
    b.subscribe(0, 1, "x");
    b.subscribe(0, 2, "y");
    for k in 0..20_000u64 {
        let t = 1_000 + k * 10_000;
        if k < 1_000 {
            b.data(0, &row(t, 0.0));
        }
        if k < 500 && k % 10 == 0 {
            b.data(1, &row(t, 1.0));
        }
        b.data(2, &row(t, 2.0));
    }
    let bytes = b.into_bytes();
    let three = vec![
        Track::new("x", 0, Method::Linear),
        Track::new("y", 0, Method::Previous),
    ];
    let (got, summary) = streamed(&bytes, &grid, &three, StreamOptions::default());
    assert_eq!(got.len(), 1_000);
    assert!(summary.held_rows_peak < 1_500, "{summary:?}");
}
