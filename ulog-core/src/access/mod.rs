//! Access to a parsed log: topics, fields by path, typed values, bindings.
pub mod columns;
pub mod load;
pub mod numeric;
pub mod topic;
pub mod typed;
