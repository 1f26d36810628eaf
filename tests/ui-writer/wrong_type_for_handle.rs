use ulog_core::ULogMessage;
use ulog_core::LogWriter;

#[derive(ULogMessage)]
struct Attitude {
    timestamp: u64,
    q: [f32; 4],
}

#[derive(ULogMessage)]
struct Battery {
    timestamp: u64,
    voltage_v: f32,
}

fn main() {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    let att = w.subscribe::<Attitude>(0).unwrap();
    let mut data = w.start_data().unwrap();
    data.write(&att, &Battery { timestamp: 0, voltage_v: 16.0 }).unwrap();
}
