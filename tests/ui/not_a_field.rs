use ulog_core::{typed::CharArray, ULogMessage};

struct Plain {
    x: u8,
}

#[derive(ULogMessage)]
struct M {
    plain: Plain,
    names: [CharArray<4>; 2],
}

fn main() {}
