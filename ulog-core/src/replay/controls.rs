//! The handle that steers a player, from its own thread or another: commands queued
//! in order, taken by the player when it is next polled.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};

use super::pace::{InvalidRate, Pace};

/// What a [`Controls`] asked, in the order asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Command {
    Pause,
    Resume,
    Step,
    Seek(u64),
    Looping(bool),
    Pace(Pace),
    Stop,
}

/// The commands not yet taken, and the state they leave the player in (for the
/// handle's questions, answered without the player).
#[derive(Debug)]
struct State {
    queue: Vec<Command>,
    paused: bool,
    looping: bool,
    pace: Pace,
    stopped: bool,
    /// The handles alive, the player's own among them: a paused player that is the
    /// last waits for no one.
    handles: usize,
}

#[derive(Debug)]
struct Shared {
    state: Mutex<State>,
    /// Whether `queue` holds anything: the player looks here on every poll, and
    /// takes the lock only when there is something to take.
    pending: AtomicBool,
    /// Wakes a player blocked while paused.
    changed: Condvar,
}

/// Steers a [`Player`](super::Player): pause, resume, step, seek, loop, pace, stop. A
/// cloneable handle that may be sent to other threads; each command takes effect, in
/// the order given, when the player is next polled.
///
/// ```
/// use ulog_core::replay::{Player, PlayerOptions, Poll, Recorded, VirtualClock};
/// let items = Recorded::new(vec![(0, 'a'), (1_000, 'b'), (2_000, 'c')]);
/// let mut player = Player::new(items, VirtualClock::new(), PlayerOptions::paced(1.0).unwrap()).unwrap();
/// let controls = player.controls();
/// controls.pause();
/// assert_eq!(player.poll(), Poll::Paused);
/// controls.step(); // exactly one item, though paused
/// assert!(matches!(player.poll(), Poll::Ready(r) if r.item == 'a'));
/// assert_eq!(player.poll(), Poll::Paused);
/// controls.seek(1_500);
/// controls.step();
/// assert!(matches!(player.poll(), Poll::Ready(r) if r.item == 'c'));
/// ```
#[derive(Debug)]
pub struct Controls {
    shared: Arc<Shared>,
}

impl Clone for Controls {
    fn clone(&self) -> Controls {
        self.state().handles += 1;
        Controls {
            shared: Arc::clone(&self.shared),
        }
    }
}

impl Drop for Controls {
    fn drop(&mut self) {
        self.state().handles -= 1;
        // A player waiting while paused for a command learns that none can come.
        self.shared.changed.notify_all();
    }
}

impl Controls {
    pub(super) fn new(pace: Pace, looping: bool) -> Controls {
        Controls {
            shared: Arc::new(Shared {
                state: Mutex::new(State {
                    queue: Vec::new(),
                    paused: false,
                    looping,
                    pace,
                    stopped: false,
                    handles: 1,
                }),
                pending: AtomicBool::new(false),
                changed: Condvar::new(),
            }),
        }
    }

    /// The state, whether or not a thread panicked holding it: it is a queue and
    /// flags, valid at every point.
    fn state(&self) -> MutexGuard<'_, State> {
        self.shared
            .state
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    fn send(&self, command: Command) {
        let mut state = self.state();
        match command {
            Command::Pause | Command::Step => state.paused = true,
            Command::Resume => state.paused = false,
            Command::Looping(on) => state.looping = on,
            Command::Pace(pace) => state.pace = pace,
            Command::Stop => state.stopped = true,
            Command::Seek(_) => {}
        }
        state.queue.push(command);
        self.shared.pending.store(true, Ordering::Release);
        self.shared.changed.notify_all();
    }

    /// Stops releasing items: the play head stays where it is until [`resume`](Self::resume).
    pub fn pause(&self) {
        self.send(Command::Pause);
    }

    /// Plays on from the play head, the schedule anchored again (no catch-up burst).
    pub fn resume(&self) {
        self.send(Command::Resume);
    }

    /// Releases exactly the next item, at once, and stays paused (pausing first if
    /// playing). Steps add up: two steps release two items.
    pub fn step(&self) {
        self.send(Command::Step);
    }

    /// Moves to log time `t_us`: the next item is the first at or after it (none past
    /// the end, unless looping), due after its distance from `t_us` at the pace.
    pub fn seek(&self, t_us: u64) {
        self.send(Command::Seek(t_us));
    }

    /// Whether the end of the timeline starts it again from its first item.
    pub fn set_looping(&self, on: bool) {
        self.send(Command::Looping(on));
    }

    /// Plays on at `pace` from the play head; a rate that is not a positive, finite
    /// number is refused (the pace is then unchanged).
    pub fn set_pace(&self, pace: Pace) -> Result<(), InvalidRate> {
        if let Pace::Rate(r) = pace {
            Pace::rate(r)?;
        }
        self.send(Command::Pace(pace));
        Ok(())
    }

    /// Plays on at log time × `rate` ([`set_pace`](Self::set_pace) of
    /// [`Pace::Rate`]); a rate that is not a positive, finite number is refused.
    pub fn set_rate(&self, rate: f64) -> Result<(), InvalidRate> {
        self.set_pace(Pace::Rate(rate))
    }

    /// Ends the replay: the player releases nothing more, and a player blocked in
    /// [`next`](super::Player::next) returns `None`.
    pub fn stop(&self) {
        self.send(Command::Stop);
    }

    /// Whether the commands given leave the player paused.
    pub fn is_paused(&self) -> bool {
        self.state().paused
    }

    /// Whether the commands given leave the player looping.
    pub fn is_looping(&self) -> bool {
        self.state().looping
    }

    /// The pace the commands given leave the player at.
    pub fn pace(&self) -> Pace {
        self.state().pace
    }

    /// Whether the replay was stopped.
    pub fn is_stopped(&self) -> bool {
        self.state().stopped
    }

    /// The commands given since the last call, in order (none without taking the
    /// lock).
    pub(super) fn take(&self, into: &mut Vec<Command>) {
        if !self.shared.pending.load(Ordering::Acquire) {
            return;
        }
        let mut state = self.state();
        self.shared.pending.store(false, Ordering::Release);
        into.append(&mut state.queue);
    }

    /// Blocks until a command is given, or no other handle is left to give one;
    /// whether one was given.
    pub(super) fn wait_for_command(&self) -> bool {
        let mut state = self.state();
        while state.queue.is_empty() && state.handles > 1 {
            state = self
                .shared
                .changed
                .wait(state)
                .unwrap_or_else(|poisoned| poisoned.into_inner());
        }
        !state.queue.is_empty()
    }

    /// Whether this is the only handle: no one else can give a command.
    pub(super) fn is_sole(&self) -> bool {
        self.state().handles == 1
    }
}
