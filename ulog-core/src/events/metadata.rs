//! [`Metadata`]: PX4's event definitions (the JSON of its events library), as a log
//! embeds them (multi-information `metadata_events`, xz-compressed, its SHA-256 in
//! the information `metadata_events_sha256`) or as a file the user has.

use std::collections::HashMap;
use std::fmt;

use serde_json::Value as Json;
use sha2::{Digest, Sha256};

use crate::log::ulog::ULog;

/// The xz container's magic bytes.
const XZ_MAGIC: &[u8] = &[0xFD, b'7', b'z', b'X', b'Z', 0x00];

/// Event definitions: by component (the top 8 bits of an event id), the events of
/// each group by their 24-bit sub-id, and the enums their arguments use.
#[derive(Debug, Clone, Default)]
pub struct Metadata {
    pub(crate) components: HashMap<u8, Component>,
    /// Every enum by `namespace::name` (a later component's of the same name
    /// replaces an earlier one's, as PX4's library reads them).
    pub(crate) enums: HashMap<String, EnumDef>,
}

#[derive(Debug, Clone, Default)]
pub(crate) struct Component {
    pub namespace: String,
    /// Groups in the file's order, each with its events.
    pub groups: Vec<(String, HashMap<u32, Definition>)>,
}

/// One event's definition.
#[derive(Debug, Clone, Default)]
pub(crate) struct Definition {
    pub name: String,
    pub message: String,
    pub description: Option<String>,
    /// Argument types as written (a basic type, or an enum's name).
    pub arguments: Vec<String>,
}

/// An enum or bitfield that arguments may be of.
#[derive(Debug, Clone, Default)]
pub(crate) struct EnumDef {
    /// Its basic type.
    pub ty: String,
    pub is_bitfield: bool,
    pub separator: String,
    /// (value, description), in the file's order.
    pub entries: Vec<(u64, String)>,
}

/// What is wrong with event metadata.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum MetadataError {
    /// The embedded bytes' SHA-256 is not the one the log gives
    /// (`metadata_events_sha256`).
    HashMismatch {
        /// The hash the log gives.
        expected: String,
        /// The hash of the bytes.
        found: String,
    },
    /// The xz stream does not decompress.
    Xz(String),
    /// The JSON does not parse.
    Json(String),
    /// The JSON parses, but is not event metadata: what is missing or wrong.
    Shape(String),
}

impl fmt::Display for MetadataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetadataError::HashMismatch { expected, found } => write!(
                f,
                "the embedded event metadata has SHA-256 {found}, the log says {expected}"
            ),
            MetadataError::Xz(e) => write!(f, "the event metadata does not decompress (xz): {e}"),
            MetadataError::Json(e) => write!(f, "the event metadata is not JSON: {e}"),
            MetadataError::Shape(e) => write!(f, "the event metadata is not PX4 events JSON: {e}"),
        }
    }
}

impl std::error::Error for MetadataError {}

impl Metadata {
    /// The metadata `log` embeds: `None` when it has none (no `metadata_events`),
    /// an error when it is there but cannot be used (its hash, its compression, its
    /// JSON).
    pub fn from_log(log: &ULog<'_>) -> Option<Result<Metadata, MetadataError>> {
        let multi = log
            .multi_info()
            .iter()
            .find(|m| m.name == "metadata_events")?;
        let first = multi.entries.first()?;
        let bytes: Vec<u8> = first.iter().flat_map(|kv| kv.raw.iter().copied()).collect();
        if let Some(expected) = log.info_value("metadata_events_sha256") {
            let expected = expected.to_string();
            let found = hex(&Sha256::digest(&bytes));
            if !expected.eq_ignore_ascii_case(&found) {
                return Some(Err(MetadataError::HashMismatch { expected, found }));
            }
        }
        Some(Metadata::from_bytes(&bytes))
    }

    /// Metadata from a file's bytes: JSON, or JSON compressed with xz (as PX4's
    /// build writes `all_events.json.xz`).
    pub fn from_bytes(bytes: &[u8]) -> Result<Metadata, MetadataError> {
        if bytes.starts_with(XZ_MAGIC) {
            let mut json = Vec::new();
            lzma_rs::xz_decompress(&mut &bytes[..], &mut json)
                .map_err(|e| MetadataError::Xz(e.to_string()))?;
            return Metadata::from_json(&json);
        }
        Metadata::from_json(bytes)
    }

