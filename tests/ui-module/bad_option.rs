ulog_core::ulog_module!(unbound = loud; mod bindings = "unbindable.ulg");

fn main() {}
