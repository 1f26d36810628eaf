//! Compile-fail tests of `ulog_module!`'s `unbound` option: `deny` is an error naming
//! every format not bound with why; the default (`warn`) is a warning per format
//! (made an error here by `#![deny(deprecated)]`, so that its text is checked).
//! Re-bless the expected output with `TRYBUILD=overwrite`.

use std::path::Path;

#[test]
fn formats_not_bound_are_named() {
    // trybuild builds the cases in its own crate, whose `CARGO_MANIFEST_DIR` (the
    // macro's base for the log's path) is `<target>/tests/trybuild/ulog-tests`: the
    // log goes there.
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("the target directory");
    let project = target.join("tests/trybuild/ulog-tests");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(
        project.join("unbindable.ulg"),
        ulog_tests::module_logs::unbindable(),
    )
    .unwrap();
    let t = trybuild::TestCases::new();
    t.compile_fail("ui-module/*.rs");
}
