//! The pacing rule, run on a virtual clock: no test waits on the wall clock.

use std::time::Duration;

use super::*;

const MS: u64 = 1_000;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn us(n: u64) -> Duration {
    Duration::from_micros(n)
}

/// Items `0, 1, 2, …` at log times 1 s + 10 ms × i.
fn every_10ms(n: u64) -> Recorded<u64> {
    (0..n).map(|i| (1_000_000 + 10 * MS * i, i)).collect()
}

fn player(
    n: u64,
    options: PlayerOptions,
) -> (Player<Recorded<u64>, VirtualClock>, VirtualClock, Controls) {
    let clock = VirtualClock::new();
    let player = Player::new(every_10ms(n), clock.clone(), options).unwrap();
    let controls = player.controls();
    (player, clock, controls)
}

/// The item of a poll that must be ready.
#[track_caller]
fn ready(p: Poll<u64>) -> Release<u64> {
    match p {
        Poll::Ready(r) => r,
        other => panic!("not ready: {other:?}"),
    }
}

#[test]
fn paced_items_are_released_at_their_due_times() {
    let (mut p, clock, _) = player(3, PlayerOptions::paced(1.0).unwrap());
    clock.set(ms(500)); // the clock's origin is not the log's
    let a = ready(p.poll());
    assert_eq!(
        (a.item, a.t_us, a.due, a.released),
        (0, 1_000_000, ms(500), ms(500))
    );
    assert_eq!(p.poll(), Poll::Wait(ms(510)));
    clock.advance(ms(9));
    assert_eq!(p.poll(), Poll::Wait(ms(510)), "never early");
    clock.advance(ms(1));
    let b = ready(p.poll());
    assert_eq!((b.item, b.lateness, b.late), (1, Duration::ZERO, false));
    assert_eq!(p.poll(), Poll::Wait(ms(520)));
    clock.set(ms(520));
    assert_eq!(ready(p.poll()).item, 2);
    assert_eq!(p.poll(), Poll::Finished);
    assert_eq!((p.released_count(), p.late_count()), (3, 0));
}

#[test]
fn the_rate_scales_log_time() {
    for (rate, gap) in [(2.0, us(5_000)), (0.5, ms(20)), (3.0, us(3_333))] {
        let (mut p, clock, _) = player(2, PlayerOptions::paced(rate).unwrap());
        ready(p.poll());
        let Poll::Wait(due) = p.poll() else { panic!() };
        // Rounded to the nanosecond.
        assert!(due.abs_diff(gap) < us(1), "{rate}: {due:?}");
        clock.set(due);
        assert_eq!(ready(p.poll()).due, due);
    }
}

#[test]
fn as_fast_as_possible_never_waits() {
    let (p, clock, _) = player(100, PlayerOptions::default());
    clock.set(ms(7));
    let releases: Vec<_> = p.collect();
    assert_eq!(releases.len(), 100);
    assert!(releases
        .iter()
        .all(|r| r.due == ms(7) && r.released == ms(7) && !r.late));
    assert_eq!(clock.now(), ms(7));
}

#[test]
fn next_sleeps_on_the_clock_until_each_item_is_due() {
    let (mut p, clock, controls) = player(5, PlayerOptions::paced(1.0).unwrap());
    // A handle is held: waits are cut into slices to look for commands; the
    // releases are the same.
    let releases: Vec<_> = p.by_ref().collect();
    drop(controls);
    let dues: Vec<_> = releases.iter().map(|r| r.due).collect();
    assert_eq!(dues, [ms(0), ms(10), ms(20), ms(30), ms(40)]);
    assert!(releases.iter().all(|r| r.lateness.is_zero()));
    assert_eq!(clock.now(), ms(40));
    assert_eq!(p.next(), None);
}

