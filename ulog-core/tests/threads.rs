//! A call that starts threads returns after they have ended. The scope's own join
//! returns once each thread's closure has, while the thread may still be running its
//! thread-local destructors (rust-lang/rust#116179): a caller would count our threads
//! still alive, and a leak checker reported their destructor lists (the `chunked` and
//! `columns` fuzz targets under AddressSanitizer). Alone in its binary, so that no
//! other test starts threads meanwhile.
#![cfg(target_os = "linux")]

use ulog_core::parallel::largest_first;
use ulog_core::{scan, ScanOptions, Source};

/// The threads of this process, as Linux counts them.
fn threads() -> usize {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("Threads:")).unwrap();
    line["Threads:".len()..].trim().parse().unwrap()
}

#[test]
fn no_thread_outlives_the_call_that_started_it() {
    let bytes = ulog_core::testing::sample_log();
    let ahead = ScanOptions::default().read_ahead(true);
    let before = threads();
    for round in 0..300 {
        let done = largest_first(&[1; 8], 4, Ok::<usize, ()>);
        assert_eq!(done.len(), 8);
        assert_eq!(threads(), before, "round {round}: parallel::largest_first");
        scan(Source::reader(&bytes[..]), &ahead, |_| {}).unwrap();
        assert_eq!(threads(), before, "round {round}: a scan reading ahead");
    }
}
