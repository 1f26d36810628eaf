// A misspelt basic type is taken for a nested type: the error suggests the type meant.
ulog_core::ulog_structs!("sensor:uint64_t timestamp;flaot temperature;");

fn main() {}
