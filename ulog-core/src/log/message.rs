//! Borrowed views of the messages of a ULog file, one variant per message type.

use ulog_format::{parse_key_as_written, Field, TypeName};

use crate::bytes::{u16_at, u64_at};
use crate::framing::{FlagBits, Record};
use crate::value::{LogText, Value};

/// A `type name` key with its value bytes: the body of information (`I`),
/// multi-information (`M`), parameter (`P`) and default parameter (`Q`) messages.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyValue<'a> {
    /// The key as logged, e.g. `char[3] sys_name` (lossy if not UTF-8).
    pub key: LogText<'a>,
    /// The key parsed as a field, when it parses.
    pub field: Option<Field>,
    /// The value bytes.
    pub raw: &'a [u8],
}

impl<'a> KeyValue<'a> {
    pub(crate) fn parse(key: &'a [u8], raw: &'a [u8]) -> KeyValue<'a> {
        let field = core::str::from_utf8(key)
            .ok()
            .and_then(|k| parse_key_as_written(k).ok());
        KeyValue {
            key: LogText(key),
            field,
            raw,
        }
    }

    /// The name part of the key (`sys_name`, `Build Date`); the whole key if it does not
    /// parse.
    pub fn name(&self) -> std::borrow::Cow<'a, str> {
        match &self.field {
            Some(f) => std::borrow::Cow::Owned(f.name.clone()),
            None => self.key.to_string_lossy(),
        }
    }

    /// The value, decoded by the type in the key: every basic type, arrays, and
    /// `char[N]` strings. A key that does not parse or names a nested type gives
    /// [`Value::Bytes`].
    pub fn value(&self) -> Value<'a> {
        match &self.field {
            Some(Field {
                ty: TypeName::Basic(b),
                array_len,
                ..
            }) => Value::decode(*b, *array_len, self.raw),
            _ => Value::Bytes(self.raw),
        }
    }
}

/// The level of a logged string, as in the Linux kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LogLevel {
    /// 0: system is unusable
    Emergency,
    /// 1: action must be taken immediately
    Alert,
    /// 2: critical conditions
    Critical,
    /// 3: error conditions
    Error,
    /// 4: warning conditions
    Warning,
    /// 5: normal but significant condition
    Notice,
    /// 6: informational
    Info,
    /// 7: debug-level messages
    Debug,
}

impl LogLevel {
    /// The level of a raw level byte: PX4 writes ASCII `'0'`–`'7'`; `0`–`7` is accepted
    /// too.
    pub fn from_raw(raw: u8) -> Option<LogLevel> {
        let n = if raw >= b'0' { raw - b'0' } else { raw };
        Some(match n {
            0 => LogLevel::Emergency,
            1 => LogLevel::Alert,
            2 => LogLevel::Critical,
            3 => LogLevel::Error,
            4 => LogLevel::Warning,
            5 => LogLevel::Notice,
            6 => LogLevel::Info,
            7 => LogLevel::Debug,
            _ => return None,
        })
    }

    /// The name pyulog's `ulog_messages` prints (`EMERGENCY` … `DEBUG`).
    pub fn name(self) -> &'static str {
        match self {
            LogLevel::Emergency => "EMERGENCY",
            LogLevel::Alert => "ALERT",
            LogLevel::Critical => "CRITICAL",
            LogLevel::Error => "ERROR",
            LogLevel::Warning => "WARNING",
            LogLevel::Notice => "NOTICE",
            LogLevel::Info => "INFO",
            LogLevel::Debug => "DEBUG",
        }
    }
}

/// A logged string (`L`), or a tagged logged string (`C`) when `tag` is set: the
/// spec's names for the text messages PX4 logs (`[commander] Takeoff detected`).
#[derive(Debug, Clone, PartialEq)]
pub struct LoggedString<'a> {
    /// Byte offset of the message in the file.
    pub offset: u64,
    /// The level byte as logged (see [`LoggedString::level`]).
    pub raw_level: u8,
    /// The tag of a tagged message.
    pub tag: Option<u16>,
    /// Microseconds.
    pub timestamp: u64,
    /// The text as logged.
    pub text: LogText<'a>,
}

impl LoggedString<'_> {
    /// The level, if the byte is a valid level.
    pub fn level(&self) -> Option<LogLevel> {
        LogLevel::from_raw(self.raw_level)
    }
}

