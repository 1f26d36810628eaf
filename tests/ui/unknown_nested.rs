ulog_core::ulog_structs!("outer:uint64_t timestamp;esc_report[8] esc;");

fn main() {
    // The struct is still there: no cascade of "cannot find type".
    let _ = Outer::default().timestamp;
}
