//! Playing a log's items back on its own clock: as fast as possible, or paced to the
//! log's time × a rate, with pause, resume, single step, seek and loop.
//!
//! A [`Player`] takes its items from a [`Timeline`] (items in non-decreasing log
//! time that can be repositioned: [`Recorded`] holds them in memory) and its sense of
//! time from a [`Clock`]: the [`SystemClock`] of a real replay, or a [`VirtualClock`]
//! that moves only when told, so that a tool is tested without waiting.
//!
//! ```
//! use std::time::Duration;
//! use ulog_core::replay::{Pace, Player, PlayerOptions, Poll, Recorded, VirtualClock};
//!
//! // Three items 10 ms apart (log times in boot microseconds), played at twice speed.
//! let items = Recorded::new(vec![(1_000_000, 'a'), (1_010_000, 'b'), (1_020_000, 'c')]);
//! let clock = VirtualClock::new();
//! let mut player = Player::new(items, clock.clone(), PlayerOptions::paced(2.0).unwrap()).unwrap();
//!
//! // The first item anchors the schedule: it is due at once.
//! let Poll::Ready(a) = player.poll() else { panic!() };
//! assert_eq!((a.item, a.due), ('a', Duration::ZERO));
//! // The next is 10 ms of log time later: 5 ms of clock time at rate 2.
//! assert_eq!(player.poll(), Poll::Wait(Duration::from_millis(5)));
//! clock.advance(Duration::from_millis(7));
//! let Poll::Ready(b) = player.poll() else { panic!() };
//! assert_eq!((b.item, b.lateness, b.late), ('b', Duration::from_millis(2), true));
//! // Still on the schedule (not 5 ms after `b`'s late release): due at 10 ms.
//! assert_eq!(player.poll(), Poll::Wait(Duration::from_millis(10)));
//!
//! // `next` blocks on the clock (a virtual one just moves ahead).
//! let c = player.next().unwrap();
//! assert_eq!((c.item, c.released), ('c', Duration::from_millis(10)));
//! assert_eq!(player.poll(), Poll::Finished);
//! assert_eq!(player.late_count(), 1);
//! ```
//!
//! # Pacing
//!
//! - **Schedule.** At rate `r` an item of log time `t` is due at clock time
//!   `anchor_clock + (t − anchor_log) / r`. The first item anchors the schedule
//!   (`anchor_log = t`, `anchor_clock` = the clock when it is polled): it is due at
//!   once.
//! - **Release.** An item is released when the clock reaches its due time, never
//!   before; its [`Release`] says when it was due, when it was released and how late.
//!   A release later than [`PlayerOptions::late_after`] is
//!   [`late`](Release::late) and counted ([`Player::late_count`]). Late items keep
//!   the schedule: the ones after them come out as soon as they are due, each
//!   reported late, until the player has caught up (unless
//!   [`PlayerOptions::slip`]: then a late release re-anchors the schedule and the log's
//!   spacing is kept from it).
//! - **Play head.** The log time the schedule has reached,
//!   `anchor_log + (clock − anchor_clock) × r`. Pause freezes it, a [step](Controls::step)
//!   or a [seek](Controls::seek) moves it (to the item stepped to, to the time sought).
//! - **Re-anchoring.** After a pause, a seek, a step or a change of pace the schedule
//!   is anchored again when the next item is polled: at the play head
//!   (`anchor_log` = the head, or the next item's time if that is earlier),
//!   `anchor_clock` = the clock then. So the next item keeps its distance from the
//!   head, and no burst of catch-up releases follows.
//! - **Loop.** With [looping](Controls::set_looping) on, the end of the timeline
//!   seeks it to its start ([`Timeline::seek`] to 0), and the first item is due at once.
//! - **As fast as possible** ([`Pace::AsFastAsPossible`]): every item is due when
//!   polled; nothing is late.
//!
//! Controls ([`Controls`]: pause, resume, step, seek, loop, pace, stop) are a handle
//! that another thread can hold; they take effect at the next [`Player::poll`].

mod clock;
mod controls;
mod pace;
mod player;
mod recorded;

#[cfg(test)]
mod tests;

pub use clock::{Clock, SystemClock, VirtualClock};
pub use controls::Controls;
pub use pace::{InvalidRate, Pace};
pub use player::{Player, PlayerOptions, Poll, Release};
pub use recorded::Recorded;

/// A stream of items in non-decreasing time (boot microseconds) that can be repositioned:
/// [`Recorded`] items, the structs of an alignment
/// ([`AlignedSteps`](crate::align::AlignedSteps)) or the rows of several topics by time
/// ([`TimeOrdered`](crate::align::TimeOrdered)). Its method is not named `next`, so
/// that a timeline that is also an iterator reads either way without ambiguity.
pub trait Timeline {
    /// What the timeline holds at each time.
    type Item;
    /// Moves to the next item and returns it with its time.
    fn advance(&mut self) -> Option<(u64, Self::Item)>;
    /// Repositions so that the next item is the first whose time is `t_us` or later.
    fn seek(&mut self, t_us: u64);
}

/// A timeline borrowed: a player over it leaves it with the caller.
impl<L: Timeline + ?Sized> Timeline for &mut L {
    type Item = L::Item;
    fn advance(&mut self) -> Option<(u64, L::Item)> {
        (**self).advance()
    }
    fn seek(&mut self, t_us: u64) {
        (**self).seek(t_us)
    }
}
