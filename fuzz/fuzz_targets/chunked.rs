//! The incremental reader fed arbitrary bytes in chunks of sizes chosen by the input:
//! its messages and findings must equal the whole-file reader's.
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_core::{Incremental, Messages, Status};

fuzz_target!(|input: (Vec<u16>, &[u8])| {
    let (sizes, data) = input;
    let mut whole = Messages::new(data);
    let expected: Result<Vec<(u64, u8)>, _> = whole
        .by_ref()
        .map(|m| m.map(|m| (m.offset, m.message.msg_type())))
        .collect();
    let mut inc = Incremental::new();
    let mut got = Vec::new();
    let mut rest = data;
    let mut i = 0;
    let mut result = Ok(());
    'feed: loop {
        if !rest.is_empty() {
            let n = (sizes.get(i).copied().unwrap_or(4096) as usize).clamp(1, rest.len());
            inc.push(&rest[..n]);
            rest = &rest[n..];
            i += 1;
        } else {
            inc.finish();
        }
        loop {
            match inc.advance() {
                Ok(Status::Ready) => {
                    let m = inc.current().unwrap();
                    got.push((m.offset, m.message.msg_type()));
                }
                Ok(Status::NeedMore) => break,
                Ok(Status::End) => break 'feed,
                Err(e) => {
                    result = Err(e);
                    break 'feed;
                }
            }
        }
        assert!(inc.buffered() <= 3 * 65538 + 65536);
    }
    match (expected, result) {
        (Ok(e), Ok(())) => {
            assert_eq!(e, got);
            assert_eq!(whole.findings(), inc.findings());
        }
        (Err(a), Err(b)) => assert_eq!(a, b),
        (a, b) => panic!("whole {a:?} vs incremental {b:?}"),
    }
});
