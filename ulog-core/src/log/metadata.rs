//! What a log holds besides topic data: multi-information, parameter changes and
//! defaults, dropouts, messages of unknown types, release versions.

use crate::log::message::KeyValue;

/// A multi-information key with its entries: each entry is the list of parts that
/// `is_continued` joined, in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiInfo<'a> {
    /// The key's name.
    pub name: String,
    /// The entries, each a list of continued parts.
    pub entries: Vec<Vec<KeyValue<'a>>>,
}

/// A parameter change in the data section.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamChange<'a> {
    /// The latest data timestamp seen before the change (as pyulog reports it).
    pub timestamp: u64,
    /// Byte offset of the message.
    pub offset: u64,
    /// The parameter and its new value.
    pub kv: KeyValue<'a>,
}

/// A default parameter (`Q`).
#[derive(Debug, Clone, PartialEq)]
pub struct DefaultParam<'a> {
    /// Bit 0: system-wide default; bit 1: default of the current configuration.
    pub default_types: u8,
    /// Byte offset of the message.
    pub offset: u64,
    /// The parameter and its default value.
    pub kv: KeyValue<'a>,
}

/// A dropout (`O`): logging data lost for `duration_ms`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dropout {
    /// Byte offset of the message.
    pub offset: u64,
    /// The latest data timestamp seen before the dropout.
    pub timestamp: u64,
    /// Duration in milliseconds.
    pub duration_ms: u16,
}

/// A message of a type this reader does not know, kept as it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownMessage<'a> {
    /// Byte offset of the message.
    pub offset: u64,
    /// The type byte.
    pub msg_type: u8,
    /// The payload.
    pub payload: &'a [u8],
}

/// Software or OS version decoded from `ver_sw_release` / `ver_os_release`
/// (`0xAABBCCTT`: major, minor, patch, type).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReleaseVersion {
    /// Major version.
    pub major: u8,
    /// Minor version.
    pub minor: u8,
    /// Patch version.
    pub patch: u8,
    /// Type byte: < 64 development, < 128 alpha, < 192 beta, < 255 RC, 255 release.
    pub kind: u8,
}

impl ReleaseVersion {
    /// Decodes the packed `0xAABBCCTT` form.
    pub fn from_packed(v: u32) -> ReleaseVersion {
        let [major, minor, patch, kind] = v.to_be_bytes();
        ReleaseVersion {
            major,
            minor,
            patch,
            kind,
        }
    }

    /// `development`, `alpha`, `beta`, `rc` or `release`.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            0..=63 => "development",
            64..=127 => "alpha",
            128..=191 => "beta",
            192..=254 => "rc",
            255 => "release",
        }
    }
}

impl core::fmt::Display for ReleaseVersion {
    /// As pyulog: `v1.4.2`, `v1.4.2 (RC)`; development versions too (`(dev)`).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "v{}.{}.{}", self.major, self.minor, self.patch)?;
        match self.kind {
            0..=63 => write!(f, " (dev)"),
            64..=127 => write!(f, " (alpha)"),
            128..=191 => write!(f, " (beta)"),
            192..=254 => write!(f, " (RC)"),
            255 => Ok(()),
        }
    }
}
