//! Small written logs for the `ulog_module!` tests: one whose formats come after
//! data messages (as the spec allows and real loggers write), one with formats that
//! cannot be bound.

use ulog_core::testing::LogBuilder;

/// A log that defines `first`, logs a row of it, then defines `later` and
/// `later_pair` (which nests `later`) and logs rows of them.
pub fn formats_after_data() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 1_000);
    b.format("first:uint64_t timestamp;uint8_t x;");
    b.subscribe(0, 0, "first");
    b.data(0, &[&2_000u64.to_le_bytes()[..], &[7]].concat());
    b.format("later:uint64_t timestamp;float y;");
    b.format("later_pair:uint64_t timestamp;later[2] pair;");
    b.subscribe(0, 1, "later");
    b.subscribe(0, 2, "later_pair");
    for i in 0..3u64 {
        let t = 3_000 + i;
        let y = 0.5 * i as f32;
        b.data(1, &[&t.to_le_bytes()[..], &y.to_le_bytes()].concat());
        let mut pair = t.to_le_bytes().to_vec();
        for k in 0..2u64 {
            pair.extend_from_slice(&(t + k).to_le_bytes());
            pair.extend_from_slice(&(y + k as f32).to_le_bytes());
        }
        b.data(2, &pair);
    }
    b.into_bytes()
}

/// A log with one format that binds (`ok`) and formats that cannot: `odd` (a type
/// the spec does not have, `float32`), `orphan` (an unknown nested type) and
/// `clash` (two fields of one Rust name), the last two after data.
pub fn unbindable() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 1_000);
    b.format("ok:uint64_t timestamp;");
    b.format("odd:uint64_t timestamp;float32 x;");
    b.subscribe(0, 0, "ok");
    b.data(0, &5_000u64.to_le_bytes());
    b.format("orphan:uint64_t timestamp;nowhere n;");
    b.format("clash:uint64_t timestamp;uint8_t self;uint8_t self_;");
    b.into_bytes()
}
