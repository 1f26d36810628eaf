ulog_core::ulog_structs!("a:uint8_t v;b[2] x;", "b:a y;");

fn main() {}
