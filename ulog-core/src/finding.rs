//! Findings: what the reader stepped over, and why. Returned as data, never printed.

use core::fmt;

/// What the reader found. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum FindingKind {
    /// The header's version is newer than 1; the log was read anyway.
    NewerVersion(u8),
    /// A flag bits message that is not the first message; ignored.
    MisplacedFlagBits,
    /// The flag bits message is longer than 40 bytes; the extra bytes were ignored.
    LongFlagBits(u16),
    /// Compatible flag bits this reader does not know (ignored, as the spec allows).
    UnknownCompatFlags {
        /// Byte index.
        byte: usize,
        /// The unknown bits.
        bits: u8,
    },
    /// An appended offset that points nowhere useful (before the data, or past the end).
    InvalidAppendedOffset(u64),
    /// The DATA_APPENDED bit is set but no offset is.
    AppendedFlagWithoutOffsets,
    /// Appended offsets are set but the DATA_APPENDED bit is not; they were ignored.
    AppendedOffsetsWithoutFlag,
    /// An appended data section starts here.
    AppendedData,
    /// The partial message before an appended offset, dropped (as the spec says).
    PartialBeforeAppended,
    /// The file ends inside a message, which was dropped.
    Truncated,
    /// Bytes that do not frame as messages; skipped up to the next sync magic or valid
    /// header.
    Corrupt(Corruption),
    /// A message type this reader does not know; skipped and kept.
    UnknownMessageType(u8),
    /// A data message for a msg_id with no subscription; skipped.
    UnknownMsgId(u16),
    /// A data message whose size fits neither its format's full size nor the size
    /// without trailing padding. Shorter: skipped, not decoded from garbage. Longer,
    /// and framed by its own size (the messages after it frame cleanly): kept, and
    /// read as its format's first bytes, where the format puts the fields (pyulog 1.3
    /// drops such messages).
    SizeMismatch {
        /// The subscription's msg_id.
        msg_id: u16,
        /// Valid sizes: full, and without trailing padding.
        expected: (usize, usize),
        /// The size found.
        found: usize,
    },
    /// A message too short or malformed for its type; skipped.
    Malformed {
        /// The message type.
        msg_type: u8,
        /// What is wrong with it.
        what: &'static str,
    },
    /// A format definition that does not parse; only that format is lost.
    InvalidFormat(ulog_format::FormatError),
    /// A format that cannot be laid out (unknown nested type, cycle, limits); its topic
    /// is kept but cannot be decoded.
    Layout(ulog_format::LayoutError),
    /// A format defined again with other fields; the later definition is used.
    RedefinedFormat(String),
    /// A subscription to a name no format defines.
    UnknownFormat(String),
    /// An information, parameter or default parameter key that does not parse.
    InvalidKey,
    /// A data message without a usable timestamp field in its format.
    NoTimestamp(String),
}

/// Why bytes were judged corrupt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Corruption {
    /// A message header with size 0.
    ZeroSize,
    /// A header whose type and size frame no plausible message.
    BadHeader,
    /// A run of zero bytes (a zero-filled stretch or tail).
    ZeroFill,
    /// A message that would end past the end of the file, with valid messages after it.
    Overrun,
    /// A data message whose last bytes lie in zero fill (at least a 512-byte sector of
    /// zeros, as an SD card leaves a block it never wrote after a power loss), with the
    /// zeros after it: its header was written, the rest of it was not, so it is not a
    /// row (see the README's section on damaged input for the rule).
    CutByZeroFill,
}

/// Something the reader stepped over: what, where, and how many bytes it covers.
///
/// Repeats are one finding: damaged stretches that follow each other are one stretch,
/// and the same message-level finding met again with no other finding between (the
/// same size mismatch of the same msg_id, say, every message of a topic) is one
/// finding with a [`count`](Finding::count), so that a log damaged the same way a
/// million times gives one line, not a million.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finding {
    /// What.
    pub kind: FindingKind,
    /// Byte offset in the file where it starts (of its first occurrence).
    pub offset: u64,
    /// Number of bytes it covers (skipped or dropped bytes; the message's size for a
    /// skipped message; 0 where no bytes were lost). With a `count` above 1: from the
    /// first occurrence to the end of the last, good messages between included.
    pub len: u64,
    /// How many times it occurred in `offset..offset + len` (1 for most).
    pub count: u64,
}

impl Finding {
    pub(crate) fn new(kind: FindingKind, offset: u64, len: u64) -> Finding {
        Finding {
            kind,
            offset,
            len,
            count: 1,
        }
    }

    /// Takes in the same finding met again at `offset` (`len` bytes), if it repeats
    /// this one (see [`Finding`]); `false` if it is another.
    pub(crate) fn absorb(&mut self, kind: &FindingKind, offset: u64, len: u64) -> bool {
        let end = self.offset + self.len;
        let repeats = self.kind == *kind
            && match kind {
                // Stretches that touch are one stretch.
                FindingKind::Corrupt(_) => offset == end,
                FindingKind::SizeMismatch { .. }
                | FindingKind::UnknownMsgId(_)
                | FindingKind::UnknownMessageType(_)
                | FindingKind::Malformed { .. } => offset >= end,
                _ => false,
            };
        if repeats {
            if !matches!(kind, FindingKind::Corrupt(_)) {
                self.count += 1;
            }
            self.len = offset + len - self.offset;
        }
        repeats
    }

