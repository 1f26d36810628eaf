//! Logs read from, and datasets written to, object storage (feature `store`): S3 and
//! S3-compatible servers (`s3://bucket/key`), and any HTTP(S) server that answers
//! ranged requests (`https://host/path`), through the Arrow project's
//! [`object_store`].
//!
//! - [`Location::parse`] tells a URL from a local path;
//! - [`Remote::reader`] reads an object in order by ranged requests, for a pass
//!   ([`Source::reader`](crate::Source::reader)); [`Remote::fetch`] reads one whole
//!   into a [`LogFile`](crate::LogFile); [`Remote::find_logs`] lists the logs under a
//!   prefix;
//! - [`RemoteDataset`] writes a [`Dataset`](crate::export::Dataset) under an `s3://`
//!   prefix so that no reader sees half of it (see there how, on a store without
//!   rename).

mod dataset;
mod error;
mod remote;

pub use dataset::{Downloaded, Published, RemoteDataset};
pub use error::{StoreError, StoreErrorKind};
pub use remote::{Location, Remote, RemoteReader, AHEAD, FIRST_CHUNK};
