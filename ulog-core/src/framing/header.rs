//! The file header and the flag bits message, and what a file that is not ULog
//! looks like.

use crate::bytes::{u64_at, HEADER_SIZE, MAGIC};
use crate::error::{ReadError, ReadErrorKind};
use crate::finding::FindingKind;

use super::{Framer, Phase, Record, Step};

/// The file header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// File format version (0 or 1 today).
    pub version: u8,
    /// When logging started, in microseconds.
    pub timestamp: u64,
}

/// The flag bits message (`B`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FlagBits {
    /// Compatible flags; bit 0 of byte 0 is DEFAULT_PARAMETERS.
    pub compat_flags: [u8; 8],
    /// Incompatible flags; bit 0 of byte 0 is DATA_APPENDED.
    pub incompat_flags: [u8; 8],
    /// File offsets of appended data (0 where unused).
    pub appended_offsets: [u64; 3],
}

impl FlagBits {
    /// Whether the DEFAULT_PARAMETERS compatible flag is set.
    pub fn has_default_parameters(&self) -> bool {
        self.compat_flags[0] & 1 != 0
    }

    /// Whether the DATA_APPENDED incompatible flag is set.
    pub fn has_data_appended(&self) -> bool {
        self.incompat_flags[0] & 1 != 0
    }
}

impl Framer {
    pub(super) fn read_header(&mut self, win: &[u8], eof: bool) -> Result<Option<Step>, ReadError> {
        if win.len() < HEADER_SIZE {
            if !eof {
                return Ok(Some(Step::NeedMore));
            }
            if win.is_empty() {
                return Err(ReadError::new(ReadErrorKind::Empty, None));
            }
            if MAGIC.starts_with(&win[..win.len().min(7)]) {
                let len = win.len() as u64;
                return Err(ReadError::new(
                    ReadErrorKind::TruncatedHeader { len },
                    Some(len),
                ));
            }
            let found = describe_non_ulog(win);
            return Err(ReadError::new(ReadErrorKind::NotULog { found }, Some(0)));
        }
        if win[..7] != MAGIC {
            let found = describe_non_ulog(win);
            return Err(ReadError::new(ReadErrorKind::NotULog { found }, Some(0)));
        }
        let header = Header {
            version: win[7],
            timestamp: u64_at(win, 8),
        };
        if header.version > 1 {
            self.finding(FindingKind::NewerVersion(header.version), 7, 0);
        }
        self.header = Some(header);
        self.pos = HEADER_SIZE as u64;
        self.phase = Phase::First;
        Ok(None)
    }

    pub(super) fn flag_bits(&mut self, record: Record, p: &[u8]) -> Result<(), ReadError> {
        let mut fb = FlagBits {
            compat_flags: [0; 8],
            incompat_flags: [0; 8],
            appended_offsets: [0; 3],
        };
        fb.compat_flags.copy_from_slice(&p[0..8]);
        fb.incompat_flags.copy_from_slice(&p[8..16]);
        for (i, o) in fb.appended_offsets.iter_mut().enumerate() {
            *o = u64_at(p, 16 + 8 * i);
        }
        let at = record.offset + 3;
        for (byte, &bits) in fb.incompat_flags.iter().enumerate() {
            let unknown = if byte == 0 { bits & !1 } else { bits };
            if unknown != 0 {
                let kind = ReadErrorKind::UnknownIncompatFlags {
                    byte,
                    bits: unknown,
                };
                return Err(ReadError::new(kind, Some(at + 8 + byte as u64)));
            }
        }
        for (byte, &bits) in fb.compat_flags.iter().enumerate() {
            let unknown = if byte == 0 { bits & !1 } else { bits };
            if unknown != 0 {
                self.finding(
                    FindingKind::UnknownCompatFlags {
                        byte,
                        bits: unknown,
                    },
                    at + byte as u64,
                    0,
                );
            }
        }
        if record.size > 40 {
            self.finding(FindingKind::LongFlagBits(record.size), record.offset, 0);
        }
        let offsets: Vec<u64> = fb
            .appended_offsets
            .iter()
            .copied()
            .filter(|&o| o != 0)
            .collect();
        if fb.has_data_appended() {
            if offsets.is_empty() {
                self.finding(FindingKind::AppendedFlagWithoutOffsets, at + 8, 0);
            }
            let mut valid: Vec<u64> = Vec::new();
            for o in offsets {
                if o < record.end() {
                    self.finding(FindingKind::InvalidAppendedOffset(o), at + 16, 0);
                } else if !valid.contains(&o) {
                    valid.push(o);
                }
            }
            valid.sort_unstable();
            self.appended = valid;
            self.appended_field = at + 16;
        } else if !offsets.is_empty() {
            self.finding(FindingKind::AppendedOffsetsWithoutFlag, at + 16, 0);
        }
        self.flag_bits = Some(fb);
        Ok(())
    }
}

/// What a file that is not ULog looks like, for the error message.
pub(crate) fn describe_non_ulog(bytes: &[u8]) -> String {
    let head = &bytes[..bytes.len().min(16)];
    let known: &[(&[u8], &str)] = &[
        (b"\x1f\x8b", "a gzip file"),
        (b"PK\x03\x04", "a zip file"),
        (b"BZh", "a bzip2 file"),
        (b"\xfd7zXZ", "an xz file"),
        (b"\x28\xb5\x2f\xfd", "a zstd file"),
        (b"\x89PNG", "a PNG image"),
        (b"%PDF", "a PDF document"),
        (b"#ROSBAG", "a ROS bag"),
        (b"SQLite format", "an SQLite database"),
        (b"\xa3\x95\x80\x80", "a PX4 sdlog2 (.px4log) file"),
        (b"\xa3\x95", "an APM/PX4 DataFlash log"),
        (b"ULog", "a ULog magic with wrong trailing bytes"),
    ];
    // Only the first 16 bytes are looked at, so that the whole-file and the
    // incremental reader describe a file the same way.
    if head.iter().all(|&b| b == 0) {
        return "zero bytes where the header should be".to_owned();
    }
    for (magic, what) in known {
        if head.starts_with(magic) {
            return (*what).to_owned();
        }
    }
    let text = head
        .iter()
        .all(|b| b.is_ascii_graphic() || b.is_ascii_whitespace());
    let hex: Vec<String> = head.iter().take(8).map(|b| format!("{b:02x}")).collect();
    if text {
        format!(
            "text ({:?}…)",
            String::from_utf8_lossy(&head[..head.len().min(12)])
        )
    } else {
        format!("bytes {}", hex.join(" "))
    }
}
