#![deny(deprecated)]

ulog_core::ulog_module!(mod bindings = "unbindable.ulg");

fn main() {
    let _ = bindings::Ok::default();
}
