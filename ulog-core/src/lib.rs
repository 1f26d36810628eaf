//! A spec-complete, typed, zero-copy reader and writer of PX4 ULog flight logs.
//!
//! ```
//! let bytes = ulog_core::testing::sample_log();
//! let log = ulog_core::ULog::parse(&bytes)?;
//! assert_eq!(log.info_value("sys_name").unwrap().to_string(), "PX4");
//! let esc = log.topic("esc_status", 0)?;
//! let rpm = esc.field("esc[1].esc_rpm")?;
//! assert_eq!(rpm.read(esc.payload(0).unwrap()), Some(ulog_core::Value::I32(5001)));
//! assert!(log.findings().is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # One way per job
//!
//! | job | entry point |
//! |---|---|
//! | open a log | [`LogFile::open`] (read into memory; [`LogFile::map`] maps it) then [`LogFile::parse`]; [`ULog::parse`] over bytes |
//! | read one topic typed | [`ULog::read`] (one instance), [`ULog::read_instances`] (each instance on its own) |
//! | read several topics typed, in file or time order | [`scan_topics`] with a [`ULogTopics`] enum |
//! | read every data message once, untyped | [`scan`] |
//! | read any field by path | [`ULog::topic`], [`Topic::field`] |
//! | every message of the log | [`ULog::messages`]; from a `Read` or a log still being written, [`stream`] |
//! | load all topics as columns | [`load_columns`] |
//! | write | [`LogWriter`], then [`DataWriter`] |
//! | append (crash data) | [`append`] |
//! | copy byte for byte | [`copy_log`] |
//! | cut a time window, keep or drop topics, map payloads | [`Edit`] |
//! | the parameters that differ between two flights, or from the defaults | [`ULog::diff_params`], [`ULog::diff_param_defaults`] |
//! | several topics on one time base (previous, nearest, linear; by name or typed) | [`ULog::align`], [`ULog::select_columns`] |
//! | play items back on the log's clock (paced, paused, stepped, sought, looped) | [`replay::Player`] |
//! | the UTC time of the timestamps | [`ULog::utc`] |
//! | the time span of a log (what a time axis shows), and the rows far outside it | [`ULog::span`] |
//! | the unit of a field | [`units::unit_of`] |
//! | the GPS track by flight mode (for KML, GPX), GPS receiver bytes | [`track::Track::from_log`], [`track::gps_dump`] |
//! | spectra, spectrograms, step responses of sampled signals | `analysis::psd`, `analysis::step_response` (feature `analysis`) |
//! | an MCAP file (ROS 2 CDR or JSON) for Foxglove and ROS 2 tools | `mcap::write_mcap` (feature `mcap`) |
//! | Parquet files for query engines | `export::write_parquet` (feature `parquet`) |
//!
//! A pass ([`scan`], [`scan_topics`], [`load_columns`]) reads any [`Source`]: bytes, a
//! [`LogFile`], a parsed [`ULog`], any `Read`, a file by path. How it reads (a second
//! thread reading ahead, threads for columns, time order, the topics an enum does not
//! name) is a [`ScanOptions`] choice, not another function.
//!
//! # Naming
//!
//! - `ULog` is a whole log parsed; a [`Topic`] is one topic instance of it; the one
//!   record of a topic instance that every reader shares is a
//!   [`Subscription`](read::Subscription).
//! - `…Record` is one data message met by a pass ([`DataRecord`], [`TopicRecord`]);
//!   `…Reader` reads as it goes ([`FieldReader`] one field of every payload,
//!   [`StreamReader`](stream::StreamReader) messages from a `Read`); `…Rows` are the
//!   rows of one topic; `…Options` configure one entry point.
//! - There is one error type per direction: [`ReadError`] (a log that cannot be read),
//!   [`LookupError`] (a topic or field that is not there), [`TypedError`] (a binding
//!   that does not fit, a payload that does not decode), [`WriteError`]. Each has a
//!   position only where there is a place in the file. `ReadError`, `TypedError` and
//!   `WriteError` say what went wrong through `kind()`, an enum kept in the module of
//!   their machinery: [`read::ReadErrorKind`], [`typed::TypedErrorKind`],
//!   [`write::WriteErrorKind`].
//! - The root holds what a program names; the modules hold the rest, each item at one
//!   path: [`read`] (what a log holds: metadata, messages, findings), [`stream`],
//!   [`columns`], [`typed`] (the machinery of bindings), [`write`](mod@write), `export` (feature
//!   `parquet`), `mcap` (feature `mcap`), [`format`](mod@format) (the grammar),
//!   `analysis` (feature `analysis`), `store` (feature `store`: S3 and HTTP), [`parallel`], [`replay`], [`testing`], [`units`], [`track`], [`naming`] (a topic's
//!   name in file and folder names).
//!
//! # Damage
//!
//! Damage (truncation, corruption, unknown messages, size mismatches) never fails a
//! read: it becomes [`Finding`]s with byte offsets, and the data around it is kept.
//! The library never prints.
#![warn(missing_docs)]
#![deny(unsafe_code)]
#![cfg_attr(docsrs, feature(doc_auto_cfg))]

