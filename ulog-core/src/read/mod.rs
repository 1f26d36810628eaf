//! Reading: framing, message views, the whole-file parse and the incremental reader.
pub mod framing;
pub mod iter;
pub mod log;
pub mod message;
pub mod offsets;
mod prefetch;
pub mod scan;
mod source;
pub mod stream;
pub mod timestamp;
