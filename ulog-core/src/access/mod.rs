//! Access to a parsed log: topics, fields by path, typed values.
pub mod topic;
