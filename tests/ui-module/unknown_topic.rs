ulog_core::ulog_module!(topics = ["ok", "clsh"]; mod bindings = "unbindable.ulg");

fn main() {}
