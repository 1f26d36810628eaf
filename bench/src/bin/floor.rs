//! The floor: map the file (or read it whole with `--read`, or in 1 MiB chunks into
//! one buffer with `--chunks`), then walk the 3-byte message headers (`u16` size, `u8`
//! type) after the 16-byte file header, counting messages. Nothing else: no checks,
//! no index. Any reader that looks at every message costs at least this; one that
//! reads the file with `read()` in bounded memory, at least `--chunks`.
//!
//! ```text
//! floor FILE [--read | --chunks]
//! ```
//!
//! Prints `messages=N bytes=B` (and the sum of the type bytes, so that the walk is
//! not optimised away).

use std::process::ExitCode;

fn walk(bytes: &[u8]) -> (u64, u64) {
    let mut pos = 16usize;
    let mut count = 0u64;
    let mut types = 0u64;
    while pos + 3 <= bytes.len() {
        let size = u16::from_le_bytes([bytes[pos], bytes[pos + 1]]) as usize;
        types += u64::from(bytes[pos + 2]);
        pos += 3 + size;
        count += 1;
    }
    (count, types)
}

/// Bytes read at a time by `--chunks` (as the passes' read-ahead).
const CHUNK: usize = 1 << 20;

/// The memory page: `--chunks` reads to a page boundary of its buffer, as the passes'
/// read-ahead does (the kernel copies a cached file about three times as fast there as
/// 16 bytes past one, where a buffer that `malloc` maps starts).
const PAGE: usize = 4096;

/// The walk of [`walk`] over the file read in chunks of [`CHUNK`] bytes into one
/// buffer, each read to the same page boundary, a header cut by a chunk's end carried
/// before it: (messages, type sum, bytes read).
fn walk_chunks(mut file: &std::fs::File) -> std::io::Result<(u64, u64, usize)> {
    use std::io::Read;
    let mut buf = vec![0u8; 2 * PAGE + CHUNK];
    let addr = buf.as_ptr() as usize + PAGE;
    let at = PAGE + (PAGE - addr % PAGE) % PAGE;
    // The bytes still to walk are `buf[pos..end]`; `pos` beyond `end`: the rest of a
    // message to skip in the next chunk.
    let (mut pos, mut end, mut total) = (at + 16, at, 0usize);
    let (mut count, mut types) = (0u64, 0u64);
    loop {
        if pos < end {
            // A header cut short (at most 2 bytes): before the next chunk.
            let cut = end - pos;
            buf.copy_within(pos..end, at - cut);
            pos = at - cut;
        } else {
            pos = at + (pos - end);
        }
        let n = file.read(&mut buf[at..at + CHUNK])?;
        if n == 0 {
            return Ok((count, types, total));
        }
        total += n;
        end = at + n;
        while pos + 3 <= end {
            let size = u16::from_le_bytes([buf[pos], buf[pos + 1]]) as usize;
            types += u64::from(buf[pos + 2]);
            pos += 3 + size;
            count += 1;
        }
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: floor FILE [--read | --chunks]");
        return ExitCode::from(2);
    };
    let read = args.iter().any(|a| a == "--read");
    let chunks = args.iter().any(|a| a == "--chunks");
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("floor: {path}: {e}");
            return ExitCode::from(3);
        }
    };
    let (count, types, len) = if chunks {
        match walk_chunks(&file) {
            Ok(walked) => walked,
            Err(e) => {
                eprintln!("floor: {path}: {e}");
                return ExitCode::from(3);
            }
        }
    } else if read {
        let mut bytes = Vec::new();
        if let Err(e) = std::io::Read::read_to_end(&mut &file, &mut bytes) {
            eprintln!("floor: {path}: {e}");
            return ExitCode::from(3);
        }
        let (c, t) = walk(&bytes);
        (c, t, bytes.len())
    } else {
        // SAFETY: read-only map of a file nobody writes while the benchmark runs.
        let map = match unsafe { memmap2::Mmap::map(&file) } {
            Ok(m) => m,
            Err(e) => {
                eprintln!("floor: {path}: {e}");
                return ExitCode::from(3);
            }
        };
        let (c, t) = walk(&map);
        (c, t, map.len())
    };
    println!("messages={count} bytes={len} check={types}");
    ExitCode::SUCCESS
}
