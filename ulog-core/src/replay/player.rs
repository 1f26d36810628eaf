//! The player: releases a timeline's items on a clock, by the pacing rule of the
//! [module](super).

use std::time::Duration;

use super::clock::Clock;
use super::controls::{Command, Controls};
use super::pace::{InvalidRate, Pace};
use super::Timeline;

/// How a [`Player`] starts out.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayerOptions {
    /// How fast items are released (default: as fast as possible).
    pub pace: Pace,
    /// A release later than this after its due time is [late](Release::late)
    /// (default 1 ms).
    pub late_after: Duration,
    /// Whether the end of the timeline starts it again (default: no).
    pub looping: bool,
    /// Whether a late release re-anchors the schedule, so that the items after it keep
    /// the log's spacing from it instead of catching up (default: no).
    pub slip: bool,
}

impl Default for PlayerOptions {
    fn default() -> PlayerOptions {
        PlayerOptions {
            pace: Pace::AsFastAsPossible,
            late_after: PlayerOptions::LATE_AFTER,
            looping: false,
            slip: false,
        }
    }
}

impl PlayerOptions {
    /// The default [`late_after`](Self::late_after): well above the oversleep of a
    /// sleeping thread on a desktop or server OS (BENCHMARKS.md), well below a PX4
    /// controller's period of a few milliseconds.
    pub const LATE_AFTER: Duration = Duration::from_millis(1);

    /// Paced to log time × `rate`, the rest by default; a rate that is not a
    /// positive, finite number is refused.
    pub fn paced(rate: f64) -> Result<PlayerOptions, InvalidRate> {
        Ok(PlayerOptions {
            pace: Pace::rate(rate)?,
            ..PlayerOptions::default()
        })
    }

    /// Late after `d`.
    pub fn late_after(mut self, d: Duration) -> PlayerOptions {
        self.late_after = d;
        self
    }

    /// Looping, or not.
    pub fn looping(mut self, on: bool) -> PlayerOptions {
        self.looping = on;
        self
    }

    /// Slipping after late releases, or catching up.
    pub fn slip(mut self, on: bool) -> PlayerOptions {
        self.slip = on;
        self
    }
}

/// An item released, and its timing on the player's clock.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Release<T> {
    /// The item.
    pub item: T,
    /// Its log time, boot microseconds.
    pub t_us: u64,
    /// The clock time it was due at (for a step, or as fast as possible: the time it
    /// was asked for).
    pub due: Duration,
    /// The clock time it was released at.
    pub released: Duration,
    /// `released − due`.
    pub lateness: Duration,
    /// Whether `lateness` is over [`PlayerOptions::late_after`].
    pub late: bool,
}

/// What [`Player::poll`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum Poll<T> {
    /// An item is released.
    Ready(Release<T>),
    /// The next item is due at this clock time: poll again then (or on a command).
    Wait(Duration),
    /// Paused: nothing is released until a command (resume, step, seek…).
    Paused,
    /// The timeline has no more items (a seek back plays on), or the replay was
    /// stopped.
    Finished,
}

/// Where the schedule is anchored: log time `log_us` is due at clock time `clock`.
#[derive(Debug, Clone, Copy)]
struct Anchor {
    log_us: u64,
    clock: Duration,
}

/// How long a blocking [`Player::next`] sleeps at most before it looks for commands
/// from other threads: how soon a pause or a seek takes effect during a long gap
/// in the log.
const WAIT_SLICE: Duration = Duration::from_millis(20);

/// Releases a [`Timeline`]'s items on a [`Clock`]: paced, or as fast as possible,
/// steered by [`Controls`] (see the [module](super) for the pacing rule).
///
/// [`poll`](Player::poll) never blocks: it releases an item or says what to wait for.
/// [`next`](Player::next) (the player is an [`Iterator`] of [`Release`]s) waits on
/// the clock and for commands, and returns `None` at the end.
pub struct Player<T: Timeline, C: Clock> {
    timeline: T,
    clock: C,
    controls: Controls,
    commands: Vec<Command>,
    pace: Pace,
    late_after: Duration,
    slip: bool,
    looping: bool,
    paused: bool,
    stopped: bool,
    /// Items to release while paused.
    steps: u32,
    /// The next item, taken from the timeline but not yet due.
    next: Option<(u64, T::Item)>,
    /// The schedule, while playing at a rate.
    anchor: Option<Anchor>,
    /// The play head while the schedule is not anchored (`None`: at the next item).
    head: Option<u64>,
    released: u64,
    late: u64,
}

