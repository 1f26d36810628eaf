//! Borrowed views: a binding whose memory is its payload's image is borrowed from each
//! row without a copy, on logs that leave out the trailing padding as PX4 does; on
//! every corpus log, through view bindings generated from the log itself.

use ulog_core::testing::LogBuilder;
use ulog_core::typed::{le, ByteBool, PlanKind, TypedErrorKind};
use ulog_core::{ULog, ULogMessage};

/// `vehicle_attitude` as PX4 v1.14 defines it, without the trailing padding PX4 never
/// writes.
#[derive(ULogMessage, Debug)]
#[ulog(name = "vehicle_attitude", view)]
#[repr(C)]
struct Attitude {
    timestamp: le::U64,
    timestamp_sample: le::U64,
    q: [le::F32; 4],
    delta_q_reset: [le::F32; 4],
    quat_reset_counter: u8,
}

/// The same with the trailing padding declared.
#[derive(ULogMessage, Debug)]
#[ulog(name = "vehicle_attitude", view)]
#[repr(C)]
struct AttitudePadded {
    timestamp: le::U64,
    timestamp_sample: le::U64,
    q: [le::F32; 4],
    delta_q_reset: [le::F32; 4],
    quat_reset_counter: u8,
    _padding0: [u8; 7],
}

/// Only the first fields: a prefix of the payload.
#[derive(ULogMessage, Debug)]
#[ulog(name = "vehicle_attitude", view)]
#[repr(C)]
struct AttitudeHead {
    timestamp: le::U64,
    timestamp_sample: le::U64,
    q: [le::F32; 4],
}

/// A field out of the log's order.
#[derive(ULogMessage, Debug)]
#[ulog(name = "vehicle_attitude", view)]
#[repr(C)]
struct AttitudeMoved {
    timestamp: le::U64,
    q: [le::F32; 4],
}

const PX4_ATTITUDE: &str = "vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;float[4] delta_q_reset;uint8_t quat_reset_counter;uint8_t[7] _padding0;";

/// A log of 50 attitudes written as PX4 writes them: without the trailing padding, or,
/// with `padded`, with it.
fn attitude_log(padded: bool) -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.format(PX4_ATTITUDE);
    b.subscribe(0, 0, "vehicle_attitude");
    for i in 0..50u64 {
        let mut p = (1000 + i).to_le_bytes().to_vec();
        p.extend_from_slice(&(900 + i).to_le_bytes());
        for k in 0..8 {
            p.extend_from_slice(&(i as f32 + k as f32 / 10.0).to_le_bytes());
        }
        p.push(i as u8);
        if padded {
            p.extend_from_slice(&[0; 7]);
        }
        b.data(0, &p);
    }
    b.into_bytes()
}

#[test]
fn a_binding_without_the_trailing_padding_borrows_every_row() {
    for padded in [false, true] {
        let bytes = attitude_log(padded);
        let log = ULog::parse(&bytes).unwrap();
        let rows = log.read::<Attitude>(0).unwrap();
        assert_eq!(rows.plan().kind(), PlanKind::Exact);
        let views: Vec<&Attitude> = rows.views().unwrap().map(Result::unwrap).collect();
        assert_eq!(views.len(), 50);
        for (i, v) in views.iter().enumerate() {
            assert_eq!(v.timestamp.get(), 1000 + i as u64);
            assert_eq!(v.q[1].get(), i as f32 + 0.1);
            assert_eq!(v.quat_reset_counter, i as u8);
            // Borrowed in place: the view is the payload.
            let payload = rows.topic().payload(i).unwrap();
            assert!(std::ptr::eq(
                *v as *const Attitude as *const u8,
                payload.as_ptr()
            ));
        }
        // A prefix of the fields borrows too.
        let head = log.read::<AttitudeHead>(0).unwrap();
        assert_eq!(head.plan().kind(), PlanKind::Exact);
        assert_eq!(head.views().unwrap().filter(Result::is_ok).count(), 50);
    }
}

