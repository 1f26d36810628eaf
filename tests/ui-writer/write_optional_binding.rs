// A binding with an `Option` field reads, but cannot be written: `None` has no bytes.
use ulog_core::{LogWriter, ULogMessage};

#[derive(ULogMessage)]
struct Battery {
    timestamp: u64,
    discharged_mah: Option<f32>,
}

fn main() {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    let _ = w.subscribe::<Battery>(0);
}
