use ulog_core::LogWriter;

fn main() {
    let w = LogWriter::new(Vec::new(), 0).unwrap();
    let mut data = w.start_data().unwrap();
    // Formats belong to the definitions section: the data writer has no such method.
    data.format("late:uint64_t timestamp;").unwrap();
}
