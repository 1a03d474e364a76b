//! Compile-fail cases of `#[lagrangian]`: each bad input gets a clear error at the user's token.
//! Regenerate the expected output with `TRYBUILD=overwrite cargo test --test ui` and review it.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*/*.rs");
}
