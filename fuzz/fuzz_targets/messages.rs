//! Real logs damaged at the message level: one to four messages of the data section
//! get a new size, type, log level, key byte or payload byte (overwritten in place,
//! so every other message keeps its offset). The invariant is pyulog's at its best:
//! no valid message is lost outside the damaged ones, where a damaged message spans
//! the bytes its new size claims as well as its own (and a data message whose
//! subscription is among them has lost what it is read by; a message alone between
//! two damaged ones is skipped with them, as the reader documents). Messages that define (formats,
//! subscriptions, their removal, flag bits) are left alone: changing one changes what
//! the messages after it mean, not only whether they are read.
#![no_main]

use std::collections::HashSet;
use std::sync::OnceLock;

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use ulog_core::read::Messages;

const LOGS: [&[u8]; 3] = [
    include_bytes!("../../tests/corpus/files/esc_status_log.ulg"),
    include_bytes!("../../tests/corpus/files/sample_appended_multiple.ulg"),
    include_bytes!("../../tests/corpus/files/trig_stats.ulg"),
];

/// Types whose messages may be damaged: those that define nothing.
const DAMAGEABLE: &[u8] = b"DLCIMPQOS";

/// A log's messages: (offset, length with header, type), the index of the first
/// message of the data section (the first subscription), and for each data message
/// the index of the subscription it belongs to.
struct Base {
    bytes: &'static [u8],
    messages: Vec<(usize, usize, u8)>,
    data_start: usize,
    subscription_of: Vec<Option<usize>>,
}

fn bases() -> &'static [Base] {
    static BASES: OnceLock<Vec<Base>> = OnceLock::new();
    BASES.get_or_init(|| {
        LOGS.iter()
            .map(|&bytes| {
                let mut it = Messages::new(bytes);
                let messages: Vec<(usize, usize, u8)> = it
                    .by_ref()
                    .map(|m| {
                        let m = m.expect("a real log frames");
                        let o = m.offset as usize;
                        let len = 3 + usize::from(u16::from_le_bytes([bytes[o], bytes[o + 1]]));
                        (o, len, bytes[o + 2])
                    })
                    .collect();
                assert!(
                    it.findings().iter().all(|f| !f.is_damage()),
                    "the base logs are undamaged"
                );
                let data_start = messages
                    .iter()
                    .position(|m| m.2 == b'A')
                    .expect("a subscription");
                let mut subscribed = std::collections::HashMap::new();
                let subscription_of = messages
                    .iter()
                    .enumerate()
                    .map(|(i, &(o, _, t))| {
                        let id = u16::from_le_bytes([bytes[o + 4], bytes[o + 5]]);
                        match t {
                            b'A' => {
                                subscribed.insert(id, i);
                                None
                            }
                            b'D' => {
                                let id = u16::from_le_bytes([bytes[o + 3], bytes[o + 4]]);
                                subscribed.get(&id).copied()
                            }
                            _ => None,
                        }
                    })
                    .collect();
                Base {
                    bytes,
                    messages,
                    data_start,
                    subscription_of,
                }
            })
            .collect()
    })
}

/// Damages `bytes` (a copy of `base`) at one message chosen by `u`; returns the
/// message's index and the bytes it spans now: its own and those its size claims.
fn damage(
    u: &mut Unstructured<'_>,
    base: &Base,
    bytes: &mut [u8],
) -> Result<Option<(usize, (usize, usize))>> {
    let candidates: Vec<usize> = (base.data_start..base.messages.len())
        .filter(|&i| DAMAGEABLE.contains(&base.messages[i].2))
        .collect();
    if candidates.is_empty() {
        return Ok(None);
    }
    let i = *u.choose(&candidates)?;
    let (o, len, t) = base.messages[i];
    let size = u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    match u.int_in_range(0..=5u8)? {
        // A size off by a little (a bit flip in the low bits, a miscounted field).
        0 => {
            let delta: i16 = u.int_in_range(-16..=16)?;
            bytes[o..o + 2].copy_from_slice(&size.wrapping_add_signed(delta).to_le_bytes());
        }
        // Any size.
        1 => {
            let s: u16 = u.arbitrary()?;
            bytes[o..o + 2].copy_from_slice(&s.to_le_bytes());
        }
        // Another type: one that defines nothing, or one that is no type.
        2 => {
            bytes[o + 2] = if u.arbitrary()? {
                *u.choose(DAMAGEABLE)?
            } else {
                u.arbitrary()?
            };
        }
        // The log level of a logged string, or the first payload byte of another.
        3 => bytes[o + 3] = u.arbitrary()?,
        // A byte of the key of an information or parameter message (or of the
        // first bytes of another message).
        4 => {
            let key_start = match t {
                b'M' | b'Q' => 5,
                _ => 4,
            };
            let end = (o + len).min(o + key_start + 64);
            if o + key_start < end {
                let k = u.int_in_range(o + key_start..=end - 1)?;
                bytes[k] = u.arbitrary()?;
            }
        }
        // Any byte of the payload.
        _ => {
            let k = u.int_in_range(o + 3..=o + len - 1)?;
            bytes[k] = u.arbitrary()?;
        }
    }
    let claimed = 3 + usize::from(u16::from_le_bytes([bytes[o], bytes[o + 1]]));
    Ok(Some((i, (o, o + len.max(claimed)))))
}

fn run(u: &mut Unstructured<'_>) -> Result<()> {
    let base = u.choose(bases())?;
    let mut bytes = base.bytes.to_vec();
    let mut damaged = HashSet::new();
    let mut spans = Vec::new();
    for _ in 0..u.int_in_range(1..=4u8)? {
        if let Some((i, span)) = damage(u, base, &mut bytes)? {
            damaged.insert(i);
            spans.push(span);
        }
    }
    // To look at a failure: the damaged log, written where this names.
    if let Some(path) = std::env::var_os("ULOG_FUZZ_DUMP") {
        std::fs::write(path, &bytes).expect("write the damaged log");
    }
    let framed: HashSet<(usize, usize)> = Messages::new(&bytes)
        .filter_map(|m| m.ok())
        .map(|m| {
            let o = m.offset as usize;
            (o, 3 + usize::from(u16::from_le_bytes([bytes[o], bytes[o + 1]])))
        })
        .collect();
    let lost = |i: usize| {
        let (o, len, _) = base.messages[i];
        damaged.contains(&i) || spans.iter().any(|&(s, e)| o < e && s < o + len)
    };
    // Damaged as the reader sees it: lost, and not framed as it was.
    let broken = |i: usize| {
        let (o, len, _) = base.messages[i];
        lost(i) && !framed.contains(&(o, len))
    };
    for (i, &(o, len, t)) in base.messages.iter().enumerate() {
        // A data message whose subscription was lost has nothing to be read by.
        if lost(i) || base.subscription_of[i].is_some_and(lost) {
            continue;
        }
        // One message alone inside damage is as likely damaged itself: resynchronising
        // asks for two before more damage.
        if i > 0 && i + 1 < base.messages.len() && broken(i - 1) && broken(i + 1) {
            continue;
        }
        assert!(
            framed.contains(&(o, len)),
            "message {i} ({}, {len} bytes at {o}) lost; damaged: {:?}",
            t as char,
            spans
        );
    }
    // The whole-file reader takes the same bytes, and every value of it reads.
    let log = ulog_core::ULog::parse(&bytes).expect("the header is intact");
    for topic in log.topics() {
        if let Ok(fields) = topic.fields() {
            for p in topic.payloads() {
                for f in &fields {
                    let _ = f.read(p);
                }
            }
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
