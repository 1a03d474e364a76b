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

/// Writes a run's animation next to its figure: `PATH.html` (the page that plays it) and
/// `PATH.gltf` (the glTF 2.0 file), `PATH` the figure's path without its extension; prints both.
///
/// ```
/// let p = std::path::Path::new("out/top.svg");
/// assert_eq!(p.with_extension("html"), std::path::Path::new("out/top.html"));
/// ```
pub fn write_animation<V: lagrange::scene::Visual<N> + ?Sized, const N: usize>(
    figure: &str,
    title: &str,
    traj: &lagrange::Trajectory<N>,
    sys: &V,
) -> Result<(), lagrange::animation::AnimationError> {
    let figure = std::path::Path::new(figure);
    let anim = lagrange::animation::Animation::of(traj, sys)
        .title(title)
        .build()?;
    for ext in ["html", "gltf"] {
        let path = figure.with_extension(ext);
        match ext {
            "html" => anim.write_html(&path)?,
            _ => anim.write_gltf(&path)?,
        }
        let kib = std::fs::metadata(&path)
            .map(|m| m.len() / 1024)
            .unwrap_or(0);
        println!(
            "wrote {} ({kib} KiB, {} keyframes)",
            path.display(),
            anim.times().len()
        );
    }
    Ok(())
}
