use ulog_core::ULogMessage;

#[derive(ULogMessage)]
struct M {
    #[ulog(name = "a")]
    b: u8,
    a: u8,
    #[ulog(alias = "a")]
    c: u8,
}

fn main() {}
