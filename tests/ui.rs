//! The one trybuild driver (a package of its own, tests/Cargo.toml, so that trybuild builds the
//! cases against the facade alone). Compile-fail cases of `#[lagrangian]`, one directory per kind
//! under tests/ui/ (each bad input gets a clear error at the user's token, with the symbolic mode's own
//! errors in tests/ui/symbolic/). The compile-pass cases (hygiene) are ordinary tests in
//! tests/hygiene/; tests/ui_pass/ holds bodies deeper than anything written by hand, programs of
//! this package built as a user's debug build (opt-level 0, full debug info; see its manifest):
//! trybuild would build every dependency a second time in its own debug build for them.
//! Regenerate the expected output with `TRYBUILD=overwrite cargo test -p lagrange-ui` and review
//! it.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    // Every directory holds compile-fail cases: a new one is picked up without an edit.
    let mut groups: Vec<String> = std::fs::read_dir("ui")
        .expect("tests/ui is readable")
        .filter_map(Result::ok)
        .filter(|e| e.path().is_dir())
        .filter_map(|e| e.file_name().into_string().ok())
        .collect();
    groups.sort();
    assert!(!groups.is_empty(), "no compile-fail cases under tests/ui/");
    for group in &groups {
        t.compile_fail(format!("ui/{group}/*.rs"));
    }
}
