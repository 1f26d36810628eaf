use ulog_core::ULogMessage;

#[derive(ULogMessage)]
struct M {
    a: usize,
    b: String,
    c: &'static str,
    d: [[u8; 2]; 2],
    e: (u8, u8),
    f: char,
}

fn main() {}
