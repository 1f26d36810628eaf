ulog_core::ulog_structs!("vehicle_attitude:uint64_t timestamp;float[x] q;");

fn main() {}
