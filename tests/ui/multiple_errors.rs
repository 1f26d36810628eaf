use ulog_core::ULogMessage;

#[derive(ULogMessage)]
#[ulog(name = "bad name", name = "again")]
struct M {
    a: usize,
    #[ulog(char)]
    b: u32,
    #[ulog(name = "c", unknown)]
    c: u8,
    #[ulog(name = "bad-field")]
    d: u8,
}

ulog_core::ulog_structs!("m:uint8_t a;float[0] b;int8_t a;", "x:nope y;");

fn main() {}
