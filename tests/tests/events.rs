//! PX4 events (`ULog::events`): every corpus log with embedded metadata decodes every
//! event with nothing left unformatted, and logs built for each rule (every argument
//! type, enums and bitfields, profiles, no metadata, bad metadata, short arguments)
//! give the text the events library's rules give.

use sha2::{Digest, Sha256};
use ulog_core::events::{EventFinding, EventOptions, Metadata, MetadataError};
use ulog_core::testing::LogBuilder;
use ulog_core::ULog;
use ulog_tests::{corpus_files, stem};

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its logs with event metadata"
)]
fn every_event_of_the_corpus_logs_with_metadata_is_decoded() {
    let mut logs = 0;
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        if !log.multi_info().iter().any(|m| m.name == "metadata_events") {
            continue;
        }
        let name = stem(&path);
        for profile in ["normal", "dev"] {
            let events = log.events(&EventOptions::default().profile(profile));
            assert!(events.findings.is_empty(), "{name}: {:?}", events.findings);
            assert!(!events.events.is_empty(), "{name}: no events");
            for e in events.iter() {
                let what = format!("{name}: event {} {:?}", e.id, e.name);
                assert!(e.name.is_some(), "{what}: not defined");
                let texts = std::iter::once(&e.text).chain(e.description.iter());
                for text in texts {
                    // No argument left as `{N…}`, no tag left.
                    let chars: Vec<char> = text.chars().collect();
                    let placeholder = chars
                        .windows(2)
                        .any(|w| w[0] == '{' && w[1].is_ascii_digit());
                    assert!(!placeholder, "{what}: `{text}`");
                    for tag in ["<profile", "</profile>", "<param>", "</a>"] {
                        assert!(!text.contains(tag), "{what}: `{text}`");
                    }
                }
            }
        }
        logs += 1;
    }
    assert!(logs >= 3, "{logs} corpus logs with event metadata");
}

/// Event definitions for the logs built here: component 1 (`px4`) with enums and a
/// bitfield, component 0 (`common`) whose enum `px4` events use by its full name.
const JSON: &str = r#"{
  "version": 2,
  "components": {
    "0": {
      "namespace": "common",
      "enums": {
        "side_t": {"type": "uint8_t", "entries": {
          "0": {"name": "left", "description": "Left"},
          "1": {"name": "right", "description": "Right"}}}
      },
      "event_groups": {}
    },
    "1": {
      "namespace": "px4",
      "enums": {
        "mode_t": {"type": "uint16_t", "entries": {
          "3": {"name": "hold", "description": "Hold"},
          "4": {"name": "mission", "description": "Mission"}}},
        "checks_t": {"type": "uint32_t", "is_bitfield": true, "separator": ", ", "entries": {
          "1": {"name": "gps", "description": "GPS"},
          "4": {"name": "baro", "description": "Barometer"}}}
      },
      "event_groups": {
        "default": {"events": {
          "1": {"name": "ints", "message": "u8 {1} i8 {2} u16 {3} i16 {4} u32 {5} i32 {6}",
                "arguments": [{"type": "uint8_t", "name": "a"}, {"type": "int8_t", "name": "b"},
                              {"type": "uint16_t", "name": "c"}, {"type": "int16_t", "name": "d"},
                              {"type": "uint32_t", "name": "e"}, {"type": "int32_t", "name": "f"}]},
          "2": {"name": "wide", "message": "u64 {1} i64 {2} f {3} f1 {3:.1} alt {3:.2m_v} v {3m/s}",
                "arguments": [{"type": "uint64_t", "name": "a"}, {"type": "int64_t", "name": "b"},
                              {"type": "float", "name": "c"}]},
          "3": {"name": "enums", "message": "mode {1}, checks {2}, side {3}, other {4}",
                "description": "Set <param>COM_MODE</param> to {1}.",
                "arguments": [{"type": "mode_t", "name": "m"}, {"type": "checks_t", "name": "c"},
                              {"type": "common::side_t", "name": "s"}, {"type": "mode_t", "name": "o"}]},
          "4": {"name": "profiles", "message": "<profile name=\"dev\">dev {1}</profile><profile name=\"!dev\">user {1}</profile> \\{1\\}",
                "arguments": [{"type": "uint8_t", "name": "a"}]},
          "5": {"name": "too_long", "message": "{1} {2} {3} {4}",
                "arguments": [{"type": "uint64_t", "name": "a"}, {"type": "uint64_t", "name": "b"},
                              {"type": "uint64_t", "name": "c"}, {"type": "uint64_t", "name": "d"}]}
        }},
        "health": {"events": {
          "6": {"name": "health_only", "message": "checked"}
        }}
      }
    }
  }
}"#;

