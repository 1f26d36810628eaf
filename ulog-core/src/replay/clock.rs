//! What a player keeps time with: the system's monotonic clock, or a virtual one that
//! moves only when told (tests, simulations).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A monotonic clock: the time since its origin, and a way to wait for a time.
pub trait Clock {
    /// The time since the clock's origin; never goes back.
    fn now(&self) -> Duration;
    /// Returns once [`now`](Clock::now) is `t` or later (at once if it is already).
    fn sleep_until(&self, t: Duration);
}

/// The system's monotonic clock ([`Instant`]), from when it was made.
///
/// It waits with [`std::thread::sleep`], which wakes up late by the scheduler's
/// latency, then, for the last stretch before the time ([`SystemClock::spin`]),
/// spins on the clock: a release comes within a few microseconds of its time, at the
/// cost of a busy core for that stretch of each wait. BENCHMARKS.md has the release
/// jitter of both.
///
/// ```
/// use std::time::Duration;
/// use ulog_core::replay::{Clock, SystemClock};
/// let clock = SystemClock::new();
/// assert_eq!(clock.spin(), SystemClock::DEFAULT_SPIN);
/// let t = clock.now();
/// clock.sleep_until(t); // already reached: returns at once
/// assert!(clock.now() >= t);
/// assert_eq!(SystemClock::with_spin(Duration::ZERO).spin(), Duration::ZERO);
/// ```
#[derive(Debug, Clone, Copy)]
pub struct SystemClock {
    origin: Instant,
    spin: Duration,
}

impl SystemClock {
    /// How long before its time a wait stops sleeping and spins, by default: longer
    /// than the usual oversleep of `thread::sleep` on Linux (BENCHMARKS.md).
    pub const DEFAULT_SPIN: Duration = Duration::from_micros(100);

    /// The clock from now, spinning the last [`DEFAULT_SPIN`](Self::DEFAULT_SPIN) of
    /// each wait.
    pub fn new() -> SystemClock {
        SystemClock::with_spin(SystemClock::DEFAULT_SPIN)
    }

    /// The clock from now, spinning the last `spin` of each wait
    /// ([`Duration::ZERO`]: only sleeping, no busy core, later releases).
    pub fn with_spin(spin: Duration) -> SystemClock {
        SystemClock {
            origin: Instant::now(),
            spin,
        }
    }

    /// How long before its time a wait stops sleeping and spins.
    pub fn spin(&self) -> Duration {
        self.spin
    }

    /// The instant of the clock's origin.
    pub fn origin(&self) -> Instant {
        self.origin
    }
}

impl Default for SystemClock {
    fn default() -> SystemClock {
        SystemClock::new()
    }
}

impl Clock for SystemClock {
    fn now(&self) -> Duration {
        self.origin.elapsed()
    }

    fn sleep_until(&self, t: Duration) {
        let left = t.saturating_sub(self.now());
        if left > self.spin {
            std::thread::sleep(left - self.spin);
        }
        while self.now() < t {
            std::hint::spin_loop();
        }
    }
}

/// A clock that moves only when slept on or told to: a player's schedule run in a test
/// or a simulation without waiting. Clones share the time, so a test keeps one and
/// hands the other to the player.
///
/// ```
/// use std::time::Duration;
/// use ulog_core::replay::{Clock, VirtualClock};
/// let clock = VirtualClock::new();
/// let theirs = clock.clone();
/// theirs.sleep_until(Duration::from_secs(3)); // returns at once, at 3 s
/// clock.advance(Duration::from_millis(500));
/// assert_eq!(theirs.now(), Duration::from_millis(3_500));
/// clock.sleep_until(Duration::from_secs(1)); // in the past: no change
/// assert_eq!(clock.now(), Duration::from_millis(3_500));
/// ```
#[derive(Debug, Clone, Default)]
pub struct VirtualClock {
    nanos: Arc<AtomicU64>,
}

impl VirtualClock {
    /// A clock at zero.
    pub fn new() -> VirtualClock {
        VirtualClock::default()
    }

    /// Moves the time on by `d`.
    pub fn advance(&self, d: Duration) {
        let d = nanos(d);
        // Saturating: a clock at its end stays there rather than wrap to zero.
        let _ = self
            .nanos
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                Some(n.saturating_add(d))
            });
    }

    /// Moves the time to `t`, if that is later (the clock never goes back).
    pub fn set(&self, t: Duration) {
        self.nanos.fetch_max(nanos(t), Ordering::SeqCst);
    }
}

/// Nanoseconds as the virtual clock counts them (u64: 584 years).
fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

impl Clock for VirtualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.nanos.load(Ordering::SeqCst))
    }

    fn sleep_until(&self, t: Duration) {
        self.set(t);
    }
}

/// A clock shared: the player and its caller both reading one clock.
impl<C: Clock + ?Sized> Clock for &C {
    fn now(&self) -> Duration {
        (**self).now()
    }
    fn sleep_until(&self, t: Duration) {
        (**self).sleep_until(t)
    }
}
