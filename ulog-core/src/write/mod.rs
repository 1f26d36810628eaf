//! Writing ULog: a typed writer whose section order is enforced by the API, a raw
//! message writer for tools that copy or edit logs, byte-exact pass-through, and
//! appending crash data to an existing log.

pub mod append;
pub mod copy;
pub mod raw;
pub mod writer;
