//! A spec-complete, typed, zero-copy reader of PX4 ULog flight logs.
//!
//! - [`ULog::parse`] reads a whole log from bytes (a buffer, or a [`MappedFile`]) in one
//!   pass: header, flag bits, formats, information, parameters, subscriptions with the
//!   offsets of their data messages, logged strings, dropouts, appended data. Payloads
//!   stay borrowed from the input.
//! - [`Topic::field`] resolves a field path (`esc[3].esc_rpm`) once; reading it from
//!   each payload is then a load at a fixed offset, giving a typed [`Value`].
//! - [`Incremental`] and [`StreamReader`] yield messages as they complete, from chunks
//!   or any `Read`, in bounded memory, with the same framing decisions.
//! - Damage (truncation, corruption, unknown messages, size mismatches) never fails the
//!   read: it becomes [`Finding`]s with byte offsets, and the data around it is kept.
//!   What does fail (not a ULog file, unknown incompatibility flags) is an [`Error`]
//!   with a matchable [`ErrorKind`] and the byte offset. The library never prints.
//! - `export` (feature `parquet`) turns topics into Apache Arrow record batches and
//!   writes them as Parquet files, one per topic instance, with a JSON metadata file.
//!
//! ```
//! let bytes = ulog_core::testing::sample_log();
//! let log = ulog_core::ULog::parse(&bytes)?;
//! assert_eq!(log.info_value("sys_name").unwrap().to_string(), "PX4");
//! let rpm = log.topic("esc_status", 0)?.field("esc[1].esc_rpm")?;
//! let first = log.topic("esc_status", 0)?.payload(0).unwrap();
//! assert_eq!(rpm.read(first), Some(ulog_core::Value::I32(5001)));
//! assert!(log.findings().is_empty());
//! # Ok::<(), ulog_core::Error>(())
//! ```
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod access;
mod error;
mod estimate;
#[cfg(feature = "parquet")]
pub mod export;
mod finding;
#[allow(unsafe_code)]
#[cfg(feature = "mmap")]
mod mmap;
pub mod numfmt;
pub mod read;
mod suggest;
pub mod testing;
pub mod typed;
mod value;
pub mod write;

pub use access::columns::{Column, ColumnData};
pub use access::load::{load_columns, load_file_columns, LoadedColumns, TopicColumns};
pub use access::numeric::{NumericBlock, NumericRow, NumericRows};
pub use access::topic::{FieldReader, FieldShape, Topic};
pub use access::typed::{scan_topics, scan_topics_only, Order, TypedRows, Walk};
pub use error::{Error, ErrorKind, Result};
pub use finding::{Corruption, Finding, FindingKind};
#[cfg(feature = "mmap")]
pub use mmap::MappedFile;
pub use read::framing::{FlagBits, Header, MAGIC, SYNC_MAGIC};
pub use read::iter::{MessageAt, Messages};
pub use read::log::{
    DefaultParam, Dropout, MultiInfo, ParamChange, ReleaseVersion, Subscription, ULog,
    UnknownMessage,
};
pub use read::message::{KeyValue, LogLevel, LogMessage, Message};
pub use read::offsets::{MessageOffsets, OffsetsIter};
pub use read::scan::{scan, scan_reader, scan_reader_ahead, ScanRecord, ScanSummary, ScanTopic};
pub use read::stream::{Incremental, Status, StreamReader};
pub use read::timestamp::{TimestampField, Unwrapper};
#[cfg(feature = "derive")]
pub use typed::{ulog_module, ulog_structs};
pub use typed::{CharArray, Plan, PlanKind, ULogMessage, ULogTopics};
pub use ulog_format as format;
pub use value::{Array, NumpyFloat, Str, Value};
pub use write::append::{append, Appender, ExistingSubscription};
pub use write::copy::copy_log;
pub use write::raw::RawWriter;
pub use write::writer::{
    DataWriter, DefaultTypes, Handle, InfoValue, LogWriter, ParamValue, RawHandle, WriterOptions,
};
