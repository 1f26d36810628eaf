ulog_core::ulog_module!(unbound = deny; mod bindings = "unbindable.ulg");

fn main() {}
