//! How a topic's name becomes part of a file or folder name: the one rule of the
//! CSV files (`ulog csv`), a log's Parquet files (`<topic>_<multi_id>.parquet`) and a
//! dataset's topic folders (`<topic>/<log_id>.parquet`).
//!
//! A ULog topic name may hold any text; file systems refuse or fold some: Windows
//! refuses `<>:"/\|?*` and control characters, a name ending in a dot or a space, and
//! the device names `CON`, `PRN`, `AUX`, `NUL`, `COM0`–`COM9`, `LPT0`–`LPT9` (in any
//! case); Windows and macOS do not tell names apart that differ only in case; most
//! file systems take at most 255 bytes per name; macOS stores Unicode names in another
//! normal form, so that two byte sequences may name one file. So:
//!
//! - A name of ASCII letters, digits, `_` and `-` only, of at most
//!   [`PLAIN_MAX`] bytes, and not a device name, is used as it is (every PX4 topic:
//!   the files keep pyulog's names);
//! - any other name is *escaped*: each character outside that set becomes `_`, the
//!   result is cut to its first [`KEPT`] bytes, and `~` and 16 hex digits of a hash of
//!   the whole name ([`hash`]) are added (`vehicle/status` →
//!   `vehicle_status~…`, `CON` → `CON~…`). No plain name holds a `~`, so an escaped
//!   name never takes a plain one's place, and two names escaped alike differ in
//!   their hashes;
//! - where names that differ only in case would meet: a dataset's folders hold the
//!   topics of every log it will ever have, so a folder name ([`folder_name`]) escapes
//!   every name with an upper-case letter; a log's own files ([`LogNames`]) escape
//!   only the names that another topic of the log differs from in case alone.
//!
//! The topic's real name stays with its data: in a Parquet file's key-value metadata
//! (`ulog.topic`), and in a CSV file's name only as escaped.
//!
//! ```
//! use ulog_core::naming::{folder_name, LogNames};
//! assert_eq!(folder_name("vehicle_status"), "vehicle_status");
//! assert!(folder_name("CON").starts_with("CON~"));
//! assert!(folder_name("Foo").starts_with("Foo~"));
//! let names = LogNames::new(["Foo", "foo", "Bar"]);
//! assert_eq!(names.file_part("Bar"), "Bar");
//! assert_ne!(names.file_part("Foo").to_lowercase(), names.file_part("foo").to_lowercase());
//! ```

use std::borrow::Cow;
use std::collections::HashMap;

/// The longest name used as it is, in bytes: the file names add the log's name,
/// `_<multi_id>.parquet` or `.csv`, and the temporary suffix of a file being written,
/// within the 255 bytes of most file systems.
pub const PLAIN_MAX: usize = 160;

/// The bytes of an escaped name kept before its hash.
pub const KEPT: usize = 96;

/// Windows's device names, refused as a file or folder name (with any extension).
const DEVICES: [&str; 4] = ["CON", "PRN", "AUX", "NUL"];

/// Whether `c` may stand in a name used as it is; `fold`: only lower case.
fn plain_char(c: char, fold: bool) -> bool {
    c.is_ascii_lowercase()
        || c.is_ascii_digit()
        || c == '_'
        || c == '-'
        || (!fold && c.is_ascii_uppercase())
}

/// Whether `name` is one of Windows's device names (`CON`, `com1`, `Lpt9`…).
fn is_device(name: &str) -> bool {
    let upper = name.to_ascii_uppercase();
    DEVICES.contains(&upper.as_str())
        || (upper.len() == 4
            && (upper.starts_with("COM") || upper.starts_with("LPT"))
            && upper.as_bytes()[3].is_ascii_digit())
}

/// Whether `name` is used as it is (case folded too when `fold`).
fn is_plain(name: &str, fold: bool) -> bool {
    !name.is_empty()
        && name.len() <= PLAIN_MAX
        && name.chars().all(|c| plain_char(c, fold))
        && !is_device(name)
}

/// The 64-bit FNV-1a hash of `bytes`, which an escaped name ends with (in 16 hex
/// digits): stable across versions and platforms, so that a topic has one folder in
/// a dataset whatever wrote it.
pub fn hash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// `name` escaped: its characters outside the plain set `_`, cut to [`KEPT`] bytes,
/// then `~` and its hash.
fn escaped(name: &str) -> String {
    let mut out = String::with_capacity(KEPT + 17);
    for c in name.chars() {
        if out.len() >= KEPT {
            break;
        }
        out.push(if plain_char(c, false) { c } else { '_' });
    }
    out.push_str(&format!("~{:016x}", hash(name.as_bytes())));
    out
}

