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

/// The walk of [`walk`] over the file read in chunks of [`CHUNK`] bytes into one
/// buffer, a message cut by a chunk's end carried to the next: (messages, type sum,
/// bytes read).
fn walk_chunks(mut file: &std::fs::File) -> std::io::Result<(u64, u64, usize)> {
    use std::io::Read;
    let mut buf = vec![0u8; CHUNK + (1 << 16) + 3];
    // The file's bytes from `base` are `buf[..end]`; the next header is at `pos`.
    let (mut end, mut base, mut pos) = (0usize, 0usize, 16usize);
    let (mut count, mut types) = (0u64, 0u64);
    loop {
        let n = file.read(&mut buf[end..end + CHUNK])?;
        if n == 0 {
            return Ok((count, types, base + end));
        }
        end += n;
        while pos + 3 <= end {
            let size = u16::from_le_bytes([buf[pos], buf[pos + 1]]) as usize;
            types += u64::from(buf[pos + 2]);
            pos += 3 + size;
            count += 1;
        }
        // Keep the bytes from the next header on (none when it lies beyond them).
        let keep = pos.min(end);
        buf.copy_within(keep..end, 0);
        base += keep;
        end -= keep;
        pos -= keep;
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
