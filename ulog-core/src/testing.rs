//! Building raw ULog bytes message by message, for tests, examples and fuzz seeds, and
//! a few hooks for tests and fuzzing ([`read_ahead_in`], [`load_columns_in`]).
//!
//! This writes exactly the bytes it is told to, valid or not, so that tests can build
//! damaged logs too. (Applications that log data use the writer, not this.)

use crate::bytes::{MAGIC, SYNC_MAGIC};

/// A byte-level ULog builder.
///
/// ```
/// use ulog_core::testing::LogBuilder;
/// let mut b = LogBuilder::new(1, 0);
/// b.format("t:uint64_t timestamp;float x;");
/// b.subscribe(0, 0, "t");
/// b.data(0, &[&1u64.to_le_bytes()[..], &2.5f32.to_le_bytes()].concat());
/// let log = ulog_core::ULog::parse(b.bytes()).unwrap();
/// assert_eq!(log.topic("t", 0).unwrap().len(), 1);
/// ```
#[derive(Debug, Clone)]
pub struct LogBuilder {
    bytes: Vec<u8>,
    boundaries: Vec<usize>,
}

impl LogBuilder {
    /// A log with the 16-byte header of `version` and start `timestamp`.
    pub fn new(version: u8, timestamp: u64) -> LogBuilder {
        let mut bytes = MAGIC.to_vec();
        bytes.push(version);
        bytes.extend_from_slice(&timestamp.to_le_bytes());
        LogBuilder {
            boundaries: vec![bytes.len()],
            bytes,
        }
    }

    /// The bytes so far.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The bytes, consuming the builder.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    /// Offsets where each message starts (the first is the end of the header), and
    /// the end of the last message.
    pub fn boundaries(&self) -> &[usize] {
        &self.boundaries
    }

    /// Appends a message of type `t` with `payload` (the size is its length).
    pub fn raw(&mut self, t: u8, payload: &[u8]) -> &mut Self {
        let size = u16::try_from(payload.len()).expect("payload fits a message");
        self.bytes.extend_from_slice(&size.to_le_bytes());
        self.bytes.push(t);
        self.bytes.extend_from_slice(payload);
        self.boundaries.push(self.bytes.len());
        self
    }

    /// Appends bytes that are not a message (garbage, zeros).
    pub fn garbage(&mut self, bytes: &[u8]) -> &mut Self {
        self.bytes.extend_from_slice(bytes);
        self.boundaries.push(self.bytes.len());
        self
    }

    /// `B`: flag bits with these compat/incompat bytes and appended offsets.
    pub fn flag_bits(
        &mut self,
        compat: [u8; 8],
        incompat: [u8; 8],
        appended: [u64; 3],
    ) -> &mut Self {
        let mut p = Vec::with_capacity(40);
        p.extend_from_slice(&compat);
        p.extend_from_slice(&incompat);
        for o in appended {
            p.extend_from_slice(&o.to_le_bytes());
        }
        self.raw(b'B', &p)
    }

    /// `F`: a format definition.
    pub fn format(&mut self, text: &str) -> &mut Self {
        self.raw(b'F', text.as_bytes())
    }

    fn key_value(key: &str, value: &[u8]) -> Vec<u8> {
        let mut p = vec![u8::try_from(key.len()).expect("key fits")];
        p.extend_from_slice(key.as_bytes());
        p.extend_from_slice(value);
        p
    }

    /// `I`: information, `key` as `type name`.
    pub fn info(&mut self, key: &str, value: &[u8]) -> &mut Self {
        let p = Self::key_value(key, value);
        self.raw(b'I', &p)
    }

    /// `I` with a `char[N]` string value.
    pub fn info_str(&mut self, name: &str, value: &str) -> &mut Self {
        self.info(&format!("char[{}] {name}", value.len()), value.as_bytes())
    }

