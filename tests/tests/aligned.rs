//! `#[derive(Aligned)]`: a struct of bound topics read at the steps of an alignment,
//! checked against the log once with every field that does not fit named, and
//! repositioned by time.

use ulog_core::align::{AlignOptions, Aligned, Grid, Method};
use ulog_core::testing::{sample_log, LogBuilder};
use ulog_core::typed::TypedErrorKind;
use ulog_core::{ULog, ULogMessage};

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct VehicleAttitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    xy_valid: bool,
}

#[derive(ULogMessage, Debug, Clone, PartialEq)]
struct BatteryStatus {
    timestamp: u64,
    voltage_v: f32,
    cell_count: u8,
}

/// What each step sees: the attitude's own row, the position before it, the second
/// battery interpolated.
#[derive(Aligned, Debug, Clone, PartialEq)]
struct Now {
    attitude: Option<VehicleAttitude>,
    #[ulog(method = "nearest")]
    position: Option<VehicleLocalPosition>,
    #[ulog(instance = 1, method = "linear")]
    battery: Option<BatteryStatus>,
}

/// The rows of binding `T` (instance `multi_id`) with their timestamps, in file order.
fn rows<T: ULogMessage>(log: &ULog<'_>, multi_id: u8, time: impl Fn(&T) -> u64) -> Vec<(u64, T)> {
    log.read::<T>(multi_id)
        .unwrap()
        .iter()
        .map(|r| {
            let r = r.unwrap();
            (time(&r), r)
        })
        .collect()
}

/// The last row at or before `t` (the last written among equal times), by a scan of
/// every row: the rule, computed the slow way.
fn previous<T: Clone>(rows: &[(u64, T)], t: u64) -> Option<T> {
    rows.iter()
        .rev()
        .find(|(rt, _)| *rt <= t)
        .map(|(_, r)| r.clone())
}

#[test]
fn each_field_is_its_topic_at_the_step_by_its_method() {
    let bytes = sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let steps = log
        .align(
            &Grid::topic("vehicle_attitude", 0),
            &AlignOptions::default(),
        )
        .unwrap();
    let attitude = rows::<VehicleAttitude>(&log, 0, |r| r.timestamp);
    let position = rows::<VehicleLocalPosition>(&log, 0, |r| r.timestamp);
    let battery = rows::<BatteryStatus>(&log, 1, |r| r.timestamp);
    let read: Vec<(u64, Now)> = steps.read::<Now>().unwrap().collect();
    assert_eq!(read.len(), attitude.len());
    let mut interpolated = 0;
    for (t, now) in &read {
        assert_eq!(now.attitude, previous(&attitude, *t), "attitude at {t}");
        // Nearest: the closer of the rows around t, the earlier on a tie.
        let before = position.iter().rev().find(|(rt, _)| rt <= t);
        let after = position.iter().find(|(rt, _)| rt > t);
        let nearest = match (before, after) {
            (Some(b), Some(a)) if a.0 - t < t - b.0 => Some(a),
            (Some(b), _) => Some(b),
            (None, a) => a,
        };
        assert_eq!(
            now.position,
            nearest.map(|r| r.1.clone()),
            "position at {t}"
        );
        // Linear: the voltage between the rows around t; the cell count (an integer)
        // the earlier row's; none after the last row.
        let before = battery.iter().rev().find(|(rt, _)| rt <= t);
        let after = battery.iter().find(|(rt, _)| rt > t);
        match (before, after, &now.battery) {
            (Some(b), _, Some(got)) if b.0 == *t => assert_eq!(got, &b.1),
            (Some(b), Some(a), Some(got)) => {
                let w = (t - b.0) as f64 / (a.0 - b.0) as f64;
                let v = b.1.voltage_v as f64 + w * (a.1.voltage_v as f64 - b.1.voltage_v as f64);
                assert!((got.voltage_v as f64 - v).abs() < 1e-5, "battery at {t}");
                assert_eq!(got.cell_count, b.1.cell_count);
                interpolated += 1;
            }
            (b, a, got) => assert!(
                got.is_none() && (b.is_none() || a.is_none()),
                "battery at {t}: {got:?}"
            ),
        }
    }
    assert!(
        interpolated > 100,
        "{interpolated} steps between battery rows"
    );
    // The struct equals its fields read one by one.
    let one = steps.topic::<BatteryStatus>(1, Method::Linear).unwrap();
    assert!(one.zip(&read).all(|(b, (_, now))| b == now.battery));
}