impl<T: Timeline, C: Clock> Player<T, C> {
    /// A player of `timeline` on `clock`, playing (not paused) from the timeline's
    /// current position; a pace whose rate is not a positive, finite number is
    /// refused.
    pub fn new(timeline: T, clock: C, options: PlayerOptions) -> Result<Player<T, C>, InvalidRate> {
        options.pace.checked()?;
        Ok(Player {
            timeline,
            clock,
            controls: Controls::new(options.pace, options.looping),
            commands: Vec::new(),
            pace: options.pace,
            late_after: options.late_after,
            slip: options.slip,
            looping: options.looping,
            paused: false,
            stopped: false,
            steps: 0,
            next: None,
            anchor: None,
            head: None,
            released: 0,
            late: 0,
        })
    }

    /// A handle to steer the player, from this thread or another.
    pub fn controls(&self) -> Controls {
        self.controls.clone()
    }

    /// The clock.
    pub fn clock(&self) -> &C {
        &self.clock
    }

    /// The timeline.
    pub fn timeline(&self) -> &T {
        &self.timeline
    }

    /// The timeline, given back.
    pub fn into_timeline(self) -> T {
        self.timeline
    }

    /// How many items were released.
    pub fn released_count(&self) -> u64 {
        self.released
    }

    /// How many of them were [late](Release::late).
    pub fn late_count(&self) -> u64 {
        self.late
    }

    /// The log time the replay has reached (boot microseconds): the play head as
    /// the clock stands now, while playing at a rate; the last item released, as
    /// fast as possible; `None` before the first item (or right after looping).
    pub fn position_us(&self) -> Option<u64> {
        self.head_at(self.clock.now())
    }

    /// Releases the next item if it is due, or says what the player waits for. Takes
    /// the commands given since the last poll first.
    pub fn poll(&mut self) -> Poll<T::Item> {
        let now = self.clock.now();
        // The buffer is kept between polls, so that commands allocate only once.
        let mut commands = std::mem::take(&mut self.commands);
        self.controls.take(&mut commands);
        for c in commands.drain(..) {
            self.apply(c, now);
        }
        self.commands = commands;
        if self.stopped {
            return Poll::Finished;
        }
        if self.paused && self.steps == 0 {
            return Poll::Paused;
        }
        let Some(t) = self.peek() else {
            return Poll::Finished;
        };
        let due = match self.pace {
            Pace::Rate(rate) if !self.paused => self.due(t, rate, now),
            // A step, or as fast as possible: due when asked for.
            _ => now,
        };
        if now < due {
            return Poll::Wait(due);
        }
        let Some((t_us, item)) = self.next.take() else {
            unreachable!("peek found an item")
        };
        let lateness = now - due;
        let late = lateness > self.late_after;
        if self.paused {
            self.steps -= 1;
            self.head = Some(t_us);
        } else if self.pace == Pace::AsFastAsPossible {
            self.head = Some(t_us);
        } else if late && self.slip {
            self.anchor = Some(Anchor {
                log_us: t_us,
                clock: now,
            });
        }
        self.released += 1;
        self.late += u64::from(late);
        Poll::Ready(Release {
            item,
            t_us,
            due,
            released: now,
            lateness,
            late,
        })
    }

    /// One command's effect, at clock time `now`.
    fn apply(&mut self, command: Command, now: Duration) {
        match command {
            Command::Pause => self.pause(now),
            Command::Resume => {
                // Anchored again at the head by the next poll.
                self.paused = false;
                self.steps = 0;
            }
            Command::Step => {
                self.pause(now);
                self.steps += 1;
            }
            Command::Seek(t_us) => {
                self.timeline.seek(t_us);
                self.next = None;
                self.anchor = None;
                self.head = Some(t_us);
            }
            Command::Looping(on) => self.looping = on,
            Command::Pace(pace) => {
                self.unanchor(now);
                self.pace = pace;
            }
            Command::Stop => self.stopped = true,
        }
    }

