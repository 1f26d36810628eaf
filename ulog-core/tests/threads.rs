//! A call that starts threads returns after they have ended. The scope's own join
//! returns once each thread's closure has, while the thread may still be running its
//! thread-local destructors (rust-lang/rust#116179): a caller would count our threads
//! still alive, and a leak checker reported their destructor lists (the `chunked` and
//! `columns` fuzz targets under AddressSanitizer). Alone in its binary, so that no
//! other test starts threads meanwhile.
#![cfg(target_os = "linux")]

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use ulog_core::parallel::largest_first;
use ulog_core::{scan, ScanOptions, Source};

/// The threads of this process, as Linux counts them.
fn threads() -> usize {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("Threads:")).unwrap();
    line["Threads:".len()..].trim().parse().unwrap()
}

/// The thread count once it is back at `before`, or what it still is after a second.
/// Linux counts a thread until it is released, a little after the join returns (the
/// join waits for the thread to clear its id, which it does earlier in its exit): on a
/// busy machine the count read right after the join was one too high, once in 300
/// rounds. A thread that outlives the call for good stays counted.
fn threads_settled(before: usize) -> usize {
    let start = Instant::now();
    loop {
        let now = threads();
        if now == before || start.elapsed() > Duration::from_secs(1) {
            return now;
        }
        std::thread::sleep(Duration::from_micros(100));
    }
}

static STARTED: AtomicUsize = AtomicUsize::new(0);
static FINISHED: AtomicUsize = AtomicUsize::new(0);

/// A thread-local whose destructor runs as its thread ends.
struct Marker;

impl Drop for Marker {
    fn drop(&mut self) {
        FINISHED.fetch_add(1, Ordering::SeqCst);
    }
}

thread_local! {
    static MARKER: Marker = {
        STARTED.fetch_add(1, Ordering::SeqCst);
        Marker
    };
}

#[test]
fn no_thread_outlives_the_call_that_started_it() {
    let bytes = ulog_core::testing::sample_log();
    let ahead = ScanOptions::default().read_ahead(true);
    let before = threads();
    let caller = std::thread::current().id();
    for round in 0..300 {
        let done = largest_first(&[1; 8], 4, |i| {
            // The calling thread runs jobs too, and lives on.
            if std::thread::current().id() != caller {
                MARKER.with(|_| {});
            }
            Ok::<usize, ()>(i)
        });
        assert_eq!(done.len(), 8);
        // Every thread that ran a job has run its thread-local destructors when the
        // call returns (exactly: no waiting).
        assert_eq!(
            FINISHED.load(Ordering::SeqCst),
            STARTED.load(Ordering::SeqCst),
            "round {round}: parallel::largest_first returned before its threads ended"
        );
        assert_eq!(
            threads_settled(before),
            before,
            "round {round}: parallel::largest_first"
        );
        scan(Source::reader(&bytes[..]), &ahead, |_| {}).unwrap();
        assert_eq!(
            threads_settled(before),
            before,
            "round {round}: a scan reading ahead"
        );
    }
    assert!(
        STARTED.load(Ordering::SeqCst) > 0,
        "the jobs ran on threads"
    );
}