    /// `M`: multi-information.
    pub fn multi_info(&mut self, continued: bool, key: &str, value: &[u8]) -> &mut Self {
        let mut p = vec![u8::from(continued)];
        p.extend(Self::key_value(key, value));
        self.raw(b'M', &p)
    }

    /// `P`: a parameter.
    pub fn param(&mut self, key: &str, value: &[u8]) -> &mut Self {
        let p = Self::key_value(key, value);
        self.raw(b'P', &p)
    }

    /// `Q`: a default parameter.
    pub fn default_param(&mut self, default_types: u8, key: &str, value: &[u8]) -> &mut Self {
        let mut p = vec![default_types];
        p.extend(Self::key_value(key, value));
        self.raw(b'Q', &p)
    }

    /// `A`: a subscription.
    pub fn subscribe(&mut self, multi_id: u8, msg_id: u16, name: &str) -> &mut Self {
        let mut p = vec![multi_id];
        p.extend_from_slice(&msg_id.to_le_bytes());
        p.extend_from_slice(name.as_bytes());
        self.raw(b'A', &p)
    }

    /// `R`: an unsubscription.
    pub fn unsubscribe(&mut self, msg_id: u16) -> &mut Self {
        self.raw(b'R', &msg_id.to_le_bytes())
    }

    /// `D`: data for `msg_id`.
    pub fn data(&mut self, msg_id: u16, payload: &[u8]) -> &mut Self {
        let mut p = msg_id.to_le_bytes().to_vec();
        p.extend_from_slice(payload);
        self.raw(b'D', &p)
    }

    /// `L`: a logged string (`level` as PX4 writes it, ASCII `'0'`–`'7'`).
    pub fn log(&mut self, level: u8, timestamp: u64, text: &str) -> &mut Self {
        let mut p = vec![level];
        p.extend_from_slice(&timestamp.to_le_bytes());
        p.extend_from_slice(text.as_bytes());
        self.raw(b'L', &p)
    }

    /// `C`: a tagged logged string.
    pub fn tagged_log(&mut self, level: u8, tag: u16, timestamp: u64, text: &str) -> &mut Self {
        let mut p = vec![level];
        p.extend_from_slice(&tag.to_le_bytes());
        p.extend_from_slice(&timestamp.to_le_bytes());
        p.extend_from_slice(text.as_bytes());
        self.raw(b'C', &p)
    }

    /// `S`: a sync message.
    pub fn sync(&mut self) -> &mut Self {
        self.raw(b'S', &SYNC_MAGIC)
    }

    /// `O`: a dropout.
    pub fn dropout(&mut self, duration_ms: u16) -> &mut Self {
        self.raw(b'O', &duration_ms.to_le_bytes())
    }
}

