//! Access to a log's values: a topic of a parsed log and its fields by path, numbers
//! read in rows and blocks, columns.
pub(crate) mod columns;
pub(crate) mod field;
pub(crate) mod load;
pub(crate) mod lookup;
pub(crate) mod numeric;
pub(crate) mod topic;
