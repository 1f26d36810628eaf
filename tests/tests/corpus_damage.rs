//! Real logs cut and fed in pieces: a truncated log keeps exactly a prefix of the full
//! decode, and the incremental reader takes the decisions of the whole-file reader.

use ulog_core::read::{FindingKind, MessageAt, Messages};
use ulog_core::stream::{Progress, PushReader};
use ulog_core::ULog;
use ulog_tests::{corpus_files, stem};

fn frame(bytes: &[u8]) -> (Vec<MessageAt<'_>>, Vec<ulog_core::Finding>) {
    let mut it = Messages::new(bytes);
    let msgs: Vec<_> = it.by_ref().map(|m| m.expect("frames")).collect();
    (msgs, it.findings().to_vec())
}

#[test]
fn a_real_log_cut_at_every_message_boundary_keeps_a_prefix() {
    let bytes = std::fs::read(ulog_tests::own_log("sample_appended_multiple.ulg")).unwrap();
    let (all, _) = frame(&bytes);
    let ends: Vec<usize> = all
        .iter()
        .map(|m| {
            let o = m.offset as usize;
            o + 3 + u16::from_le_bytes([bytes[o], bytes[o + 1]]) as usize
        })
        .collect();
    let mut checked = 0;
    for (i, &cut) in ends.iter().enumerate() {
        let (got, findings) = frame(&bytes[..cut]);
        // Every message that ends before the cut, and no other.
        let expect = ends.iter().take_while(|&&e| e <= cut).count();
        assert_eq!(got.len(), expect, "cut after message {i} at {cut}");
        assert_eq!(&got[..], &all[..expect], "cut at {cut}");
        assert!(
            findings
                .iter()
                .all(|f| !f.is_damage() || f.kind == FindingKind::PartialBeforeAppended),
            "cut at {cut}: {findings:?}"
        );
        // One byte later the cut is inside the next message: same prefix, reported.
        if cut + 1 < bytes.len() && i + 1 < ends.len() && ends[i + 1] > cut + 1 {
            let (got, findings) = frame(&bytes[..cut + 1]);
            assert_eq!(&got[..], &all[..expect], "cut at {}", cut + 1);
            let t = findings.iter().find(|f| f.kind == FindingKind::Truncated);
            assert_eq!(
                t.map(|f| (f.offset, f.len)),
                Some((cut as u64, 1)),
                "cut at {}",
                cut + 1
            );
        }
        checked += 1;
    }
    assert!(checked > 6000);
}

#[test]
fn incremental_reader_equals_whole_file_reader_on_every_corpus_log() {
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let (all, findings) = frame(&bytes);
        assert_eq!(all.len() as u64, log.message_count(), "{}", stem(&path));
        for chunk in [997usize, 65536] {
            let mut inc = PushReader::new();
            let mut i = 0;
            let mut max_buffered = 0;
            let mut check = |inc: &mut PushReader| {
                while inc.advance().unwrap() == Progress::Ready {
                    let m = inc.current().unwrap();
                    assert_eq!(m, all[i], "{}: message {i}, chunk {chunk}", stem(&path));
                    i += 1;
                }
            };
            for c in bytes.chunks(chunk) {
                inc.push(c);
                max_buffered = max_buffered.max(inc.buffered());
                check(&mut inc);
            }
            inc.finish();
            check(&mut inc);
            assert_eq!(i, all.len(), "{}", stem(&path));
            assert_eq!(inc.findings(), &findings[..], "{}", stem(&path));
            // Bounded memory: at most what framing may need to judge damage, plus a chunk.
            assert!(
                max_buffered <= 3 * 65538 + chunk,
                "{}: {max_buffered}",
                stem(&path)
            );
        }
    }
}
