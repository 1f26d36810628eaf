//! Writing ULog: a typed writer whose section order is enforced by the API, a raw
//! message writer for tools that copy or edit logs, byte-exact pass-through, edits
//! (a time window, a choice of topics, payloads mapped: [`Edit`](crate::Edit)), and
//! appending crash data to an existing log.

pub(crate) mod anonymise;
pub(crate) mod append;
pub(crate) mod copy;
pub(crate) mod edit;
pub(crate) mod error;
pub(crate) mod raw;
pub(crate) mod writer;

pub use anonymise::{
    Anonymise, ARRAY_POSITIONS, IDENTIFYING_KEYS, POSITION_COMMANDS, POSITION_FIELDS,
    RAW_GPS_TOPICS, UTC_KEYS,
};
pub use append::Appender;
pub use edit::EditSummary;
pub use error::WriteErrorKind;
pub use raw::RawWriter;
pub use writer::{DefaultTypes, InfoValue, ParamValue, RawTopicHandle, TopicHandle, WriterOptions};
