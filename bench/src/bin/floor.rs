//! The floor: map the file (or read it whole with `--read`), then walk the 3-byte
//! message headers (`u16` size, `u8` type) after the 16-byte file header, counting
//! messages. Nothing else: no checks, no index. Any reader that looks at every message
//! costs at least this.
//!
//! ```text
//! floor FILE [--read]
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

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: floor FILE [--read]");
        return ExitCode::from(2);
    };
    let read = args.iter().any(|a| a == "--read");
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("floor: {path}: {e}");
            return ExitCode::from(3);
        }
    };
    let (count, types, len) = if read {
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
