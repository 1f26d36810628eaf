//! Deterministic sweeps over every corpus log (issue 7): truncation at every message
//! boundary, at every byte of the first 64 KiB and at thousands of random offsets; and
//! corruption of each kind at random places. The reader never panics or hangs, keeps
//! exactly a prefix of the full decode when cut, decodes every message outside a
//! damaged stretch, and reports the damage with its byte range.
//!
//! A cut is judged from a copy of the whole-file iterator at the last message before
//! it ([`Messages::cut`]), which is what a reader of the cut file has seen up to there
//! as long as no decision before the cut looked past it. Decisions look ahead only
//! around damage, appended offsets and the file's start, so cuts there are read
//! afresh; a sample of the other cuts is read afresh too, and must agree.

use ulog_core::read::{FindingKind, MessageAt, Messages};
use ulog_core::testing::Rng;
use ulog_core::Finding;
use ulog_tests::{corpus_files, stem};

type Framed<'a> = (Vec<MessageAt<'a>>, Vec<Finding>);

/// Every message and finding; a refused file (a cut inside the header) gives none.
fn frame(bytes: &[u8]) -> Framed<'_> {
    let mut it = Messages::new(bytes);
    let mut msgs = Vec::new();
    for m in it.by_ref() {
        match m {
            Ok(m) => msgs.push(m),
            Err(e) => {
                assert!(
                    bytes.len() < 16 && msgs.is_empty(),
                    "{e} after {} bytes",
                    bytes.len()
                );
                return (Vec::new(), Vec::new());
            }
        }
    }
    (msgs, it.findings().to_vec())
}

fn end_of(bytes: &[u8], m: &MessageAt<'_>) -> usize {
    let o = m.offset as usize;
    o + 3 + u16::from_le_bytes([bytes[o], bytes[o + 1]]) as usize
}