/// The name of a dataset's folder for topic `name`: the name itself when it is plain
/// and has no upper-case letter, else escaped (see the [module docs](self)). A name
/// that starts with `_` is escaped and starts with `t`: query engines skip folders
/// whose names start with `_` (and a dataset keeps its own there: `_schemas`).
///
/// ```
/// use ulog_core::naming::folder_name;
/// assert!(folder_name("_private").starts_with("t_private~"));
/// ```
pub fn folder_name(name: &str) -> Cow<'_, str> {
    if is_plain(name, true) && !name.starts_with('_') {
        Cow::Borrowed(name)
    } else {
        let escaped = escaped(name);
        match escaped.starts_with('_') {
            true => Cow::Owned(format!("t{escaped}")),
            false => Cow::Owned(escaped),
        }
    }
}

/// The names of one log's topics in its own files (a log's Parquet files, its CSV
/// files): each plain name as it is, unless another topic of the log has the same
/// name but for case; every other name escaped.
#[derive(Debug, Clone, Default)]
pub struct LogNames {
    /// Per name in lower case, how many distinct names of the log fold to it.
    folded: HashMap<String, usize>,
}

impl LogNames {
    /// The names of a log's topics (each once or more).
    pub fn new<'n>(names: impl IntoIterator<Item = &'n str>) -> LogNames {
        let mut distinct: Vec<&str> = names.into_iter().collect();
        distinct.sort_unstable();
        distinct.dedup();
        let mut folded = HashMap::new();
        for n in distinct {
            *folded.entry(n.to_ascii_lowercase()).or_insert(0) += 1;
        }
        LogNames { folded }
    }

    /// The part of a file name that stands for topic `name`.
    pub fn file_part<'n>(&self, name: &'n str) -> Cow<'n, str> {
        let alone = self
            .folded
            .get(&name.to_ascii_lowercase())
            .map_or(true, |&n| n <= 1);
        if is_plain(name, false) && (alone || is_plain(name, true)) {
            Cow::Borrowed(name)
        } else {
            Cow::Owned(escaped(name))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names as Windows and macOS compare them: case folded.
    fn folded(s: &str) -> String {
        s.to_lowercase()
    }

    /// Whether `part` is a valid file name on every common file system.
    fn valid(part: &str) -> bool {
        !part.is_empty()
            && part.len() <= 255 - 40
            && part.is_ascii()
            && !part
                .chars()
                .any(|c| c.is_control() || r#"<>:"/\|?*"#.contains(c))
            && !part.ends_with(['.', ' '])
            && !is_device(part.split('.').next().unwrap_or(""))
    }

    #[test]
    fn plain_names_stay_and_others_are_escaped_valid_and_distinct() {
        let long = "x".repeat(300);
        let names = [
            "vehicle_status",
            "sensor_gps",
            "esc-status",
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
            "a<b>c:d\"e\\f|g?h*",
            "tab\there",
            "\u{1}ctl",
            "dot.",
            "space ",
            "é",
            "e\u{301}",
            &long,
            &long[..299],
            "",
        ];
        for n in ["vehicle_status", "sensor_gps", "esc-status", "foo", "a_b"] {
            assert_eq!(folder_name(n), n);
        }
        let folders: Vec<Cow<'_, str>> = names.iter().map(|n| folder_name(n)).collect();
        let mut seen = std::collections::HashSet::new();
        for (n, f) in names.iter().zip(&folders) {
            assert!(valid(f), "{n:?} -> {f:?}");
            assert!(seen.insert(folded(f)), "{n:?} -> {f:?} meets another");
        }
        assert!(folders[4].starts_with("aux~"), "{}", folders[4]);
        assert_eq!(folders[20].len(), KEPT + 17);

        // A log's files: plain names stay, case variants of one another do not.
        let log = LogNames::new(names.iter().copied());
        let parts: Vec<Cow<'_, str>> = names.iter().map(|n| log.file_part(n)).collect();
        let mut seen = std::collections::HashSet::new();
        for (n, p) in names.iter().zip(&parts) {
            assert!(valid(p), "{n:?} -> {p:?}");
            assert!(seen.insert(folded(p)), "{n:?} -> {p:?} meets another");
        }
        assert_eq!(parts[2], "esc-status");
        assert_eq!(parts[10], "foo", "the lower-case one keeps its name");
        assert!(parts[9].starts_with("Foo~"));
        let alone = LogNames::new(["Foo", "bar"]);
        assert_eq!(alone.file_part("Foo"), "Foo", "no other name folds to it");
    }

    #[test]
    fn the_hash_is_fnv_1a() {
        // The published FNV-1a 64 values.
        assert_eq!(hash(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(hash(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(hash(b"foobar"), 0x8594_4171_f739_67e8);
    }
}
