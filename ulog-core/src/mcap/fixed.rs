//! The two channels of an MCAP file that are not topics: logged strings on `/rosout`
//! and parameters on `/ulog/parameters`, their schemas, and their messages.

use super::McapEncoding;

/// The `/rosout` message type, with the `Time` it uses.
pub(super) const LOG_SCHEMA: &str =
    "uint8 DEBUG=10\nuint8 INFO=20\nuint8 WARN=30\nuint8 ERROR=40\n\
uint8 FATAL=50\nbuiltin_interfaces/Time stamp\nuint8 level\nstring name\nstring msg\n\
string file\nstring function\nuint32 line\n\
================================================================================\n\
MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";

/// The JSON Schema of `/rosout` messages in JSON.
pub(super) const LOG_JSON_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"rcl_interfaces/msg/Log","type":"object","properties":{"stamp":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}},"required":["sec","nanosec"]},"level":{"type":"integer"},"name":{"type":"string"},"msg":{"type":"string"},"file":{"type":"string"},"function":{"type":"string"},"line":{"type":"integer"}},"required":["stamp","level","name","msg","file","function","line"],"additionalProperties":false}"#;

/// The JSON Schema of `/ulog/parameters` messages in JSON.
pub(super) const PARAMETER_JSON_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"ulog_msgs/msg/Parameter","type":"object","properties":{"stamp":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}},"required":["sec","nanosec"]},"name":{"type":"string"},"value":{"type":["number","null"]},"initial":{"type":"boolean"}},"required":["stamp","name","value","initial"],"additionalProperties":false}"#;

/// The parameter message type of `/ulog/parameters`.
pub(super) const PARAMETER_SCHEMA: &str =
    "builtin_interfaces/Time stamp\nstring name\nfloat64 value\n\
bool initial\n\
================================================================================\n\
MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";

/// The two channels that are not topics.
#[derive(Clone, Copy)]
pub(super) enum Fixed {
    Rosout,
    Parameters,
}

impl Fixed {
    /// The message type, the channel, the `ros2msg` schema and the JSON Schema.
    pub(super) fn schemas(self) -> (&'static str, &'static str, &'static str, &'static str) {
        match self {
            Fixed::Rosout => (
                "rcl_interfaces/msg/Log",
                "/rosout",
                LOG_SCHEMA,
                LOG_JSON_SCHEMA,
            ),
            Fixed::Parameters => (
                "ulog_msgs/msg/Parameter",
                "/ulog/parameters",
                PARAMETER_SCHEMA,
                PARAMETER_JSON_SCHEMA,
            ),
        }
    }
}

/// A message of `/rosout` or `/ulog/parameters` being written: little-endian CDR
/// (aligned from after its header), or a JSON object.
pub(super) struct Fields {
    json: bool,
    out: Vec<u8>,
}

impl Fields {
    pub(super) fn new(encoding: McapEncoding, mut out: Vec<u8>) -> Fields {
        out.clear();
        let json = encoding == McapEncoding::Json;
        if json {
            out.push(b'{');
        } else {
            out.extend_from_slice(&[0, 1, 0, 0]);
        }
        Fields { json, out }
    }

    pub(super) fn finish(mut self) -> Vec<u8> {
        if self.json {
            self.out.push(b'}');
        }
        self.out
    }

    /// Starts a JSON member; `true` for CDR, which writes the value itself.
    fn key(&mut self, name: &str) -> bool {
        if self.json {
            if self.out.len() > 1 {
                self.out.push(b',');
            }
            self.out
                .extend_from_slice(format!("\"{name}\":").as_bytes());
        }
        !self.json
    }

    fn align(&mut self, n: usize) {
        let pos = self.out.len() - 4;
        let pad = (n - pos % n) % n;
        self.out.resize(self.out.len() + pad, 0);
    }

    pub(super) fn u8(&mut self, name: &str, v: u8) {
        if self.key(name) {
            self.out.push(v);
        } else {
            self.out.extend_from_slice(v.to_string().as_bytes());
        }
    }

    pub(super) fn bool(&mut self, name: &str, v: bool) {
        if self.key(name) {
            self.out.push(u8::from(v));
        } else {
            self.out
                .extend_from_slice(if v { b"true" } else { b"false" });
        }
    }

    pub(super) fn u32(&mut self, name: &str, v: u32) {
        if self.key(name) {
            self.align(4);
            self.out.extend_from_slice(&v.to_le_bytes());
        } else {
            self.out.extend_from_slice(v.to_string().as_bytes());
        }
    }

    pub(super) fn f64(&mut self, name: &str, v: f64) {
        if self.key(name) {
            self.align(8);
            self.out.extend_from_slice(&v.to_le_bytes());
        } else if v.is_finite() {
            self.out.extend_from_slice(format!("{v:?}").as_bytes());
        } else {
            self.out.extend_from_slice(b"null");
        }
    }

    pub(super) fn string(&mut self, name: &str, s: &str) {
        // A NUL would end the text for CDR readers: the text ends there.
        let s = s.split('\0').next().unwrap_or("");
        if self.key(name) {
            self.align(4);
            self.out
                .extend_from_slice(&(s.len() as u32 + 1).to_le_bytes());
            self.out.extend_from_slice(s.as_bytes());
            self.out.push(0);
        } else {
            let mut text = String::with_capacity(s.len() + 2);
            crate::json_text::push_string(&mut text, s.chars());
            self.out.extend_from_slice(text.as_bytes());
        }
    }

    /// A `builtin_interfaces/Time` of `nanos`.
    pub(super) fn stamp(&mut self, name: &str, nanos: u64) {
        let secs = (nanos / 1_000_000_000).min(i32::MAX as u64) as u32;
        let rest = (nanos % 1_000_000_000) as u32;
        if self.key(name) {
            self.align(4);
            self.out.extend_from_slice(&secs.to_le_bytes());
            self.out.extend_from_slice(&rest.to_le_bytes());
        } else {
            self.out
                .extend_from_slice(format!("{{\"sec\":{secs},\"nanosec\":{rest}}}").as_bytes());
        }
    }
}