const EVENT_FORMAT: &str = "event:uint64_t timestamp;uint32_t id;uint16_t event_sequence;\
                            uint8_t[25] arguments;uint8_t log_levels;";

/// A PX4 log with events (id, arguments, levels) and, if given, these metadata bytes
/// (split in two multi-information parts) with `hash` as their SHA-256.
fn log_with(events: &[(u32, Vec<u8>, u8)], metadata: Option<(&[u8], String)>) -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "PX4");
    if let Some((bytes, hash)) = metadata {
        b.info_str("metadata_events_sha256", &hash);
        let (a, c) = bytes.split_at(bytes.len() / 2);
        b.multi_info(false, &format!("uint8_t[{}] metadata_events", a.len()), a);
        b.multi_info(true, &format!("uint8_t[{}] metadata_events", c.len()), c);
    }
    b.format(EVENT_FORMAT);
    b.subscribe(0, 0, "event");
    for (i, (id, args, levels)) in events.iter().enumerate() {
        let mut p = (1_000_000 * (i as u64 + 1)).to_le_bytes().to_vec();
        p.extend_from_slice(&id.to_le_bytes());
        p.extend_from_slice(&(i as u16).to_le_bytes());
        let mut a = args.clone();
        a.resize(25, 0);
        p.extend_from_slice(&a);
        p.push(*levels);
        b.data(0, &p);
    }
    b.into_bytes()
}

fn xz(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    lzma_rs::xz_compress(&mut &bytes[..], &mut out).unwrap();
    out
}

fn sha(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The id of event `sub` of component 1.
fn px4(sub: u32) -> u32 {
    (1 << 24) | sub
}

fn args(parts: &[&[u8]]) -> Vec<u8> {
    parts.concat()
}

fn sample_events() -> Vec<(u32, Vec<u8>, u8)> {
    vec![
        (
            px4(1),
            args(&[
                &[200],
                &(-5i8).to_le_bytes(),
                &60_000u16.to_le_bytes(),
                &(-30_000i16).to_le_bytes(),
                &4_000_000_000u32.to_le_bytes(),
                &(-2_000_000_000i32).to_le_bytes(),
            ]),
            0x66,
        ),
        (
            px4(2),
            args(&[
                &u64::MAX.to_le_bytes(),
                &i64::MIN.to_le_bytes(),
                &0.1f32.to_le_bytes(),
            ]),
            0x46,
        ),
        (
            px4(3),
            args(&[
                &4u16.to_le_bytes(),
                &5u32.to_le_bytes(),
                &[1],
                &9u16.to_le_bytes(),
            ]),
            0x36,
        ),
        (px4(4), vec![7], 0x66),
        (px4(5), vec![1; 25], 0x66),
        (px4(6), vec![], 0x66),
        (px4(99), vec![], 0x66),
    ]
}

#[test]
fn events_are_filled_in_by_the_events_library_rules() {
    let compressed = xz(JSON.as_bytes());
    let bytes = log_with(&sample_events(), Some((&compressed, sha(&compressed))));
    let log = ULog::parse(&bytes).unwrap();
    let events = log.events(&EventOptions::default());
    let texts: Vec<&str> = events.iter().map(|e| e.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "u8 200 i8 -5 u16 60000 i16 -30000 u32 4000000000 i32 -2000000000",
            "u64 18446744073709551615 i64 -9223372036854775808 f 0.10000000149011612 \
             f1 0.1 alt 0.10 m v 0.10000000149011612 m/s",
            "mode Mission, checks GPS, Barometer, side Right, other (unknown: 9)",
            "user 7 {1}",
            "[too_long: its arguments hold 25 bytes, its definition needs more (8 at byte 24)]",
            "checked",
            "[Unknown event with ID 16777315]",
        ]
    );
    let e = &events.events[2];
    assert_eq!(e.description.as_deref(), Some("Set COM_MODE to Mission."));
    assert_eq!(
        (e.name.as_deref(), e.group.as_deref()),
        (Some("enums"), Some("default"))
    );
    assert_eq!((e.level, e.external_level, e.level_name()), (3, 6, "ERROR"));
    assert_eq!(e.timestamp, 3_000_000);
    assert_eq!(e.sequence, 2);
    assert_eq!(events.events[5].group.as_deref(), Some("health"));
    assert_eq!(
        events.findings,
        [
            EventFinding::BadArguments {
                name: "too_long".into(),
                timestamp: 5_000_000,
                what: "its arguments hold 25 bytes, its definition needs more (8 at byte 24)"
                    .into()
            },
            EventFinding::UnknownId {
                id: px4(99),
                count: 1
            }
        ]
    );
    // The developer profile.
    let dev = log.events(&EventOptions::default().profile("dev"));
    assert_eq!(dev.events[3].text, "dev 7 {1}");

    // Metadata given as a file (plain JSON here) is used the same way.
    let bare = log_with(&sample_events(), None);
    let log = ULog::parse(&bare).unwrap();
    let given = Metadata::from_bytes(JSON.as_bytes()).unwrap();
    let events2 = log.events(&EventOptions::default().metadata(given));
    let texts2: Vec<&str> = events2.iter().map(|e| e.text.as_str()).collect();
    assert_eq!(texts, texts2);
}