    fn pause(&mut self, now: Duration) {
        if !self.paused {
            self.unanchor(now);
            self.paused = true;
        }
    }

    /// Leaves the schedule, keeping the head where the clock has brought it.
    fn unanchor(&mut self, now: Duration) {
        self.head = self.head_at(now);
        self.anchor = None;
    }

    /// The play head at clock time `now`.
    fn head_at(&self, now: Duration) -> Option<u64> {
        match (self.anchor, self.pace) {
            (Some(a), Pace::Rate(rate)) => {
                let ran = now.saturating_sub(a.clock).as_nanos() as f64 * rate / 1e3;
                Some(a.log_us.saturating_add(ran.round() as u64))
            }
            _ => self.head,
        }
    }

    /// The next item's time, taken from the timeline if need be; at the end, the
    /// timeline started again if looping.
    fn peek(&mut self) -> Option<u64> {
        if self.next.is_none() {
            self.next = self.timeline.advance();
            if self.next.is_none() && self.looping {
                self.timeline.seek(0);
                self.next = self.timeline.advance();
                self.anchor = None;
                self.head = None;
            }
        }
        self.next.as_ref().map(|(t, _)| *t)
    }

    /// The clock time an item of log time `t` is due at, the schedule anchored at
    /// `now` first if it is not.
    fn due(&mut self, t: u64, rate: f64, now: Duration) -> Duration {
        let anchor = *self.anchor.get_or_insert(Anchor {
            log_us: self.head.map_or(t, |h| h.min(t)),
            clock: now,
        });
        let to_clock = |us: u64| Duration::from_nanos((us as f64 * 1e3 / rate).round() as u64);
        if t >= anchor.log_us {
            anchor.clock + to_clock(t - anchor.log_us)
        } else {
            // Before the anchor: an item the head passed while the player was late.
            anchor.clock.saturating_sub(to_clock(anchor.log_us - t))
        }
    }

    /// How [`next`](Player::next) waits for a poll that is not ready.
    fn wait(&mut self, poll: &Poll<T::Item>) -> bool {
        match poll {
            Poll::Wait(due) => {
                let due = if self.controls.is_sole() {
                    // No other handle: no command can come during the wait.
                    *due
                } else {
                    (*due).min(self.clock.now() + WAIT_SLICE)
                };
                self.clock.sleep_until(due);
                true
            }
            Poll::Paused => self.controls.wait_for_command(),
            _ => false,
        }
    }
}

/// The player as an iterator: [`next`](Iterator::next) blocks until an item is due
/// (sleeping on the clock) or, while paused, until a command comes from another
/// thread. It returns `None` when the timeline ends (without looping), when the
/// replay is stopped, and when the player is paused with no other [`Controls`] left
/// that could resume it. With a [`VirtualClock`](super::VirtualClock) it never waits
/// on the wall clock (the clock moves to each due time), except paused.
impl<T: Timeline, C: Clock> Iterator for Player<T, C> {
    type Item = Release<T::Item>;

    fn next(&mut self) -> Option<Release<T::Item>> {
        loop {
            let poll = self.poll();
            if let Poll::Ready(release) = poll {
                return Some(release);
            }
            if !self.wait(&poll) {
                return None;
            }
        }
    }
}

impl<T, C> core::fmt::Debug for Player<T, C>
where
    T: Timeline + core::fmt::Debug,
    C: Clock + core::fmt::Debug,
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Player")
            .field("timeline", &self.timeline)
            .field("clock", &self.clock)
            .field("pace", &self.pace)
            .field("paused", &self.paused)
            .field("looping", &self.looping)
            .field("stopped", &self.stopped)
            .field("next_us", &self.next.as_ref().map(|(t, _)| *t))
            .field("released", &self.released)
            .field("late", &self.late)
            .finish_non_exhaustive()
    }
}