#[test]
fn rows_that_cannot_be_borrowed_are_refused_once_with_why() {
    // The trailing padding declared, the log without it (as PX4 writes it).
    let bytes = attitude_log(false);
    let log = ULog::parse(&bytes).unwrap();
    let rows = log.read::<AttitudePadded>(0).unwrap();
    assert_eq!(rows.plan().kind(), PlanKind::Exact);
    let Err(e) = rows.views() else {
        panic!("rows without the padding are borrowed as a binding with it")
    };
    let TypedErrorKind::NoView { binding, why } = e.kind() else {
        panic!("{e}")
    };
    assert_eq!(binding, "AttitudePadded");
    assert!(why.contains("50 of 50 rows"), "{why}");
    assert!(e.to_string().contains("leave the trailing padding"), "{e}");
    assert_eq!(e.topic(), Some(("vehicle_attitude", 0)));
    // Decoding (a copy) still reads it.
    assert_eq!(rows.iter().filter(Result::is_ok).count(), 50);
    // The same binding borrows a log that does write the padding.
    let padded = attitude_log(true);
    let log_padded = ULog::parse(&padded).unwrap();
    let rows = log_padded.read::<AttitudePadded>(0).unwrap();
    assert_eq!(rows.views().unwrap().filter(Result::is_ok).count(), 50);

    let moved = log.read::<AttitudeMoved>(0).unwrap();
    assert_eq!(moved.plan().kind(), PlanKind::Mapped);
    let Err(e) = moved.views() else {
        panic!("a mapped plan is borrowed")
    };
    assert!(matches!(e.kind(), TypedErrorKind::NoView { .. }), "{e}");
    assert!(
        e.to_string()
            .contains("field `q` is at byte 16 of the log's payload, 8 of the binding"),
        "{e}"
    );
    assert!(
        e.to_string().contains("`iter()` decodes them by copy"),
        "{e}"
    );
    assert_eq!(moved.iter().filter(Result::is_ok).count(), 50);
}

/// The view of `TypedRows::views`'s documentation: `vehicle_attitude` as PX4 logs it
/// from v1.13 on, up to `q`.
#[derive(ULogMessage, Debug)]
#[ulog(view)]
#[repr(C)]
struct VehicleAttitude {
    timestamp: le::U64,
    timestamp_sample: le::U64,
    q: [le::F32; 4],
}

/// On every corpus log, the documentation's view borrows every row where the log's
/// format begins as it does (PX4 v1.13 on); the older firmware has no
/// `timestamp_sample` (v1.9 and older: rates before `q`; v1.11: `q` after
/// `timestamp`), so the binding does not fit them at all. The borrowed values are the
/// reader's own by path.
#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its logs of PX4 v1.13 and later"
)]
fn the_documented_view_borrows_the_logs_of_its_firmware() {
    const PREFIX: &str =
        "vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;";
    let (mut borrowed, mut older) = (0, 0);
    for path in ulog_tests::corpus_files() {
        let file = ulog_core::LogFile::open(&path).unwrap();
        let Ok(log) = file.parse() else { continue };
        let Ok(instances) = log.read_instances::<VehicleAttitude>() else {
            continue;
        };
        for rows in instances {
            let rows = match rows {
                Ok(rows) => rows,
                Err(e) => {
                    assert!(
                        e.to_string().contains("field `timestamp_sample`: missing"),
                        "{e}"
                    );
                    older += 1;
                    continue;
                }
            };
            let format = rows
                .topic()
                .subscription()
                .layout()
                .unwrap()
                .format()
                .to_string();
            match rows.views() {
                Ok(views) => {
                    assert!(format.starts_with(PREFIX), "{}: {format}", path.display());
                    let q0 = rows.topic().field("q[0]").unwrap();
                    for (i, v) in views.enumerate() {
                        let v = v.unwrap();
                        let payload = rows.topic().payload(i).unwrap();
                        assert_eq!(
                            q0.read(payload),
                            Some(ulog_core::Value::F32(v.q[0].get())),
                            "{}",
                            path.display()
                        );
                        borrowed += 1;
                    }
                }
                Err(e) => panic!("{}: {e}", path.display()),
            };
        }
    }
    eprintln!("documented view: {borrowed} rows borrowed; {older} instances of older firmware");
    assert!(borrowed > 0 && older > 0);
}

/// A `bool` in a view, as its byte.
#[derive(ULogMessage, Debug)]
#[ulog(name = "flags", view)]
#[repr(C)]
struct Flags {
    timestamp: le::U64,
    armed: ByteBool,
    mode: u8,
}

#[test]
fn bools_are_borrowed_as_their_byte() {
    let mut b = LogBuilder::new(1, 0);
    b.format("flags:uint64_t timestamp;bool armed;uint8_t mode;uint8_t[6] _padding0;");
    b.subscribe(0, 0, "flags");
    b.data(0, &[&5u64.to_le_bytes()[..], &[2, 7]].concat());
    let log = ULog::parse(b.bytes()).unwrap();
    let rows = log.read::<Flags>(0).unwrap();
    let v = rows.views().unwrap().next().unwrap().unwrap();
    assert!(v.armed.get(), "any byte but 0 is true");
    assert_eq!(v.mode, 7);
    let mut seen = Vec::new();
    v.visit_fields(&mut |path, value| seen.push(format!("{path}={value}")));
    assert_eq!(seen, ["timestamp=5", "armed=true", "mode=7"]);
}
