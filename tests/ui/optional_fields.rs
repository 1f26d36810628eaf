// Optional fields: an `Option` is already optional, padding is never optional, and an
// `Option` holds a whole field.
use ulog_core::ULogMessage;

#[derive(ULogMessage)]
struct Gps {
    timestamp: u64,
    #[ulog(default)]
    lat: Option<i32>,
    #[ulog(default = 1)]
    _padding0: [u8; 3],
    _padding1: Option<[u8; 2]>,
    alt: [Option<i32>; 2],
}

fn main() {}
