//! Keeps `examples/heavy_top_expanded.rs` and `examples/pendulum_expanded.rs` (what the macro
//! writes for the heavy top and for a one-coordinate pendulum) in sync with the macro: the region
//! between the markers must equal the formatted expansion.
//! Regenerate with `UPDATE_EXPANDED=1 cargo test -p lagrange-macros expanded`.

use std::io::Write;
use std::process::{Command, Stdio};

const INPUT: &str = r#"
impl HeavyTop {
    /// Symmetric heavy top, eq. (92).
    fn lagrangian(&self, (theta, theta_dot): Coord, (phi, phi_dot): Coord, (psi, psi_dot): Coord) -> Scalar {
        let (s, c) = theta.sin_cos();
        self.i_perp / 2.0 * (theta_dot.powi(2) + (phi_dot * s).powi(2))
            + self.i_par / 2.0 * (psi_dot + phi_dot * c).powi(2)
            - self.m * self.g * self.l * c
    }
}
"#;

const PENDULUM: &str = r#"
impl Pendulum {
    /// A plane pendulum: a point mass m on a massless rod of length l.
    fn lagrangian(&self, (theta, theta_dot): Coord) -> Scalar {
        0.5 * self.m * self.l * self.l * theta_dot * theta_dot + self.m * self.g * self.l * theta.cos()
    }
}
"#;

const BEGIN: &str = "// ---- BEGIN GENERATED (do not edit) ----\n";
const END: &str = "// ---- END GENERATED ----\n";

fn rustfmt(code: &str) -> Option<String> {
    let mut child = Command::new("rustfmt")
        .args(["--edition", "2021", "--emit", "stdout", "--quiet"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .ok()?;
    child.stdin.take()?.write_all(code.as_bytes()).ok()?;
    let out = child.wait_with_output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The expansion of `input`, formatted, must stand between the markers of `example` (a file of
/// `examples/`); `UPDATE_EXPANDED=1` writes it there.
fn check(input: &str, example: &str) {
    let input: proc_macro2::TokenStream = input.parse().expect("test input parses");
    let expanded = crate::expand::expand(proc_macro2::TokenStream::new(), input).to_string();
    let Some(formatted) = rustfmt(&expanded) else {
        panic!("rustfmt is needed for this test (it ships with the Rust toolchain)");
    };
    let path = format!("{}/../examples/{example}", env!("CARGO_MANIFEST_DIR"));
    let file = std::fs::read_to_string(&path).unwrap_or_default();
    let (head, tail) = match (file.find(BEGIN), file.find(END)) {
        (Some(b), Some(e)) => (file[..b].to_string(), file[e + END.len()..].to_string()),
        _ => (String::new(), String::new()),
    };
    let want = format!("{head}{BEGIN}{formatted}{END}{tail}");
    if std::env::var_os("UPDATE_EXPANDED").is_some() {
        std::fs::write(&path, &want).expect("write the expanded example");
        return;
    }
    assert!(
        file == want,
        "examples/{example} is out of date with the macro; regenerate with \
         `UPDATE_EXPANDED=1 cargo test -p lagrange-macros expanded` and review the diff"
    );
}

#[test]
fn expanded_example_is_up_to_date() {
    check(INPUT, "heavy_top_expanded.rs");
}

#[test]
fn expanded_pendulum_is_up_to_date() {
    check(PENDULUM, "pendulum_expanded.rs");
}
