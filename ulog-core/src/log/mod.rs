//! A whole log: the one-pass parse into [`ULog`](ulog::ULog) with an index of every
//! topic's data messages, the views of single messages, every message in file order,
//! and a file mapped into memory.
pub(crate) mod file;
pub(crate) mod message;
pub(crate) mod messages;
pub(crate) mod metadata;
pub(crate) mod offsets;
pub(crate) mod params;
pub(crate) mod span;
pub(crate) mod ulog;
pub(crate) mod utc;
