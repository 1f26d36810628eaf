//! Arbitrary and mutated bytes: the reader never panics, and the incremental reader
//! agrees with the whole-file reader whatever the chunking.

use proptest::prelude::*;
use ulog_core::read::{FindingKind, MessageAt, Messages};
use ulog_core::stream::{Progress, PushReader};
use ulog_core::{Finding, ReadError, ULog};

/// Messages (offset and type) and findings of one read.
type Framed = (Vec<(u64, u8)>, Vec<Finding>);

fn whole(bytes: &[u8]) -> Result<(Vec<MessageAt<'_>>, Vec<Finding>), ReadError> {
    let mut it = Messages::new(bytes);
    let mut out = Vec::new();
    for m in it.by_ref() {
        out.push(m?);
    }
    Ok((out, it.findings().to_vec()))
}

fn incremental(bytes: &[u8], chunks: &[usize]) -> Result<Framed, ReadError> {
    let mut inc = PushReader::new();
    let mut out = Vec::new();
    let mut rest = bytes;
    let mut i = 0;
    while !rest.is_empty() {
        let n = chunks[i % chunks.len()].clamp(1, rest.len());
        inc.push(&rest[..n]);
        rest = &rest[n..];
        i += 1;
        while inc.advance()? == Progress::Ready {
            let m = inc.current().unwrap();
            out.push((m.offset, m.message.msg_type()));
        }
    }
    inc.finish();
    while inc.advance()? == Progress::Ready {
        let m = inc.current().unwrap();
        out.push((m.offset, m.message.msg_type()));
    }
    Ok((out, inc.findings().to_vec()))
}

fn check(bytes: &[u8], chunks: &[usize]) {
    let w = whole(bytes);
    let i = incremental(bytes, chunks);
    match (w, i) {
        (Ok((wm, wf)), Ok((im, imf))) => {
            let wm: Vec<(u64, u8)> = wm
                .iter()
                .map(|m| (m.offset, m.message.msg_type()))
                .collect();
            assert_eq!(wm, im);
            assert_eq!(wf, imf);
            // The whole-log model builds too, and every indexed payload fits its format,
            // or is longer (kept, read as the format's first bytes) and reported.
            let log = ULog::parse(bytes).unwrap();
            for t in log.topics() {
                if let Ok(l) = t.layout() {
                    for (p, o) in t.payloads().zip(t.message_offsets()) {
                        if l.accepts_len(p.len()) {
                            continue;
                        }
                        assert!(p.len() > l.size(), "{} bytes at {o}", p.len());
                        assert!(
                            log.findings().iter().any(|f| matches!(
                                f.kind,
                                FindingKind::SizeMismatch { .. }
                            ) && f.offset <= o
                                && o < f.offset + f.len),
                            "a longer payload at {o} not reported: {:?}",
                            log.findings()
                        );
                    }
                }
            }
        }
        (Err(a), Err(b)) => assert_eq!(a, b),
        (a, b) => panic!("whole {:?} vs incremental {:?}", a.err(), b.err()),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_after_a_header(tail in proptest::collection::vec(any::<u8>(), 0..4096), chunks in proptest::collection::vec(1usize..300, 1..5)) {
        let mut bytes = ulog_core::format::definitions::MAGIC.to_vec();
        bytes.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0, 0, 0]);
        bytes.extend_from_slice(&tail);
        check(&bytes, &chunks);
    }

    #[test]
    fn mutated_sample_log(flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..20),
                          zero_run in proptest::option::of((any::<prop::sample::Index>(), 1usize..200)),
                          cut in any::<prop::sample::Index>(),
                          chunks in proptest::collection::vec(1usize..5000, 1..4)) {
        let mut bytes = ulog_core::testing::sample_log();
        for (at, v) in flips {
            let i = at.index(bytes.len());
            bytes[i] = v;
        }
        if let Some((at, n)) = zero_run {
            let i = at.index(bytes.len());
            let end = (i + n).min(bytes.len());
            bytes[i..end].fill(0);
        }
        let cut = 16 + cut.index(bytes.len() - 16);
        bytes.truncate(cut);
        check(&bytes, &chunks);
    }
}

#[test]
fn many_huge_formats_lay_out_without_expanding_leaves() {
    // 20,000 formats of 65,535 one-byte leaves each, all subscribed: a few hundred KB
    // of file that would describe over a billion leaves if they were built eagerly.
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    for i in 0..20_000u16 {
        b.format(&format!("f{i}:uint8_t[65535] x;"));
    }
    for i in 0..20_000u16 {
        b.subscribe(0, i, &format!("f{i}"));
    }
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(log.subscriptions().len(), 20_000);
    assert!(!log.has_damage());
    // Each topic is still fully usable.
    let t = log.topic("f19999", 0).unwrap();
    assert_eq!(t.field("x[65534]").unwrap().offset(), 65534);
}
