//! Bodies far deeper than anything written by hand (a 2000-term sum, a 2000-deep method chain,
//! 700 chained `let`s) expand on a stack much smaller than the compiler's (8 MiB): every walk
//! over the body, the DAG and the printed equations is a loop or an explicit stack, not a
//! recursion per level.

use proc_macro2::TokenStream;

/// The stack each expansion runs on: a quarter of the compiler's main thread.
const STACK: usize = 2 << 20;

/// Expands `#[lagrangian(args)] impl X { fn lagrangian(&self, (x, x_dot): Coord) -> Scalar { body } }`
/// on a small stack and returns the output's text.
fn expand_small_stack(args: &'static str, body: String) -> String {
    let run = move || {
        let args: TokenStream = args.parse().unwrap_or_default();
        let item =
            format!("impl X {{ fn lagrangian(&self, (x, x_dot): Coord) -> Scalar {{ {body} }} }}");
        let input: TokenStream = item.parse().expect("the generated item parses");
        crate::expand::expand(args, input).to_string()
    };
    std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(run)
        .expect("a thread")
        .join()
        .expect("the expansion finished on a 2 MiB stack")
}

fn sum_body(n: usize) -> String {
    let terms: Vec<String> = (0..n)
        .map(|k| format!("x.powi({}) * {}.0", k % 7 + 1, k + 1))
        .collect();
    format!("0.5 * x_dot * x_dot - ({})", terms.join(" + "))
}

fn chain_body(n: usize) -> String {
    format!("0.5 * x_dot * x_dot - x{}", ".sin()".repeat(n))
}

fn lets_body(n: usize) -> String {
    let mut s = String::from("let a0 = x;");
    for k in 1..=n {
        s.push_str(&format!(
            " let a{k} = a{} * 0.999 + (x * {k}.0).cos();",
            k - 1
        ));
    }
    format!("{s} 0.5 * x_dot * x_dot - a{n}")
}

#[test]
fn a_2000_term_sum_expands_in_both_modes() {
    for args in ["", "mode = \"jets\""] {
        let out = expand_small_stack(args, sum_body(2000));
        assert!(
            out.contains("impl"),
            "{args}: {}",
            &out[..out.len().min(300)]
        );
        assert!(!out.contains("compile_error"), "{args}");
    }
}

#[test]
fn a_2000_deep_method_chain_expands_in_both_modes() {
    for args in ["", "mode = \"jets\""] {
        let out = expand_small_stack(args, chain_body(2000));
        assert!(!out.contains("compile_error"), "{args}");
    }
}

#[test]
fn seven_hundred_chained_lets_expand_in_both_modes() {
    for args in ["", "mode = \"jets\""] {
        let out = expand_small_stack(args, lets_body(700));
        assert!(!out.contains("compile_error"), "{args}");
    }
}

#[test]
fn an_equation_too_long_to_print_says_so() {
    // d/dx of sin applied 2000 times is a product of 2000 cosines of ever deeper arguments:
    // quadratically long as text, so its line is a note.
    let out = expand_small_stack("", chain_body(2000));
    assert!(out.contains("too long to print"));
    assert!(out.len() < 4 << 20, "{} bytes", out.len());
}
