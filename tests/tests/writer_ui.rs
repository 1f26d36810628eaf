//! Compile-fail tests of the writer's API: what the type system rules out.

#[test]
fn writer_misuse_does_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("ui-writer/*.rs");
}
