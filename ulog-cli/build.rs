//! Only for this package's tests: which corpus of real logs and whether pyulog they
//! have (`tests/probe.rs`, the rule the workspace's tests share). Left out of the
//! published package, with the tests.

include!("../tests/probe.rs");

fn main() {
    probe("../../shared/corpus", "../tests/corpus");
}