#[test]
fn late_releases_are_reported_and_caught_up() {
    let (mut p, clock, _) = player(6, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    // The consumer stalls for 35 ms: items 1, 2 and 3 are overdue.
    clock.advance(ms(35));
    let caught_up: Vec<_> = (0..3).map(|_| ready(p.poll())).collect();
    let lateness: Vec<_> = caught_up.iter().map(|r| r.lateness).collect();
    assert_eq!(lateness, [ms(25), ms(15), ms(5)]);
    assert!(caught_up.iter().all(|r| r.late));
    // Back on the schedule: item 4 is due at 40 ms.
    assert_eq!(p.poll(), Poll::Wait(ms(40)));
    assert_eq!(p.late_count(), 3);
}

#[test]
fn the_threshold_decides_what_is_late() {
    let options = PlayerOptions::paced(1.0).unwrap().late_after(ms(5));
    let (mut p, clock, _) = player(3, options);
    ready(p.poll());
    clock.set(ms(15)); // 5 ms late: not over the threshold
    assert!(!ready(p.poll()).late);
    clock.set(ms(26));
    assert!(ready(p.poll()).late);
    assert_eq!(p.late_count(), 1);
}

#[test]
fn slip_keeps_the_spacing_after_a_late_release() {
    let (mut p, clock, _) = player(4, PlayerOptions::paced(1.0).unwrap().slip(true));
    ready(p.poll());
    clock.advance(ms(35));
    let late = ready(p.poll());
    assert_eq!((late.item, late.lateness, late.late), (1, ms(25), true));
    // The schedule is anchored at the late release: 10 ms of log time later.
    assert_eq!(p.poll(), Poll::Wait(ms(45)));
}

#[test]
fn pause_freezes_the_head_and_resume_reanchors() {
    let (mut p, clock, controls) = player(4, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(4)); // 4 ms into the 10 ms before item 1
    controls.pause();
    assert_eq!(p.poll(), Poll::Paused);
    assert_eq!(p.position_us(), Some(1_004_000));
    clock.set(ms(1_000)); // a long pause
    assert_eq!(p.poll(), Poll::Paused);
    controls.resume();
    // The 6 ms left, from the resume; no release is late.
    assert_eq!(p.poll(), Poll::Wait(ms(1_006)));
    let rest: Vec<_> = p.by_ref().collect();
    assert_eq!(rest.iter().map(|r| r.item).collect::<Vec<_>>(), [1, 2, 3]);
    assert_eq!(
        rest.iter().map(|r| r.due).collect::<Vec<_>>(),
        [ms(1_006), ms(1_016), ms(1_026)]
    );
    assert_eq!(p.late_count(), 0);
}

#[test]
fn resume_after_falling_behind_brings_no_burst() {
    let (mut p, clock, controls) = player(4, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(35)); // behind by items 1, 2, 3
    controls.pause();
    assert_eq!(p.poll(), Poll::Paused);
    controls.resume();
    // Anchored at the next item, not at the head 35 ms on: item 1 now, then its spacing.
    let one = ready(p.poll());
    assert_eq!((one.item, one.lateness), (1, Duration::ZERO));
    assert_eq!(p.poll(), Poll::Wait(ms(45)));
}

#[test]
fn a_pause_and_resume_between_polls_is_no_change() {
    let (mut p, clock, controls) = player(3, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(3));
    controls.pause();
    controls.resume();
    assert_eq!(p.poll(), Poll::Wait(ms(10)));
}

#[test]
fn a_step_releases_exactly_one_item_while_paused() {
    let (mut p, clock, controls) = player(5, PlayerOptions::paced(1.0).unwrap());
    controls.pause();
    assert_eq!(p.poll(), Poll::Paused);
    clock.set(ms(100));
    controls.step();
    let a = ready(p.poll());
    assert_eq!((a.item, a.due, a.lateness), (0, ms(100), Duration::ZERO));
    assert_eq!(p.poll(), Poll::Paused);
    clock.set(ms(200));
    assert_eq!(p.poll(), Poll::Paused, "time passing releases nothing");
    controls.step();
    controls.step();
    assert_eq!(ready(p.poll()).item, 1);
    assert_eq!(ready(p.poll()).item, 2);
    assert_eq!(p.poll(), Poll::Paused);
    assert!(controls.is_paused());
    // Resumed from the item stepped to: the next 10 ms on.
    controls.resume();
    assert_eq!(p.poll(), Poll::Wait(ms(210)));
}

#[test]
fn a_step_while_playing_pauses() {
    let (mut p, clock, controls) = player(5, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(2));
    controls.step();
    // Item 1 at once (8 ms early by the schedule), then paused.
    let one = ready(p.poll());
    assert_eq!((one.item, one.due), (1, ms(2)));
    assert_eq!(p.poll(), Poll::Paused);
    assert!(controls.is_paused());
}

#[test]
fn unused_steps_are_dropped_on_resume() {
    let (mut p, clock, controls) = player(5, PlayerOptions::paced(1.0).unwrap());
    controls.step();
    controls.step();
    controls.resume();
    clock.set(ms(1));
    // Played from the start, not two items at once.
    assert_eq!(ready(p.poll()).item, 0);
    assert_eq!(p.poll(), Poll::Wait(ms(11)));
}

#[test]
fn seek_while_playing_reanchors_at_the_time_sought() {
    let (mut p, clock, controls) = player(100, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(5));
    // Between items 50 (1.5 s) and 51: item 51 is 5 ms after the time sought.
    controls.seek(1_505_000);
    assert_eq!(p.poll(), Poll::Wait(ms(10)));
    clock.set(ms(10));
    assert_eq!(ready(p.poll()).item, 51);
    assert_eq!(p.poll(), Poll::Wait(ms(20)));
    // Backwards, onto an item: due at once.
    controls.seek(1_000_000 + 20 * MS);
    let two = ready(p.poll());
    assert_eq!((two.item, two.lateness), (2, Duration::ZERO));
    assert_eq!(p.late_count(), 0);
}

#[test]
fn seek_while_paused_stays_paused() {
    let (mut p, clock, controls) = player(10, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    controls.pause();
    controls.seek(1_052_000);
    assert_eq!(p.poll(), Poll::Paused);
    assert_eq!(p.position_us(), Some(1_052_000));
    clock.set(ms(100));
    controls.step();
    assert_eq!(ready(p.poll()).item, 6);
    controls.seek(1_072_000);
    controls.resume();
    // Item 8 is 8 ms after the time sought.
    assert_eq!(p.poll(), Poll::Wait(ms(108)));
}

#[test]
fn seek_past_the_end_finishes_and_a_seek_back_plays_on() {
    let (mut p, clock, controls) = player(3, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    controls.seek(u64::MAX);
    assert_eq!(p.poll(), Poll::Finished);
    assert_eq!(p.poll(), Poll::Finished);
    clock.set(ms(50));
    controls.seek(1_010_000);
    let one = ready(p.poll());
    assert_eq!((one.item, one.due), (1, ms(50)));
    assert_eq!(p.poll(), Poll::Wait(ms(60)));
}

#[test]
fn seek_past_the_end_while_looping_starts_again() {
    let (mut p, _, controls) = player(3, PlayerOptions::paced(1.0).unwrap().looping(true));
    ready(p.poll());
    controls.seek(5_000_000);
    assert_eq!(ready(p.poll()).item, 0);
}

#[test]
fn a_loop_restarts_at_the_first_item_at_once() {
    let (mut p, clock, _) = player(3, PlayerOptions::paced(1.0).unwrap().looping(true));
    let laps: Vec<_> = p.by_ref().take(7).collect();
    let items: Vec<_> = laps.iter().map(|r| r.item).collect();
    assert_eq!(items, [0, 1, 2, 0, 1, 2, 0]);
    // Each lap starts when the last ended: no gap, no burst, nothing late.
    let dues: Vec<_> = laps.iter().map(|r| r.due).collect();
    assert_eq!(
        dues,
        [ms(0), ms(10), ms(20), ms(20), ms(30), ms(40), ms(40)]
    );
    assert_eq!(laps[3].t_us, laps[0].t_us);
    assert_eq!(p.late_count(), 0);
    assert_eq!(clock.now(), ms(40));
}

#[test]
fn looping_turned_off_ends_at_the_end() {
    let (mut p, _, controls) = player(2, PlayerOptions::default().looping(true));
    assert_eq!(ready(p.poll()).item, 0);
    assert_eq!(ready(p.poll()).item, 1);
    assert_eq!(ready(p.poll()).item, 0);
    controls.set_looping(false);
    assert!(!controls.is_looping());
    assert_eq!(ready(p.poll()).item, 1);
    assert_eq!(p.poll(), Poll::Finished);
}

#[test]
fn looping_an_empty_timeline_finishes() {
    let clock = VirtualClock::new();
    let empty = Recorded::<u8>::new(Vec::new());
    let mut p = Player::new(empty, clock, PlayerOptions::default().looping(true)).unwrap();
    assert_eq!(p.poll(), Poll::Finished);
    assert_eq!(p.next(), None);
}

#[test]
fn a_rate_change_mid_play_reanchors_at_the_head() {
    let (mut p, clock, controls) = player(5, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(4)); // head at 4 ms of the 10 ms to item 1
    controls.set_rate(2.0).unwrap();
    // The 6 ms of log time left take 3 ms.
    assert_eq!(p.poll(), Poll::Wait(ms(7)));
    clock.set(ms(7));
    assert_eq!(ready(p.poll()).item, 1);
    assert_eq!(p.poll(), Poll::Wait(ms(12)));
    // Slower: 10 ms of log time in 40 ms.
    clock.set(ms(8)); // head 2 ms past item 1
    controls.set_rate(0.25).unwrap();
    assert_eq!(p.poll(), Poll::Wait(ms(8 + 32)));
    assert_eq!(controls.pace(), Pace::Rate(0.25));
    assert_eq!(p.late_count(), 0);
}

#[test]
fn a_rate_change_while_paused_applies_on_resume() {
    let (mut p, clock, controls) = player(3, PlayerOptions::paced(1.0).unwrap());
    ready(p.poll());
    clock.set(ms(5));
    controls.pause();
    controls.set_rate(0.5).unwrap();
    assert_eq!(p.poll(), Poll::Paused);
    clock.set(ms(100));
    controls.resume();
    // 5 ms of log time left, at half speed.
    assert_eq!(p.poll(), Poll::Wait(ms(110)));
}

#[test]
fn switching_between_as_fast_as_possible_and_a_rate() {
    let (mut p, clock, controls) = player(6, PlayerOptions::default());
    assert_eq!(ready(p.poll()).item, 0);
    assert_eq!(ready(p.poll()).item, 1);
    controls.set_rate(1.0).unwrap();
    // From the last item released: item 2 is 10 ms on.
    assert_eq!(p.poll(), Poll::Wait(ms(10)));
    clock.set(ms(13));
    controls.set_pace(Pace::AsFastAsPossible).unwrap();
    assert_eq!(ready(p.poll()).item, 2);
    assert_eq!(ready(p.poll()).item, 3);
    assert_eq!(p.position_us(), Some(1_030_000));
}

#[test]
fn stop_finishes_for_good() {
    let (mut p, _, controls) = player(3, PlayerOptions::default());
    ready(p.poll());
    controls.stop();
    assert!(controls.is_stopped());
    assert_eq!(p.poll(), Poll::Finished);
    controls.seek(0);
    assert_eq!(p.next(), None);
}

#[test]
fn next_while_paused_with_no_other_handle_ends() {
    let clock = VirtualClock::new();
    let mut p = Player::new(every_10ms(3), clock, PlayerOptions::paced(1.0).unwrap()).unwrap();
    p.controls().pause(); // the handle is dropped: nothing can resume the player
    assert_eq!(p.next(), None);
}

#[test]
fn controls_from_another_thread_wake_a_paused_player() {
    let (mut p, _, controls) = player(3, PlayerOptions::paced(1.0).unwrap());
    controls.pause();
    assert_eq!(p.poll(), Poll::Paused);
    // Whichever comes first, the player blocking or the commands, the outcome is
    // the same: the commands are queued.
    let other = std::thread::spawn(move || {
        controls.seek(1_020_000);
        controls.resume();
    });
    let r = p.next().expect("resumed");
    assert_eq!(r.item, 2);
    other.join().unwrap();
    assert_eq!(p.next(), None);
}

#[test]
fn the_player_and_its_controls_go_to_other_threads() {
    fn send<S: Send>() {}
    fn sync<S: Sync>() {}
    send::<Player<Recorded<String>, SystemClock>>();
    send::<Player<Recorded<String>, VirtualClock>>();
    send::<Controls>();
    sync::<Controls>();
}

#[test]
fn a_borrowed_timeline_stays_with_the_caller() {
    let mut items = every_10ms(3);
    let clock = VirtualClock::new();
    let first: Vec<u64> = Player::new(&mut items, &clock, PlayerOptions::default())
        .unwrap()
        .take(2)
        .map(|r| r.item)
        .collect();
    assert_eq!(first, [0, 1]);
    assert_eq!(items.position(), 2);
}

#[test]
fn a_rate_of_zero_is_refused() {
    let e = PlayerOptions::paced(0.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "rate 0: log time × rate must be a positive, finite number"
    );
    // A pace made by hand is checked by the player.
    let options = PlayerOptions {
        pace: Pace::Rate(-1.0),
        ..PlayerOptions::default()
    };
    assert_eq!(
        Player::new(every_10ms(1), VirtualClock::new(), options).err(),
        Some(InvalidRate(-1.0))
    );
}

#[test]
fn a_rate_of_nan_is_refused_by_the_controls() {
    let (p, _, controls) = player(1, PlayerOptions::default());
    let e = controls.set_rate(f64::NAN).unwrap_err();
    assert!(e.to_string().starts_with("rate NaN"), "{e}");
    assert_eq!(controls.set_pace(Pace::Rate(-1.0)), Err(InvalidRate(-1.0)));
    // The pace is unchanged.
    assert_eq!(controls.pace(), Pace::AsFastAsPossible);
    drop(p);
}
