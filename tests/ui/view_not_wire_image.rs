// A view needs a struct whose memory is its payload's image: `#[repr(C)]` and
// alignment-1 fields; and it cannot hold an `Option`.
use ulog_core::typed::le;
use ulog_core::ULogMessage;

#[derive(ULogMessage)]
#[ulog(view)]
#[repr(C)]
struct NativeFields {
    timestamp: u64,
    x: f32,
}

#[derive(ULogMessage)]
#[ulog(view)]
struct Reordered {
    a: u8,
    timestamp: le::U64,
}

#[derive(ULogMessage)]
#[ulog(view)]
#[repr(C)]
struct Optional {
    timestamp: le::U64,
    x: Option<le::F32>,
}

fn main() {}
