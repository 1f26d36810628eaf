//! One pass over a log from any source: the data messages in file order or by
//! timestamp, and the incremental readers that yield every message as its bytes come.
pub(crate) mod driver;
pub(crate) mod keep;
pub(crate) mod order;
pub(crate) mod scan;
pub(crate) mod source;
pub(crate) mod stream;
pub(crate) mod visit;