/// A small deterministic generator (xorshift64*) for tests that sweep inputs: the
/// same seed gives the same sequence, so a failure repeats.
///
/// ```
/// let mut a = ulog_core::testing::Rng::new(7);
/// let mut b = ulog_core::testing::Rng::new(7);
/// assert_eq!(a.next_u64(), b.next_u64());
/// assert!(a.below(10) < 10);
/// ```
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed` (0 is replaced: xorshift never leaves 0).
    pub fn new(seed: u64) -> Rng {
        Rng(if seed == 0 {
            0x9e37_79b9_7f4a_7c15
        } else {
            seed
        })
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}

/// A log whose topic names a file system refuses or folds: Windows's device names,
/// names that differ only in case, `a/b` beside `a_b`, a name of 300 bytes. (The
/// format grammar takes only letters, digits, `_`, `-` and `/` in a topic's name: other
/// characters cannot reach a file name; `naming`'s tests cover them.) Each topic has
/// `1 + i` rows holding its number `i`; it returns the names in that order.
pub fn awkward_names_log() -> (Vec<u8>, Vec<String>) {
    let long = format!("long_{}", "x".repeat(295));
    let names: Vec<String> = [
        "CON",
        "aux",
        "nul",
        "com1",
        "LPT9",
        "FOO",
        "Foo",
        "foo",
        "a/b",
        "a_b",
        &long,
        "vehicle_status",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut b = LogBuilder::new(1, 0);
    for name in &names {
        b.format(&format!("{name}:uint64_t timestamp;uint32_t n;"));
    }
    // Formats first, as PX4 writes them: in the data section, a format whose name is
    // this long is not told from garbage.
    for (id, name) in names.iter().enumerate() {
        b.subscribe(0, id as u16, name);
    }
    // Each topic's rows hold its own number: 1 + id rows of it.
    for (id, _) in names.iter().enumerate() {
        for row in 0..=id as u64 {
            let mut p = (1000 + row).to_le_bytes().to_vec();
            p.extend_from_slice(&(id as u32).to_le_bytes());
            b.data(id as u16, &p);
        }
    }
    (b.into_bytes(), names)
}

/// A small, valid, version-1 log of a short simulated flight: flag bits, information,
/// parameters and defaults, nested and multi-instance topics with trailing padding,
/// logged and tagged strings, a parameter change, a dropout and sync messages. Used by
/// examples and doctests, and by `ulog info` when given no file.
pub fn sample_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 1_000_000);
    b.flag_bits([1, 0, 0, 0, 0, 0, 0, 0], [0; 8], [0; 3]);
    b.info_str("sys_name", "PX4");
    b.info_str("ver_hw", "SIMULATED");
    b.info("uint32_t ver_sw_release", &0x010e_03ffu32.to_le_bytes());
    b.info("int32_t time_ref_utc", &0i32.to_le_bytes());
    b.multi_info(false, "char[6] boot_console", b"line 1");
    b.multi_info(true, "char[6] boot_console", b"line 2");
    b.format("vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t[4] _padding0;");
    b.format("vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;float vy;float vz;bool xy_valid;uint8_t[7] _padding0;");
    b.format("battery_status:uint64_t timestamp;float voltage_v;float remaining;uint8_t cell_count;uint8_t[7] _padding0;");
    b.format(
        "esc_status:uint64_t timestamp;uint8_t esc_count;uint8_t[7] _padding0;esc_report[2] esc;",
    );
    b.format("esc_report:uint64_t timestamp;int32_t esc_rpm;float esc_voltage;");
    b.param("int32_t MAV_TYPE", &2i32.to_le_bytes());
    b.param("float MPC_XY_VEL_MAX", &12.0f32.to_le_bytes());
    b.default_param(1, "float MPC_XY_VEL_MAX", &12.0f32.to_le_bytes());
    b.default_param(3, "int32_t MAV_TYPE", &1i32.to_le_bytes());
    b.subscribe(0, 0, "vehicle_attitude");
    b.subscribe(0, 1, "vehicle_local_position");
    b.subscribe(0, 2, "battery_status");
    b.subscribe(1, 3, "battery_status");
    b.subscribe(0, 4, "esc_status");
    b.log(b'6', 1_000_000, "[commander] Takeoff detected");
    for i in 0..200u64 {
        let t = 1_000_000 + i * 50_000;
        let s = i as f32 / 200.0;
        let angle = s * core::f32::consts::PI;
        let mut att = t.to_le_bytes().to_vec();
        for q in [(angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin()] {
            att.extend_from_slice(&q.to_le_bytes());
        }
        b.data(0, &att);
        if i % 2 == 0 {
            let mut pos = t.to_le_bytes().to_vec();
            let (x, y, z) = (
                20.0 * angle.cos(),
                20.0 * angle.sin(),
                -10.0 * (s * 4.0).min(1.0),
            );
            for v in [x, y, z, -20.0 * angle.sin(), 20.0 * angle.cos(), 0.0] {
                pos.extend_from_slice(&v.to_le_bytes());
            }
            pos.push(1);
            b.data(1, &pos);
        }
        if i % 10 == 0 {
            for (id, v) in [(2u16, 16.8f32), (3, 16.7)] {
                let mut bat = t.to_le_bytes().to_vec();
                bat.extend_from_slice(&(v - s).to_le_bytes());
                bat.extend_from_slice(&(1.0 - s * 0.3).to_le_bytes());
                bat.push(4);
                b.data(id, &bat);
            }
            let mut esc = t.to_le_bytes().to_vec();
            esc.push(2);
            esc.extend_from_slice(&[0; 7]);
            for k in 0..2u64 {
                esc.extend_from_slice(&(t + k).to_le_bytes());
                esc.extend_from_slice(&(5000 + i as i32 * 10 + k as i32).to_le_bytes());
                esc.extend_from_slice(&(16.0 - s).to_le_bytes());
            }
            b.data(4, &esc);
        }
        if i == 100 {
            b.param("float MPC_XY_VEL_MAX", &8.0f32.to_le_bytes());
            b.tagged_log(b'4', 1, t, "battery at 70%");
            b.dropout(12);
        }
        if i % 50 == 0 {
            b.sync();
        }
    }
    b.log(b'6', 11_000_000, "[commander] Landing detected");
    b.into_bytes()
}

/// [`scan`](crate::scan) of a reader read ahead ([`ScanOptions::read_ahead`](crate::ScanOptions::read_ahead)),
/// reading `chunk` bytes at a time (at least 1) with `room` bytes kept before each
/// chunk for what framing still needs of the one before: small sizes take the path a
/// file rarely takes, where those bytes do not fit the room. For tests and fuzzing.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// use ulog_core::ScanOptions;
/// let mut small = Vec::new();
/// let summary = ulog_core::testing::read_ahead_in(&bytes[..], 5, 2, |r| small.push(r.offset))?;
/// let mut plain = Vec::new();
/// assert_eq!(summary, ulog_core::scan(&bytes, &ScanOptions::default(), |r| plain.push(r.offset))?);
/// assert_eq!(small, plain);
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub fn read_ahead_in<R, F>(
    src: R,
    chunk: usize,
    room: usize,
    mut f: F,
) -> Result<crate::ScanSummary, crate::ReadError>
where
    R: std::io::Read + Send,
    F: FnMut(crate::DataRecord<'_>),
{
    use crate::pass::driver::Driver;
    use crate::pass::visit::Hand;
    let mut driver = Driver::new();
    crate::pass::source::read_ahead_chunks(
        src,
        chunk.max(1),
        room,
        &mut driver,
        &mut |r: crate::DataRecord<'_>| {
            f(r);
            Hand::Next
        },
    )?;
    Ok(driver.summary())
}

/// [`load_columns`](crate::load_columns) of `source` (bytes or a file, read once per
/// thread) on exactly `threads` threads (at least 1; no minimum size per thread),
/// the topics shared by their work in the log's first `sample` bytes (`0`: none,
/// every topic first met after the sample). For tests and fuzzing.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// use ulog_core::{ScanOptions, Source};
/// let shared = ulog_core::testing::load_columns_in(Source::from(&bytes), 2, 100)?;
/// let one = ulog_core::load_columns(&bytes, &ScanOptions::default())?;
/// assert_eq!(shared, one);
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub fn load_columns_in(
    source: crate::Source<'_>,
    threads: usize,
    sample: u64,
) -> Result<crate::columns::LoadedColumns, crate::ReadError> {
    use crate::pass::source::Inner;
    let len = match &source.inner {
        Inner::Bytes(bytes, _) => bytes.len() as u64,
        Inner::File(path) => crate::access::load::file_len(path)?,
        Inner::Parsed(log) => log.data().len() as u64,
        Inner::Reader(_) => u64::MAX,
    };
    match source.inner {
        // A reader is read once, on this thread.
        Inner::Reader(_) => crate::access::load::load_one(source, false, len),
        _ => crate::access::load::load_shared(&source, len, threads.max(1), sample),
    }
}
