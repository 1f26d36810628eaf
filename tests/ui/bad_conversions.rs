use ulog_core::ULogMessage;

fn seconds(us: u32) -> f32 {
    us as f32 * 1e-6
}

// Every error of the conversions and topic aliases at once: a type name that is not
// a ULog type, one declared twice, a conversion on a `char` string, a topic alias
// that is not a valid name and one that repeats the topic's name.
#[derive(ULogMessage)]
#[ulog(name = "sensor_combined", alias = "sensor combined", alias = "sensor_combined")]
struct SensorCombined {
    timestamp: u64,
    #[ulog(convert(uint23_t = seconds))]
    gyro_integral_dt: f32,
    #[ulog(convert(uint32_t = seconds, uint32_t = seconds))]
    accelerometer_integral_dt: f32,
    #[ulog(char, convert(uint8_t = seconds))]
    name: [u8; 4],
}

fn main() {}