    /// Metadata from JSON text.
    pub fn from_json(bytes: &[u8]) -> Result<Metadata, MetadataError> {
        let json: Json =
            serde_json::from_slice(bytes).map_err(|e| MetadataError::Json(e.to_string()))?;
        parse(&json).map_err(MetadataError::Shape)
    }

    /// How many events are defined.
    pub fn len(&self) -> usize {
        self.components
            .values()
            .flat_map(|c| c.groups.iter())
            .map(|(_, g)| g.len())
            .sum()
    }

    /// Whether no event is defined.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The definition of event `id`: its component, group name and definition.
    pub(crate) fn find(&self, id: u32) -> Option<(&Component, &str, &Definition)> {
        let component = self.components.get(&((id >> 24) as u8))?;
        let sub = id & 0x00FF_FFFF;
        component
            .groups
            .iter()
            .find_map(|(name, events)| events.get(&sub).map(|d| (component, name.as_str(), d)))
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Reads the metadata's JSON. As PX4's library, an entry that is not as expected (a
/// component id that is not a number, an event without a message, an enum entry
/// whose value is not a number) is passed over, not the whole file: its events then
/// show as undefined.
fn parse(json: &Json) -> Result<Metadata, String> {
    let version = json.get("version").and_then(Json::as_f64).unwrap_or(0.0);
    if version < 1.0 {
        return Err(format!("version {version} (1 or more expected)"));
    }
    let mut metadata = Metadata::default();
    let Some(components) = json.get("components") else {
        return Ok(metadata);
    };
    let components = components
        .as_object()
        .ok_or("`components` is not an object")?;
    for (id, c) in components {
        let Ok(id) = id.trim().parse::<u8>() else {
            continue;
        };
        let Some(namespace) = c.get("namespace").and_then(Json::as_str) else {
            continue;
        };
        let mut component = Component {
            namespace: namespace.to_owned(),
            ..Component::default()
        };
        if let Some(groups) = c.get("event_groups").and_then(Json::as_object) {
            for (group, g) in groups {
                let mut events = HashMap::new();
                if let Some(list) = g.get("events").and_then(Json::as_object) {
                    for (sub, e) in list {
                        if let (Ok(sub), Some(def)) = (sub.trim().parse::<u32>(), definition(e)) {
                            events.insert(sub, def);
                        }
                    }
                }
                component.groups.push((group.clone(), events));
            }
        }
        if let Some(enums) = c.get("enums").and_then(Json::as_object) {
            for (name, e) in enums {
                if let Some(def) = enum_def(e) {
                    metadata.enums.insert(format!("{namespace}::{name}"), def);
                }
            }
        }
        metadata.components.insert(id, component);
    }
    Ok(metadata)
}

fn text(e: &Json, key: &str) -> Option<String> {
    e.get(key).and_then(Json::as_str).map(str::to_owned)
}

fn definition(e: &Json) -> Option<Definition> {
    let mut arguments = Vec::new();
    if let Some(args) = e.get("arguments").and_then(Json::as_array) {
        for a in args {
            arguments.push(text(a, "type")?);
        }
    }
    Some(Definition {
        name: text(e, "name")?,
        message: text(e, "message")?,
        description: text(e, "description"),
        arguments,
    })
}

fn enum_def(e: &Json) -> Option<EnumDef> {
    let mut entries = Vec::new();
    if let Some(list) = e.get("entries").and_then(Json::as_object) {
        for (value, entry) in list {
            let value = value.trim();
            let value = match value.parse::<u64>() {
                Ok(v) => v,
                Err(_) => match value.parse::<i64>() {
                    Ok(v) => v as u64,
                    Err(_) => continue,
                },
            };
            if let Some(d) = text(entry, "description") {
                entries.push((value, d));
            }
        }
    }
    Some(EnumDef {
        ty: text(e, "type")?,
        is_bitfield: e
            .get("is_bitfield")
            .and_then(Json::as_bool)
            .unwrap_or(false),
        separator: text(e, "separator").unwrap_or_else(|| "|".to_owned()),
        entries,
    })
}