#[test]
fn previous_equals_the_slow_rule_on_every_corpus_log() {
    #[derive(ULogMessage, Debug, Clone, PartialEq)]
    #[ulog(name = "sensor_combined")]
    struct Imu {
        timestamp: u64,
        gyro_rad: [f32; 3],
    }
    #[derive(ULogMessage, Debug, Clone, PartialEq)]
    #[ulog(name = "vehicle_attitude")]
    struct Attitude {
        timestamp: u64,
        q: [f32; 4],
    }
    #[derive(Aligned)]
    struct Step {
        imu: Option<Imu>,
        attitude: Option<Attitude>,
    }
    let mut checked = 0;
    for path in ulog_tests::corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ULog::parse(&bytes) else {
            continue;
        };
        let Ok(steps) = log.align(&Grid::topic("sensor_combined", 0), &AlignOptions::default())
        else {
            continue;
        };
        let Ok(read) = steps.read::<Step>() else {
            continue;
        };
        let attitude = rows::<Attitude>(&log, 0, |r| r.timestamp);
        let mut attitude_sorted = attitude.clone();
        attitude_sorted.sort_by_key(|r| r.0);
        for (t, step) in read.step_by(7) {
            assert_eq!(step.imu.map(|i| i.timestamp), Some(t));
            assert_eq!(
                step.attitude,
                previous(&attitude_sorted, t),
                "{}: attitude at {t}",
                path.display()
            );
        }
        checked += 1;
    }
    // The repository's own corpus has none with both topics; the full one has many.
    if cfg!(full_corpus) {
        assert!(checked >= 5, "{checked} logs with both topics");
    }
}

#[test]
fn every_field_that_does_not_fit_is_named_at_once() {
    #[derive(ULogMessage, Debug)]
    #[ulog(name = "battery_status")]
    struct WrongBattery {
        timestamp: u64,
        voltage_v: u16,
    }
    #[derive(ULogMessage, Debug)]
    struct AirspeedValidated {
        timestamp: u64,
    }
    // Never read: its binding is refused.
    #[allow(dead_code)]
    #[derive(Aligned)]
    struct Broken {
        attitude: Option<VehicleAttitude>,
        battery: Option<WrongBattery>,
        airspeed: Option<AirspeedValidated>,
        #[ulog(instance = 3)]
        position: Option<VehicleLocalPosition>,
    }
    let bytes = sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let steps = log
        .align(&Grid::Rate(10.0), &AlignOptions::default())
        .unwrap();
    let e = steps.read::<Broken>().unwrap_err();
    let named: Vec<(&str, u8)> = e
        .fields()
        .iter()
        .map(|(f, _)| (f.field, f.multi_id))
        .collect();
    assert_eq!(named, [("battery", 0), ("airspeed", 0), ("position", 3)]);
    assert!(
        matches!(e.fields()[0].1.kind(), TypedErrorKind::Mismatch(_)),
        "{e}"
    );
    let text = e.to_string();
    assert!(
        text.starts_with("3 fields of the aligned struct do not fit this log:"),
        "{text}"
    );
    for needle in [
        "`battery` (battery_status instance 0)",
        "voltage_v",
        "airspeed_validated",
        "`position` (vehicle_local_position instance 3)",
    ] {
        assert!(text.contains(needle), "{needle} in {text}");
    }
    assert!(std::error::Error::source(&e).is_some());
    assert_eq!(Broken::FIELDS.len(), 4);
    assert_eq!(Broken::FIELDS[3].method, Method::Previous);
}