    /// Whether bytes of the file were lost or could not be read as intended
    /// (truncation, corruption, skipped messages), rather than a note about the log.
    pub fn is_damage(&self) -> bool {
        matches!(
            self.kind,
            FindingKind::Truncated
                | FindingKind::Corrupt(_)
                | FindingKind::UnknownMsgId(_)
                | FindingKind::SizeMismatch { .. }
                | FindingKind::Malformed { .. }
                | FindingKind::PartialBeforeAppended
        )
    }
}

fn type_char(t: u8) -> String {
    if t.is_ascii_graphic() {
        format!("'{}'", t as char)
    } else {
        format!("{t:#04x}")
    }
}

impl Finding {
    /// What was found, without the `at byte N` that its `Display` ends with: for output
    /// that shows the offset in a column of its own.
    ///
    /// ```
    /// let bytes = [&ulog_core::testing::sample_log()[..], &[9, 0, b'D', 1]].concat();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let cut = &log.findings()[0];
    /// assert_eq!(format!("{cut}"), format!("{} at byte {}", cut.what(), cut.offset));
    /// ```
    pub fn what(&self) -> String {
        struct What<'a>(&'a Finding);
        impl fmt::Display for What<'_> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.describe(f)?;
                let w = self.0;
                if w.count > 1 {
                    write!(f, " ({} times, up to byte {})", w.count, w.offset + w.len)?;
                }
                Ok(())
            }
        }
        What(self).to_string()
    }

    fn describe(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let end = self.offset + self.len;
        match &self.kind {
            FindingKind::NewerVersion(v) => write!(f, "file version {v} is newer than 1"),
            FindingKind::MisplacedFlagBits => write!(f, "flag bits message not first; ignored"),
            FindingKind::LongFlagBits(n) => {
                write!(f, "flag bits message of {n} bytes; bytes after 40 ignored")
            }
            FindingKind::UnknownCompatFlags { byte, bits } => {
                write!(
                    f,
                    "unknown compatible flag bits {bits:#04x} in compat_flags[{byte}]"
                )
            }
            FindingKind::InvalidAppendedOffset(o) => write!(f, "invalid appended offset {o}"),
            FindingKind::AppendedFlagWithoutOffsets => {
                write!(f, "DATA_APPENDED flag set but no appended offset")
            }
            FindingKind::AppendedOffsetsWithoutFlag => {
                write!(
                    f,
                    "appended offsets set without the DATA_APPENDED flag; ignored"
                )
            }
            FindingKind::AppendedData => write!(f, "appended data starts"),
            FindingKind::PartialBeforeAppended => {
                write!(
                    f,
                    "partial message before appended data dropped (bytes {}..{end})",
                    self.offset
                )
            }
            FindingKind::Truncated => write!(
                f,
                "file ends inside a message; its {} bytes were dropped",
                self.len
            ),
            FindingKind::Corrupt(c) => {
                let why = match c {
                    Corruption::ZeroSize => "zero-size message header",
                    Corruption::BadHeader => "invalid message header",
                    Corruption::ZeroFill => "zero-filled bytes",
                    Corruption::Overrun => "message overruns the file",
                    Corruption::CutByZeroFill => "data message cut off by zero-filled bytes",
                };
                write!(
                    f,
                    "corruption ({why}): skipped bytes {}..{end} ({} bytes)",
                    self.offset, self.len
                )
            }
            FindingKind::UnknownMessageType(t) => {
                write!(
                    f,
                    "unknown message type {} ({} bytes) skipped",
                    type_char(*t),
                    self.len
                )
            }
            FindingKind::UnknownMsgId(id) => {
                write!(
                    f,
                    "data message for msg_id {id}, which has no subscription; skipped"
                )
            }
            FindingKind::SizeMismatch {
                msg_id,
                expected,
                found,
            } => {
                write!(
                    f,
                    "data message for msg_id {msg_id} has {found} bytes, its format "
                )?;
                if expected.0 == expected.1 {
                    write!(f, "needs {}", expected.0)?;
                } else {
                    write!(f, "needs {} or {}", expected.0, expected.1)?;
                }
                if *found > expected.0 {
                    f.write_str("; kept, read as its format's first bytes")
                } else {
                    f.write_str("; skipped")
                }
            }
            FindingKind::Malformed { msg_type, what } => {
                write!(
                    f,
                    "malformed {} message: {what}; skipped",
                    type_char(*msg_type)
                )
            }
            FindingKind::InvalidFormat(e) => write!(f, "invalid format definition: {e}"),
            FindingKind::Layout(e) => write!(f, "{e}"),
            FindingKind::RedefinedFormat(n) => {
                write!(
                    f,
                    "format `{n}` redefined with other fields; the later one is used"
                )
            }
            FindingKind::UnknownFormat(n) => write!(f, "subscription to undefined format `{n}`"),
            FindingKind::InvalidKey => write!(f, "key that does not parse as `type name`"),
            FindingKind::NoTimestamp(n) => write!(f, "topic `{n}` has no timestamp field"),
        }
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} at byte {}", self.what(), self.offset)
    }
}
