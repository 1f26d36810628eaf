//! How close to their due times a paced replay releases items on the system clock,
//! and what the player costs per release.
//!
//! ```text
//! cargo bench -p ulog-core --bench replay_jitter
//! cargo bench -p ulog-core --bench replay_jitter -- --test   # short (CI)
//! ```
//!
//! The jitter: 2,000 items at 1 kHz played at rate 1 on a [`SystemClock`], for
//! several spin margins (0: only `thread::sleep`), in rounds; each release's distance
//! from its due time, read on the clock as soon as `Player::next` returns it (what the
//! consumer sees), printed as median, p99, worst and the share over the default late
//! threshold (1 ms). Criterion measures the player's cost per
//! release, on a virtual clock (no waiting): as fast as possible, and paced.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BatchSize, Criterion, Throughput};
use ulog_core::replay::{Clock, Player, PlayerOptions, Recorded, SystemClock, VirtualClock};

/// Items at 1 kHz.
const PERIOD_US: u64 = 1_000;

fn items(n: u64) -> Recorded<u64> {
    (0..n).map(|i| (1_000_000 + i * PERIOD_US, i)).collect()
}

/// |release − due| of each item, played on the system clock spinning the last `spin`.
fn distances(n: u64, spin: Duration, into: &mut Vec<Duration>) {
    let clock = SystemClock::with_spin(spin);
    let player = Player::new(items(n), clock, PlayerOptions::paced(1.0).unwrap()).unwrap();
    // The first item anchors the schedule (due when polled): no wait to measure.
    for r in player.skip(1) {
        let seen = clock.now();
        into.push(seen.abs_diff(r.due));
    }
}

fn quantile(sorted: &[Duration], q: f64) -> Duration {
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i]
}

fn micros(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

/// The spin margins compared (µs).
const SPINS: [u64; 4] = [0, 50, 100, 200];
/// Each margin's items are played in this many rounds, the margins in turn, so that
/// a busy spell of the machine falls on all of them.
const ROUNDS: u64 = 8;

fn main() {
    let test = std::env::args().any(|a| a == "--test");
    let n = if test { 200 } else { 2_000 };
    let mut seen: Vec<Vec<Duration>> = vec![Vec::new(); SPINS.len()];
    for _ in 0..ROUNDS {
        for (spin, seen) in SPINS.iter().zip(&mut seen) {
            distances(n / ROUNDS + 1, Duration::from_micros(*spin), seen);
        }
    }
    println!(
        "release jitter, {n} items at 1 kHz per margin ({ROUNDS} rounds), rate 1, SystemClock, |release - due|:"
    );
    for (spin, d) in SPINS.iter().zip(&mut seen) {
        d.sort();
        let late = d.iter().filter(|d| **d > PlayerOptions::LATE_AFTER).count();
        println!(
            "  spin {spin:>3} µs: median {:>6.1} µs, p99 {:>7.1} µs, worst {:>7.1} µs, over 1 ms {:.2} %",
            micros(quantile(d, 0.5)),
            micros(quantile(d, 0.99)),
            micros(*d.last().unwrap()),
            100.0 * late as f64 / d.len() as f64,
        );
    }

    let mut c = Criterion::default().configure_from_args();
    let mut group = c.benchmark_group("replay");
    const N: u64 = 10_000;
    group.throughput(Throughput::Elements(N));
    for (name, options) in [
        ("as fast as possible", PlayerOptions::default()),
        ("paced, virtual clock", PlayerOptions::paced(1.0).unwrap()),
    ] {
        group.bench_function(name, |b| {
            b.iter_batched(
                || Player::new(items(N), VirtualClock::new(), options.clone()).unwrap(),
                |player| {
                    for r in player {
                        black_box(r);
                    }
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
    c.final_summary();
}
