//! "Did you mean" suggestions for topic and field names: `ulog-format`'s, which the
//! derive macros use too.

pub(crate) use ulog_format::suggest::{closest, closest_n};
