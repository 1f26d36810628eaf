//! Compile-fail tests: every macro error, with its span and text (re-bless the
//! expected output with `TRYBUILD=overwrite`).

#[test]
fn macro_errors() {
    let t = trybuild::TestCases::new();
    t.compile_fail("ui/*.rs");
}