/// One message of a ULog file, borrowed from the file's bytes.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Message<'a> {
    /// `B`: flag bits.
    FlagBits(FlagBits),
    /// `F`: a format definition (its text).
    Format(LogText<'a>),
    /// `I`: information.
    Info(KeyValue<'a>),
    /// `M`: multi-information; `continued` joins it to the previous one of its key.
    MultiInfo {
        /// Whether this part continues the previous entry with the same key.
        continued: bool,
        /// Key and value.
        kv: KeyValue<'a>,
    },
    /// `P`: a parameter (initial, or a change when in the data section).
    Param(KeyValue<'a>),
    /// `Q`: a default parameter.
    DefaultParam {
        /// Bit 0: system-wide default; bit 1: default of the current configuration.
        default_types: u8,
        /// Key and value.
        kv: KeyValue<'a>,
    },
    /// `A`: subscription.
    Subscribe {
        /// Instance of the topic.
        multi_id: u8,
        /// Id used by the data messages.
        msg_id: u16,
        /// Format name.
        name: LogText<'a>,
    },
    /// `R`: unsubscription.
    Unsubscribe {
        /// The msg_id that ends.
        msg_id: u16,
    },
    /// `D`: logged data.
    Data {
        /// Subscription id.
        msg_id: u16,
        /// The payload, as laid out by the subscription's format.
        payload: &'a [u8],
    },
    /// `L` or `C`: a logged string.
    Log(LoggedString<'a>),
    /// `S`: synchronisation.
    Sync(&'a [u8]),
    /// `O`: a dropout of `duration_ms` milliseconds.
    Dropout {
        /// Lost logging time in milliseconds.
        duration_ms: u16,
    },
    /// A message type this reader does not know, kept as it was.
    Unknown {
        /// The type byte.
        msg_type: u8,
        /// Its payload.
        payload: &'a [u8],
    },
}

impl<'a> Message<'a> {
    /// Views a framed record. Framing has checked the minimum sizes, so slicing here
    /// cannot fail.
    pub(crate) fn from_record(
        r: &Record,
        payload: &'a [u8],
        flag_bits: Option<FlagBits>,
    ) -> Message<'a> {
        let p = payload;
        if r.unknown {
            return Message::Unknown {
                msg_type: r.msg_type,
                payload: p,
            };
        }
        match r.msg_type {
            b'B' => Message::FlagBits(flag_bits.unwrap_or(FlagBits {
                compat_flags: p[0..8].try_into().expect("8 bytes"),
                incompat_flags: p[8..16].try_into().expect("8 bytes"),
                appended_offsets: [u64_at(p, 16), u64_at(p, 24), u64_at(p, 32)],
            })),
            b'F' => Message::Format(LogText(p)),
            b'I' => Message::Info(kv(&p[1..], p[0])),
            b'P' => Message::Param(kv(&p[1..], p[0])),
            b'M' => Message::MultiInfo {
                continued: p[0] != 0,
                kv: kv(&p[2..], p[1]),
            },
            b'Q' => Message::DefaultParam {
                default_types: p[0],
                kv: kv(&p[2..], p[1]),
            },
            b'A' => Message::Subscribe {
                multi_id: p[0],
                msg_id: u16_at(p, 1),
                name: LogText(&p[3..]),
            },
            b'R' => Message::Unsubscribe {
                msg_id: u16_at(p, 0),
            },
            b'D' => Message::Data {
                msg_id: u16_at(p, 0),
                payload: &p[2..],
            },
            b'L' => Message::Log(LoggedString {
                offset: r.offset,
                raw_level: p[0],
                tag: None,
                timestamp: u64_at(p, 1),
                text: LogText(&p[9..]),
            }),
            b'C' => Message::Log(LoggedString {
                offset: r.offset,
                raw_level: p[0],
                tag: Some(u16_at(p, 1)),
                timestamp: u64_at(p, 3),
                text: LogText(&p[11..]),
            }),
            b'S' => Message::Sync(p),
            b'O' => Message::Dropout {
                duration_ms: u16_at(p, 0),
            },
            t => Message::Unknown {
                msg_type: t,
                payload: p,
            },
        }
    }

    /// The message type byte (`b'D'`, …).
    pub fn msg_type(&self) -> u8 {
        match self {
            Message::FlagBits(_) => b'B',
            Message::Format(_) => b'F',
            Message::Info(_) => b'I',
            Message::MultiInfo { .. } => b'M',
            Message::Param(_) => b'P',
            Message::DefaultParam { .. } => b'Q',
            Message::Subscribe { .. } => b'A',
            Message::Unsubscribe { .. } => b'R',
            Message::Data { .. } => b'D',
            Message::Log(l) if l.tag.is_some() => b'C',
            Message::Log(_) => b'L',
            Message::Sync(_) => b'S',
            Message::Dropout { .. } => b'O',
            Message::Unknown { msg_type, .. } => *msg_type,
        }
    }
}

fn kv(body: &[u8], key_len: u8) -> KeyValue<'_> {
    let k = key_len as usize;
    KeyValue::parse(&body[..k], &body[k..])
}
