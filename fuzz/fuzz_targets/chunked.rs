//! The incremental reader (`PushReader`) fed arbitrary bytes in chunks of sizes chosen
//! by the input: its messages and findings must equal the whole-file reader's. The
//! one-pass scans (`scan` over the bytes, `scan` of a `Source::reader` over reads of
//! those sizes, and reading ahead over them with chunks and room the input chose,
//! `testing::read_ahead_in`) must hand out exactly its data messages, with the same
//! findings.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::io::Read;

use ulog_core::read::Messages;
use ulog_core::stream::{Progress, PushReader};
use ulog_core::{ScanOptions, Source};

/// Reads of the sizes the input chose.
struct Pieces<'a> {
    data: &'a [u8],
    sizes: &'a [u16],
    i: usize,
}

impl Read for Pieces<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = (self.sizes.get(self.i).copied().unwrap_or(4096) as usize)
            .clamp(1, buf.len().max(1))
            .min(self.data.len())
            .min(buf.len());
        self.i += 1;
        buf[..n].copy_from_slice(&self.data[..n]);
        self.data = &self.data[n..];
        Ok(n)
    }
}

fuzz_target!(|input: (Vec<u16>, &[u8])| {
    let (sizes, data) = input;
    let mut whole = Messages::new(data);
    let expected: Result<Vec<(u64, u8)>, _> = whole
        .by_ref()
        .map(|m| m.map(|m| (m.offset, m.message.msg_type())))
        .collect();
    let mut inc = PushReader::new();
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
                Ok(Progress::Ready) => {
                    let m = inc.current().unwrap();
                    got.push((m.offset, m.message.msg_type()));
                }
                Ok(Progress::NeedMore) => break,
                Ok(Progress::End) => break 'feed,
                Err(e) => {
                    result = Err(e);
                    break 'feed;
                }
            }
        }
        assert!(inc.buffered() <= 3 * 65538 + 65536);
    }
    let mut scanned = Vec::new();
    let options = ScanOptions::default();
    let scan = ulog_core::scan(data, &options, |r| scanned.push(r.offset));
    let mut read = Vec::new();
    let pieces = Pieces {
        data,
        sizes: &sizes,
        i: 0,
    };
    let scan_read = ulog_core::scan(Source::reader(pieces), &options, |r| read.push(r.offset));
    let mut ahead = Vec::new();
    let pieces = Pieces {
        data,
        sizes: &sizes,
        i: 0,
    };
    let (chunk, room) = match sizes.as_slice() {
        [c, r, ..] => (*c as usize % 600 + 1, *r as usize % 300),
        _ => (4096, 1024),
    };
    let scan_ahead =
        ulog_core::testing::read_ahead_in(pieces, chunk, room, |r| ahead.push(r.offset));
    match (expected, result) {
        (Ok(e), Ok(())) => {
            assert_eq!(e, got);
            assert_eq!(whole.findings(), inc.findings());
            let data_offsets: Vec<u64> = e.iter().filter(|m| m.1 == b'D').map(|m| m.0).collect();
            let (scan, scan_read) = (scan.unwrap(), scan_read.unwrap());
            assert_eq!(scanned, data_offsets);
            assert_eq!(read, data_offsets);
            assert_eq!(ahead, data_offsets);
            assert_eq!(scan_ahead.unwrap(), scan_read);
            assert_eq!(scan.findings, whole.findings());
            assert_eq!(scan, scan_read);
            assert_eq!(scan.messages as usize, e.len());
        }
        (Err(a), Err(b)) => {
            assert_eq!(a, b);
            assert_eq!(scan.unwrap_err(), a);
            assert_eq!(scan_read.unwrap_err(), a);
            assert_eq!(scan_ahead.unwrap_err(), a);
        }
        (a, b) => panic!("whole {a:?} vs incremental {b:?}"),
    }
});