/// Byte ranges where the reader's decisions may depend on bytes after a cut: from each
/// finding (and appended offset) to the end of the fourth message after it, and the
/// file's start up to the end of its first message.
fn sensitive(
    bytes: &[u8],
    all: &[MessageAt<'_>],
    ends: &[usize],
    findings: &[Finding],
) -> Vec<(usize, usize)> {
    let mut points: Vec<usize> = findings.iter().map(|f| f.offset as usize).collect();
    for m in all {
        if let ulog_core::Message::FlagBits(fb) = &m.message {
            points.extend(
                fb.appended_offsets
                    .iter()
                    .filter(|&&o| o > 0)
                    .map(|&o| o as usize),
            );
        }
    }
    let mut ranges = vec![(0, ends.first().copied().unwrap_or(bytes.len()) + 1)];
    for p in points {
        let start = p.saturating_sub(1);
        let after = ends.partition_point(|&e| e <= p);
        let end = ends.get(after + 4).copied().unwrap_or(bytes.len()) + 1;
        ranges.push((start, end));
    }
    ranges
}

struct Sweep {
    cuts: usize,
    fresh: usize,
    verified: usize,
}

fn truncation_sweep(name: &str, bytes: &[u8], rng: &mut Rng) -> Sweep {
    let (all, findings) = frame(bytes);
    let ends: Vec<usize> = all.iter().map(|m| end_of(bytes, m)).collect();
    let ranges = sensitive(bytes, &all, &ends, &findings);
    let is_sensitive = |p: usize| ranges.iter().any(|&(a, b)| a <= p && p < b);

    let mut cuts: Vec<usize> = ends.clone();
    cuts.extend(0..bytes.len().min(64 * 1024));
    cuts.extend((0..2000).map(|_| rng.below(bytes.len() + 1)));
    cuts.sort_unstable();
    cuts.dedup();
    // Cuts read afresh as well, to check that a copy of the iterator agrees.
    let mut verify: Vec<usize> = (0..25).map(|_| cuts[rng.below(cuts.len())]).collect();
    verify.sort_unstable();

    let mut it = Messages::new(bytes);
    // A copy of `it` at the last boundary outside every sensitive range: its decisions
    // looked at no byte after it, so it reads any later cut as a fresh reader would.
    let mut anchor = (0usize, it.clone());
    let mut emitted = 0;
    let mut s = Sweep {
        cuts: 0,
        fresh: 0,
        verified: 0,
    };
    for &p in &cuts {
        while emitted < all.len() && ends[emitted] <= p {
            let m = it.next().expect("message").expect("frames");
            assert_eq!(m, all[emitted], "{name}: whole-file iteration");
            emitted += 1;
            if !is_sensitive(ends[emitted - 1]) {
                anchor = (emitted, it.clone());
            }
        }
        let (from, base) = if is_sensitive(p) {
            (anchor.0, &anchor.1)
        } else {
            (emitted, &it)
        };
        // A cut inside the header is refused, which `frame` handles.
        let from_copy = (p >= 16).then(|| base.cut(p)).flatten().map(|mut c| {
            let tail: Vec<_> = c.by_ref().map(|m| m.expect("frames")).collect();
            (tail, c.findings().to_vec())
        });
        let verify_here = verify.binary_search(&p).is_ok();
        // (messages decoded, new ones after the first `from` of the full decode, findings)
        let (count, tail, found): (usize, Vec<MessageAt<'_>>, Vec<Finding>) = match from_copy {
            Some((tail, found)) => {
                if verify_here {
                    let (fresh, fresh_found) = frame(&bytes[..p]);
                    assert!(
                        fresh.len() == from + tail.len()
                            && fresh[..from] == all[..from]
                            && fresh[from..] == tail[..]
                            && fresh_found == found,
                        "{name}: cut at {p}: a copy of the iterator and a fresh read differ"
                    );
                    s.verified += 1;
                }
                (from + tail.len(), tail, found)
            }
            None => {
                s.fresh += 1;
                let (fresh, found) = frame(&bytes[..p]);
                let tail = fresh[from.min(fresh.len())..].to_vec();
                assert_eq!(
                    &fresh[..from.min(fresh.len())],
                    &all[..from.min(fresh.len())],
                    "{name}: cut at {p}"
                );
                (fresh.len(), tail, found)
            }
        };
        let last_end = if emitted == 0 { 0 } else { ends[emitted - 1] };
        // What this cut adds to the findings of the full read before it.
        let found: Vec<Finding> = found
            .into_iter()
            .filter(|f| f.offset >= last_end as u64)
            .collect();

        // Exactly a prefix of the full decode.
        assert!(count <= all.len(), "{name}: cut at {p}");
        let start = count - tail.len();
        assert_eq!(
            &tail[..],
            &all[start..count],
            "{name}: cut at {p}: not a prefix"
        );
        let got_len = count;
        if !is_sensitive(p) {
            // Nothing before the cut is lost, and a cut inside a message is reported
            // with the bytes it dropped.
            assert_eq!(got_len, emitted, "{name}: cut at {p}: messages lost");
            // A cut tail of zero bytes reads as zero fill; the range is the same.
            let t: Vec<&Finding> = found
                .iter()
                .filter(|f| {
                    f.kind == FindingKind::Truncated
                        || (f.kind == FindingKind::Corrupt(ulog_core::read::Corruption::ZeroFill)
                            && bytes[last_end..p].iter().all(|&b| b == 0))
                })
                .collect();
            if p == last_end {
                assert!(t.is_empty(), "{name}: cut at boundary {p}: {t:?}");
            } else {
                assert_eq!(
                    t.iter().map(|f| (f.offset, f.len)).collect::<Vec<_>>(),
                    [(last_end as u64, (p - last_end) as u64)],
                    "{name}: cut at {p}"
                );
            }
        } else if p > 16 && !ends.contains(&p) {
            // Around damage: what the cut drops is still reported, up to the cut.
            assert!(
                found.iter().any(|f| f.offset + f.len == p as u64)
                    || got_len < emitted
                    || p >= bytes.len(),
                "{name}: cut at {p} not reported: {found:?}"
            );
        }
        s.cuts += 1;
    }
    s
}

#[test]
fn every_log_cut_at_every_boundary_every_early_byte_and_random_offsets() {
    let files = corpus_files();
    let mut rng = Rng::new(0x5eed_0001);
    let (mut cuts, mut fresh, mut verified) = (0, 0, 0);
    for path in &files {
        let bytes = std::fs::read(path).unwrap();
        let s = truncation_sweep(&stem(path), &bytes, &mut rng);
        cuts += s.cuts;
        fresh += s.fresh;
        verified += s.verified;
    }
    eprintln!(
        "{} logs: {cuts} cuts ({fresh} read afresh, {verified} cross-checked)",
        files.len()
    );
    assert!(cuts > 100_000, "{cuts} cuts");
}

/// One kind of corruption, applied to a copy of a log.
#[derive(Debug, Clone, Copy)]
enum Damage {
    /// Flip one bit of a message header's size or type.
    HeaderBitFlip,
    /// Zero `n` bytes from a message's start.
    ZeroRun,
    /// Insert random bytes between two messages.
    Garbage,
    /// Copy a message right after itself.
    Duplicate,
    /// Swap two neighbouring messages.
    Swap,
    /// Set a message's size field.
    Size(u16),
}

/// A damaged copy: the bytes, the original messages that should still be there (index
/// and offset in the copy), and the damaged byte range in the copy (None when the copy
/// is a valid log).
struct Damaged {
    bytes: Vec<u8>,
    kept: Vec<(usize, usize)>,
    stretch: Option<(usize, usize)>,
}

fn damage(
    bytes: &[u8],
    all: &[MessageAt<'_>],
    ends: &[usize],
    i: usize,
    kind: Damage,
    rng: &mut Rng,
) -> Damaged {
    let start = all[i].offset as usize;
    let end = ends[i];
    let mut out = bytes.to_vec();
    let shifted = |delta: isize, from: usize| -> Vec<(usize, usize)> {
        (from..all.len())
            .map(|j| (j, (all[j].offset as isize + delta) as usize))
            .collect()
    };
    let before: Vec<(usize, usize)> = (0..i).map(|j| (j, all[j].offset as usize)).collect();
    match kind {
        Damage::HeaderBitFlip => {
            let byte = start + rng.below(3);
            out[byte] ^= 1 << rng.below(8);
            // The message may now swallow, or be cut by, its neighbours: a message
            // longer than it was is allowed to hide at most the next three.
            let mut kept = before;
            kept.extend(shifted(0, (i + 4).min(all.len())));
            Damaged {
                bytes: out,
                kept,
                stretch: Some((start, end)),
            }
        }
        Damage::ZeroRun => {
            let n = 1 + rng.below(64);
            let stop = (start + n).min(out.len());
            out[start..stop].fill(0);
            let first_after = ends.partition_point(|&e| e <= stop);
            let mut kept = before;
            kept.extend(shifted(0, (first_after + 1).min(all.len())));
            Damaged {
                bytes: out,
                kept,
                stretch: Some((start, stop)),
            }
        }
        Damage::Garbage => {
            let n = 1 + rng.below(200);
            let garbage: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
            out.splice(start..start, garbage);
            let mut kept = before;
            kept.extend(shifted(n as isize, i));
            Damaged {
                bytes: out,
                kept,
                stretch: Some((start, start + n)),
            }
        }
        Damage::Duplicate => {
            let copy = bytes[start..end].to_vec();
            out.splice(end..end, copy);
            let mut kept = before;
            kept.push((i, start));
            kept.extend(shifted((end - start) as isize, i + 1));
            Damaged {
                bytes: out,
                kept,
                stretch: None,
            }
        }
        Damage::Swap => {
            let next_end = ends[i + 1];
            let (a, b) = (bytes[start..end].to_vec(), bytes[end..next_end].to_vec());
            out[start..start + b.len()].copy_from_slice(&b);
            out[start + b.len()..next_end].copy_from_slice(&a);
            let mut kept = before;
            kept.push((i + 1, start));
            kept.push((i, start + b.len()));
            kept.extend(shifted(0, i + 2));
            Damaged {
                bytes: out,
                kept,
                stretch: None,
            }
        }
        Damage::Size(size) => {
            out[start..start + 2].copy_from_slice(&size.to_le_bytes());
            let mut kept = before;
            kept.extend(shifted(0, i + 1));
            Damaged {
                bytes: out,
                kept,
                stretch: Some((start, end)),
            }
        }
    }
}

/// The same message, wherever it is (a logged string records its own offset).
fn same_message(a: &ulog_core::Message<'_>, b: &ulog_core::Message<'_>) -> bool {
    use ulog_core::Message::Log;
    match (a, b) {
        (Log(x), Log(y)) => {
            (x.raw_level, x.tag, x.timestamp, x.text) == (y.raw_level, y.tag, y.timestamp, y.text)
        }
        _ => a == b,
    }
}

#[test]
fn corruption_of_every_kind_at_random_places_in_every_log() {
    let files = corpus_files();
    let mut rng = Rng::new(0x5eed_0002);
    let kinds = [
        Damage::HeaderBitFlip,
        Damage::ZeroRun,
        Damage::Garbage,
        Damage::Duplicate,
        Damage::Swap,
        Damage::Size(0),
        Damage::Size(1),
        Damage::Size(65535),
    ];
    let mut cases = 0;
    for path in &files {
        let name = stem(path);
        let bytes = std::fs::read(path).unwrap();
        let (all, findings) = frame(&bytes);
        if !findings.is_empty() {
            // Logs that are damaged already: the new damage could meet the old.
            continue;
        }
        let ends: Vec<usize> = all.iter().map(|m| end_of(&bytes, m)).collect();
        // Targets: data-section messages that nothing else depends on.
        let targets: Vec<usize> = (0..all.len().saturating_sub(6))
            .filter(|&i| {
                matches!(
                    all[i].message,
                    ulog_core::Message::Data { .. } | ulog_core::Message::Log(_)
                )
            })
            .filter(|&i| {
                matches!(
                    all[i + 1].message,
                    ulog_core::Message::Data { .. } | ulog_core::Message::Log(_)
                )
            })
            .collect();
        if targets.is_empty() {
            continue;
        }
        for kind in kinds {
            for _ in 0..4 {
                let i = targets[rng.below(targets.len())];
                let d = damage(&bytes, &all, &ends, i, kind, &mut rng);
                let (got, found) = frame(&d.bytes);
                let at = |o: usize| {
                    got.binary_search_by_key(&(o as u64), |m| m.offset)
                        .ok()
                        .map(|k| &got[k])
                };
                for &(j, o) in &d.kept {
                    let m = at(o).unwrap_or_else(|| {
                        panic!("{name}: {kind:?} at message {i} (byte {}): message {j} (now at {o}) lost; findings {found:?}", all[i].offset)
                    });
                    assert!(
                        same_message(&m.message, &all[j].message),
                        "{name}: {kind:?} at message {i}: message {j} changed: {:?} -> {:?}",
                        all[j],
                        m
                    );
                }
                if let Some((a, b)) = d.stretch {
                    // Damage that changes how the bytes frame is reported, and the
                    // reported range touches the damaged stretch.
                    let framed_as_before = got
                        .iter()
                        .map(|m| m.offset)
                        .eq(all.iter().map(|m| m.offset))
                        && got.len() == all.len();
                    if !framed_as_before {
                        // Reported where the damage starts, or where the message it
                        // made too long runs into the next one.
                        assert!(
                            found.iter().any(|f| f.is_damage()
                                || matches!(f.kind, FindingKind::UnknownMessageType(_)))
                                && found
                                    .iter()
                                    .any(|f| (a..=b + 65541).contains(&(f.offset as usize))),
                            "{name}: {kind:?} at {a}..{b} not reported: {found:?}"
                        );
                    }
                } else {
                    assert!(
                        found.iter().all(|f| !f.is_damage()),
                        "{name}: {kind:?}: {found:?}"
                    );
                }
                cases += 1;
            }
        }
    }
    eprintln!("{cases} corruptions checked");
    assert!(cases >= 100, "{cases}");
}