mod access;
pub mod align;
#[cfg(feature = "analysis")]
pub mod analysis;
#[allow(unsafe_code)]
mod audited;
mod bytes;
mod definitions;
mod error;
mod estimate;
#[cfg(feature = "events")]
pub mod events;
#[cfg(feature = "parquet")]
pub mod export;
mod finding;
mod framing;
#[cfg(any(feature = "parquet", feature = "mcap", feature = "analysis"))]
mod json_text;
mod log;
#[cfg(feature = "mcap")]
pub mod mcap;
pub mod naming;
pub mod parallel;
mod pass;
pub mod replay;
#[cfg(feature = "store")]
pub mod store;
mod suggest;
pub mod testing;
pub mod track;
pub mod typed;
pub mod units;
mod value;
pub mod write;

// The README's example, compiled as a doctest so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;

pub use access::field::FieldReader;
pub use access::load::load_columns;
pub use access::lookup::LookupError;
pub use access::topic::Topic;
pub use error::ReadError;
pub use finding::Finding;
pub use log::file::LogFile;
pub use log::message::Message;
pub use log::ulog::ULog;
pub use pass::keep::ScanSummary;
pub use pass::scan::{scan, ScanOptions};
pub use pass::source::Source;
pub use pass::visit::DataRecord;
pub use typed::error::TypedError;
pub use typed::message::ULogMessage;
pub use typed::rows::TypedRows;
pub use typed::scan::{scan_topics, TopicRecord};
pub use typed::topics::ULogTopics;
pub use value::Value;
pub use write::append::append;
pub use write::copy::copy_log;
pub use write::edit::Edit;
pub use write::error::WriteError;
pub use write::writer::{DataWriter, LogWriter};

/// The derive macros share their traits' names (feature `derive`).
#[cfg(feature = "derive")]
pub use ulog_derive::{ulog_module, ulog_structs, ULogMessage, ULogTopics};

/// The grammar and layout model of format strings (the `ulog-format` crate).
pub use ulog_format as format;

/// What a log holds and what reading it reports: the header and flag bits,
/// subscriptions, information and parameters, logged strings, messages, findings,
/// the order and flow of a pass, and the kinds of [`ReadError`].
pub mod read {
    pub use crate::access::field::FieldShape;
    pub use crate::access::lookup::TopicNotFound;
    pub use crate::access::topic::Payloads;
    pub use crate::definitions::timestamp::{TimestampField, Unwrapper};
    pub use crate::definitions::Subscription;
    pub use crate::error::ReadErrorKind;
    pub use crate::finding::{Corruption, FindingKind};
    pub use crate::framing::{FlagBits, Header};
    pub use crate::log::message::{KeyValue, LogLevel, LoggedString};
    pub use crate::log::messages::{MessageAt, Messages};
    pub use crate::log::metadata::{
        DefaultParam, Dropout, MultiInfo, ParamChange, ReleaseVersion, UnknownMessage,
    };
    pub use crate::log::offsets::{MessageOffsets, OffsetsIter};
    pub use crate::log::params::{
        diff_from_defaults, diff_params, same_param_value, vehicle_type, DefaultKind,
        ParamDefaults, ParamDiff,
    };
    pub use crate::log::span::{
        OutlierSide, SpanOutlier, TimeSpan, EARLY_OUTLIER_US, JUMP_US, STALE_RUN_ROWS,
    };
    pub use crate::log::utc::{UtcClock, UtcSource, UtcTime};
    pub use crate::pass::keep::{LogMetadata, TopicRows};
    pub use crate::pass::scan::{ScanFlow, ScanOrder};
    pub use crate::value::{LogText, ValueArray};
}

/// Reading a log as its bytes come: [`PushReader`](stream::PushReader) is fed chunks
/// (a socket, a log still being written), [`StreamReader`](stream::StreamReader)
/// pulls them from any `Read`. Both yield every message, in bounded memory.
pub mod stream {
    pub use crate::pass::stream::{Progress, PushReader, StreamReader};
}

/// Topics as typed columns ([`load_columns`], [`Topic::columns`]), and every number of a payload read into
/// `f64` rows at once, for generic tools.
pub mod columns {
    pub use crate::access::columns::{Column, ColumnData};
    pub use crate::access::load::{LoadedColumns, TopicColumns};
    pub use crate::access::numeric::{NumericBlock, NumericRow, NumericRows};
}