#[test]
fn seek_starts_at_a_time_forwards_and_backwards() {
    let bytes = sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let steps = log
        .align(&Grid::Rate(33.0), &AlignOptions::default())
        .unwrap();
    let all: Vec<(u64, Now)> = steps.read::<Now>().unwrap().collect();
    let mut it = steps.read::<Now>().unwrap();
    for (k, t) in [
        (0usize, 6_000_000u64),
        (1, 2_000_000),
        (2, 10_999_999),
        (3, 0),
        (4, u64::MAX),
    ] {
        it.seek(t);
        let from = all.partition_point(|(s, _)| *s < t);
        assert_eq!(it.remaining(), all.len() - from, "seek {k}");
        // A few steps from there equal the steps of the whole run.
        let got: Vec<(u64, Now)> = it.by_ref().take(40).collect();
        let want: Vec<(u64, Now)> = all[from..].iter().take(40).cloned().collect();
        assert_eq!(got, want, "seek {k} to {t}");
    }
}

#[test]
fn a_step_before_a_topics_first_row_has_none() {
    #[derive(ULogMessage, Debug, Clone, PartialEq)]
    struct Late {
        timestamp: u64,
        v: u32,
    }
    #[derive(ULogMessage, Debug, Clone, PartialEq)]
    struct Early {
        timestamp: u64,
        v: u32,
    }
    #[derive(Aligned, Debug, PartialEq)]
    struct Both {
        early: Option<Early>,
        #[ulog(method = "linear")]
        late: Option<Late>,
    }
    let mut b = LogBuilder::new(1, 0);
    b.format("early:uint64_t timestamp;uint32_t v;");
    b.format("late:uint64_t timestamp;uint32_t v;");
    b.subscribe(0, 0, "early");
    b.subscribe(0, 1, "late");
    for i in 0..10u64 {
        let t = 1_000 + i * 100;
        b.data(
            0,
            &[t.to_le_bytes().as_slice(), &(i as u32).to_le_bytes()].concat(),
        );
        if i >= 5 {
            b.data(
                1,
                &[(t + 50).to_le_bytes().as_slice(), &(i as u32).to_le_bytes()].concat(),
            );
        }
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let steps = log
        .align(&Grid::topic("early", 0), &AlignOptions::default())
        .unwrap();
    let late: Vec<Option<u32>> = steps
        .read::<Both>()
        .unwrap()
        .map(|(_, s)| s.late.map(|l| l.v))
        .collect();
    // Before `late`'s first row (1,550): none; integers are never interpolated.
    assert_eq!(
        late,
        [
            None,
            None,
            None,
            None,
            None,
            None,
            Some(5),
            Some(6),
            Some(7),
            Some(8)
        ]
    );
}

#[test]
fn a_player_replays_the_steps_on_the_logs_clock_and_seeks_in_them() {
    use std::time::Duration;
    use ulog_core::replay::{Player, PlayerOptions, Poll, VirtualClock};

    let bytes = sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let steps = log
        .align(
            &Grid::topic("vehicle_attitude", 0),
            &AlignOptions::default(),
        )
        .unwrap();
    let times = steps.times().to_vec();
    let clock = VirtualClock::new();
    let mut player = Player::new(
        steps.read::<Now>().unwrap(),
        clock.clone(),
        PlayerOptions::paced(1.0).unwrap(),
    )
    .unwrap();
    let controls = player.controls();
    // Real time: each step is due its log time after the first.
    for (k, &t) in times.iter().take(5).enumerate() {
        loop {
            match player.poll() {
                Poll::Ready(r) => {
                    assert_eq!(r.t_us, t);
                    assert_eq!(r.due, Duration::from_micros(t - times[0]), "step {k}");
                    assert_eq!(r.item.attitude.unwrap().timestamp, t);
                    break;
                }
                Poll::Wait(until) => clock.set(until),
                other => panic!("step {k}: {other:?}"),
            }
        }
    }
    // A seek to 8 s after the start: the next step is the first at or after it.
    let to = log.span().at(8.0);
    controls.seek(to);
    let next = player.next().unwrap();
    assert_eq!(next.t_us, times[times.partition_point(|&t| t < to)]);
    assert!(next.item.battery.is_some());
    assert_eq!(player.late_count(), 0);
}
