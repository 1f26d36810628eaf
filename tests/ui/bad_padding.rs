use ulog_core::ULogMessage;

#[derive(ULogMessage)]
struct M {
    a: u8,
    _padding0: u16,
    _padding1: [f32; 2],
}

ulog_core::ulog_structs!("n:uint8_t a;n2 _padding0;", "n2:uint8_t b;");

fn main() {}