#[test]
fn events_without_usable_metadata_keep_their_id_and_arguments() {
    let events = sample_events();
    let expect_raw = |log: &ULog<'_>, finding: EventFinding| {
        let out = log.events(&EventOptions::default());
        assert_eq!(out.findings, [finding]);
        assert_eq!(out.events.len(), events.len());
        assert_eq!(
            out.events[3].text,
            "[Unknown event with ID 16777220, arguments: 07]"
        );
        assert_eq!(
            out.events[5].text,
            "[Unknown event with ID 16777222, arguments: none]"
        );
        assert!(out.events.iter().all(|e| e.name.is_none()));
    };

    let none = log_with(&events, None);
    expect_raw(&ULog::parse(&none).unwrap(), EventFinding::NoMetadata);

    let compressed = xz(JSON.as_bytes());
    let wrong_hash = log_with(&events, Some((&compressed, sha(b"something else"))));
    let log = ULog::parse(&wrong_hash).unwrap();
    let out = log.events(&EventOptions::default());
    assert!(
        matches!(
            &out.findings[..],
            [EventFinding::BadMetadata(
                MetadataError::HashMismatch { .. }
            )]
        ),
        "{:?}",
        out.findings
    );

    // Cut short: the xz stream ends inside its block.
    let corrupt = compressed[..compressed.len() / 2].to_vec();
    let bad_xz = log_with(&events, Some((&corrupt, sha(&corrupt))));
    let log = ULog::parse(&bad_xz).unwrap();
    let out = log.events(&EventOptions::default());
    assert!(
        matches!(
            &out.findings[..],
            [EventFinding::BadMetadata(MetadataError::Xz(_))]
        ),
        "{:?}",
        out.findings
    );
    assert_eq!(out.events.len(), events.len());

    let not_json = xz(b"{\"version\": 2, \"components\": ");
    let bad_json = log_with(&events, Some((&not_json, sha(&not_json))));
    let log = ULog::parse(&bad_json).unwrap();
    let out = log.events(&EventOptions::default());
    assert!(
        matches!(
            &out.findings[..],
            [EventFinding::BadMetadata(MetadataError::Json(_))]
        ),
        "{:?}",
        out.findings
    );
    let text = out.findings[0].to_string();
    assert!(text.contains("not JSON"), "{text}");

    let not_events = xz(b"{\"version\": 0}");
    let bad_shape = log_with(&events, Some((&not_events, sha(&not_events))));
    let log = ULog::parse(&bad_shape).unwrap();
    let out = log.events(&EventOptions::default());
    assert!(
        matches!(
            &out.findings[..],
            [EventFinding::BadMetadata(MetadataError::Shape(_))]
        ),
        "{:?}",
        out.findings
    );
}

#[test]
fn a_bad_definition_is_passed_over_and_the_others_still_decode() {
    let json = r#"{"version": 2, "components": {
        "x": {"namespace": "bad"},
        "1": {"namespace": "px4", "enums": {
            "e_t": {"type": "int8_t", "is_bitfield": true, "entries": {
                "1": {"description": "one"}, "two": {"description": "?"}}}},
          "event_groups": {"default": {"events": {
            "1": {"name": "no_message"},
            "2": {"name": "fine", "message": "bits {1}", "arguments": [{"type": "e_t"}]}}}}}}}"#;
    let metadata = Metadata::from_json(json.as_bytes()).unwrap();
    assert_eq!(metadata.len(), 1);
    let bytes = log_with(&[(px4(1), vec![], 0x66), (px4(2), vec![0xFF], 0x66)], None);
    let log = ULog::parse(&bytes).unwrap();
    let events = log.events(&EventOptions::default().metadata(metadata));
    let texts: Vec<&str> = events.iter().map(|e| e.text.as_str()).collect();
    // -1 as an int8_t bitfield: bit 0 is `one`, the others unknown, by the signed value.
    assert_eq!(texts[0], "[Unknown event with ID 16777217]");
    assert!(
        texts[1].starts_with("bits one|(unknown: -1)|(unknown: -1)"),
        "{}",
        texts[1]
    );
}
