//! Command-line handling shared by the heavy-top examples: `--key value` pairs, numbers, usage.

/// The `--key value` pairs after the program name; `Err("")` asks for the usage (`--help`, `-h`).
pub fn pairs() -> Result<Vec<(String, String)>, String> {
    let mut args = std::env::args().skip(1);
    let mut out = Vec::new();
    while let Some(key) = args.next() {
        if key == "--help" || key == "-h" {
            return Err(String::new());
        }
        let val = args.next().ok_or_else(|| format!("{key} needs a value"))?;
        out.push((key, val));
    }
    Ok(out)
}

/// The number given to option `key`.
pub fn number(key: &str, val: &str) -> Result<f64, String> {
    val.trim()
        .parse()
        .map_err(|_| format!("{key}: not a number: {val}"))
}

/// The parsed options; otherwise prints the error (if any) and the usage, and exits with 2 after
/// an error or 0 after `--help`.
pub fn or_exit<T>(parsed: Result<T, String>, usage: &str) -> T {
    parsed.unwrap_or_else(|msg| {
        if !msg.is_empty() {
            eprintln!("error: {msg}\n");
        }
        eprint!("{usage}");
        std::process::exit(if msg.is_empty() { 0 } else { 2 });
    })
}

/// Runs the example's body; an error is printed as its full sentence (`Display`, not the `Debug`
/// form `main` would print, with its `\u{307}` escapes) and the process exits with 1.
pub fn run_or_exit(body: fn() -> Result<(), Box<dyn std::error::Error>>) {
    if let Err(e) = body() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
