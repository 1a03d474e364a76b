//! A run as a 3-D animation (`Trajectory::write_gltf`, `write_html`): the glTF file validates
//! (the glTF crate's reader) and its keyframes are the run's samples; a long run stays small;
//! bad input is a clear error; and each example's page plays in headless Chromium, its shapes
//! where the run puts them (projected by the page's camera, to a few pixels), two times giving
//! two different non-blank frames, no console errors. Without Chromium the browser test says how
//! to run it and passes.

use base64::Engine;
use lagrange::animation::{Animation, AnimationError, DEFAULT_MAX_FRAMES};
use lagrange::prelude::*;
use lagrange::scene::{Geometry, Visual};
use lagrange_examples::animations::{all, Watched};
use lagrange_examples::bicycle_system::Bicycle;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A folder of this test's own under the target directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("animation")
        .join(name);
    std::fs::create_dir_all(&dir).expect("the scratch folder can be made");
    dir
}

/// The glTF document's buffer, decoded from its `data:` URI.
fn buffer(doc: &gltf::Gltf) -> Vec<u8> {
    let b = doc.buffers().next().expect("one buffer");
    let gltf::buffer::Source::Uri(uri) = b.source() else {
        panic!("the buffer is embedded as a data: URI");
    };
    let data = uri
        .strip_prefix("data:application/octet-stream;base64,")
        .expect("a base64 data: URI");
    base64::engine::general_purpose::STANDARD
        .decode(data)
        .expect("valid base64")
}

/// The glTF file validates and reads back: one node per shape, and each shape's keyframes are
/// the run's samples (translations to f32, rotations to 1e-6 up to the quaternion's sign), every
/// jump among them.
#[test]
fn gltf_validates_and_its_keyframes_are_the_run() {
    for w in all().expect("the examples' runs") {
        let json = w.animation.gltf_json();
        // `from_slice` validates the document against the glTF 2.0 schema's rules.
        let doc = gltf::Gltf::from_slice(json.as_bytes())
            .unwrap_or_else(|e| panic!("{}: the glTF file does not validate: {e}", w.name));
        let data = buffer(&doc);
        let times = w.animation.times();
        let t0 = times[0];
        assert!(times.len() <= DEFAULT_MAX_FRAMES + 2 * w.jumps.len());
        assert!(
            times.len() >= 100.min(w.samples),
            "{}: too few keyframes",
            w.name
        );
        for tj in &w.jumps {
            assert!(
                times.iter().any(|t| t == tj),
                "{}: the jump at t = {tj} is not a keyframe",
                w.name
            );
        }
        let first = &w.animation.scenes()[0];
        let meshes = first
            .shapes
            .iter()
            .filter(|s| s.geometry != Geometry::Trace)
            .count();
        let anim = doc.animations().next().expect("one animation");
        assert_eq!(anim.channels().count(), 2 * meshes, "{}", w.name);
        let mut checked = 0;
        for channel in anim.channels() {
            let node = channel.target().node();
            let name = node.name().expect("named nodes");
            let i = first
                .shapes
                .iter()
                .position(|s| s.name == name)
                .unwrap_or_else(|| panic!("{}: node {name} is no shape", w.name));
            let reader = channel.reader(|_| Some(&data));
            let inputs: Vec<f32> = reader.read_inputs().expect("keyframe times").collect();
            assert_eq!(inputs.len(), times.len());
            let outputs = reader.read_outputs().expect("keyframe values");
            let values: Vec<Vec<f32>> = match outputs {
                gltf::animation::util::ReadOutputs::Translations(v) => {
                    v.map(|x| x.to_vec()).collect()
                }
                gltf::animation::util::ReadOutputs::Rotations(r) => {
                    r.into_f32().map(|x| x.to_vec()).collect()
                }
                _ => panic!("only translations and rotations are keyframed"),
            };
            for (k, &t) in times.iter().enumerate() {
                assert_eq!(
                    inputs[k],
                    (t - t0) as f32,
                    "{}: keyframe {k}'s time",
                    w.name
                );
                // A state a hair after a jump (positions that jump) is not a sample.
                let Some(scene) = (w.scene_at)(t) else {
                    assert!(w.jumps.iter().any(|j| (t - j).abs() < 1e-5));
                    continue;
                };
                let shape = &scene.shapes[i];
                if values[k].len() == 3 {
                    let p = shape.position.map(|x| x as f32);
                    assert_eq!(values[k], [p.x, p.y, p.z], "{}: {name} at t = {t}", w.name);
                } else {
                    let q = nalgebra::UnitQuaternion::from_rotation_matrix(
                        &nalgebra::Rotation3::from_matrix_unchecked(shape.rotation),
                    );
                    let want = [q.i, q.j, q.k, q.w];
                    let dot: f64 = (0..4).map(|j| f64::from(values[k][j]) * want[j]).sum();
                    assert!(
                        (dot.abs() - 1.0).abs() < 1e-6,
                        "{}: {name}'s rotation at t = {t}",
                        w.name
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 0);
    }
}

/// A long run stays small: the bicycle's 10⁵ samples make a page under 5 MB (the keyframes are
/// decimated to the default bound, evenly spread). The samples are the run's at every 10 ms,
/// refined a hundredfold by linear interpolation: the integrator's own 10⁵ samples (its multipliers
/// solved at each) take a minute in this build, and the bound is the writer's.
#[test]
fn a_long_run_stays_small() {
    let bike = Bicycle::benchmark();
    let mut tr = bike.watch_every(5.0, 10.0, 0.01).expect("the run");
    let (t, q) = (std::mem::take(&mut tr.t), std::mem::take(&mut tr.q));
    for k in 0..t.len() - 1 {
        for j in 0..100 {
            let s = j as f64 / 100.0;
            tr.t.push(t[k] + s * (t[k + 1] - t[k]));
            tr.q.push(std::array::from_fn(|i| {
                q[k][i] + s * (q[k + 1][i] - q[k][i])
            }));
        }
    }
    tr.t.push(t[t.len() - 1]);
    tr.q.push(q[q.len() - 1]);
    assert!(tr.t.len() >= 100_000);
    let anim = Animation::of(&tr, &bike).build().expect("the animation");
    assert!(anim.times().len() <= DEFAULT_MAX_FRAMES);
    let dir = scratch("large");
    anim.write_html(dir.join("bicycle.html")).expect("written");
    anim.write_gltf(dir.join("bicycle.gltf")).expect("written");
    let html = std::fs::metadata(dir.join("bicycle.html"))
        .expect("a file")
        .len();
    let gltf = std::fs::metadata(dir.join("bicycle.gltf"))
        .expect("a file")
        .len();
    eprintln!(
        "10^5 samples of the bicycle: {} keyframes, page {:.2} MB, glTF {:.2} MB",
        anim.times().len(),
        html as f64 / 1e6,
        gltf as f64 / 1e6
    );
    assert!(html <= 5_000_000, "the page takes {html} bytes");
}

/// A ball whose radius and shapes come from its coordinate: to make bad scenes.
struct Ball(Box<dyn Fn(f64) -> Scene>);

impl Lagrangian<1> for Ball {
    const COORDINATES: [&'static str; 1] = ["x"];
    const CYCLIC: [bool; 1] = [true];
    const AUTONOMOUS: bool = true;
    fn lagrangian<S: Scalar>(&self, _q: &[S; 1], v: &[S; 1], _t: S) -> S {
        v[0] * v[0] * 0.5
    }
}

impl Visual<1> for Ball {
    fn scene(&self, q: &[f64; 1], _t: f64) -> Scene {
        (self.0)(q[0])
    }
}

/// Bad input is a typed error that says what, where and what to try.
#[test]
fn bad_input_is_a_clear_error() {
    let run = |ball: &Ball| {
        Simulation::new(ball, [0.0], [1.0])
            .method(Method::Rk4 { dt: 0.1 })
            .until(1.0)
            .run()
            .expect("the run")
    };
    let at = |x: f64| Vector3::new(x, 0.0, 0.0);
    // A size that is not finite.
    let ball = Ball(Box::new(move |x: f64| {
        Scene::new().sphere(
            "ball",
            at(x),
            if x > 0.5 { f64::NAN } else { 0.1 },
            Rgb::RED,
        )
    }));
    let e = run(&ball).write_gltf(scratch("bad").join("nan.gltf"), &ball);
    let Err(e @ AnimationError::BadSize { .. }) = e else {
        panic!("a NaN radius is refused: {e:?}");
    };
    let msg = e.to_string();
    assert!(msg.contains("`ball`") && msg.contains("radius = NaN") && msg.contains("t = 0.6"));
    // No samples.
    let good = Ball(Box::new(move |x: f64| {
        Scene::new().sphere("ball", at(x), 0.1, Rgb::RED)
    }));
    let mut empty = run(&good);
    empty.t.clear();
    empty.q.clear();
    let e = empty.write_html(scratch("bad").join("empty.html"), &good);
    assert!(matches!(e, Err(AnimationError::NoSamples)));
    assert!(e.unwrap_err().to_string().contains("no samples"));
    // A scene whose shapes change during the run.
    let changing = Ball(Box::new(move |x: f64| {
        let s = Scene::new().sphere("ball", at(x), 0.1, Rgb::RED);
        if x > 0.5 {
            s.sphere("extra", at(0.0), 0.1, Rgb::RED)
        } else {
            s
        }
    }));
    let e = run(&changing).write_gltf(scratch("bad").join("changing.gltf"), &changing);
    assert!(matches!(e, Err(AnimationError::ShapesChanged { .. })));
    // Two shapes of one name; no shapes at all.
    let twice = Ball(Box::new(move |x: f64| {
        Scene::new()
            .sphere("ball", at(x), 0.1, Rgb::RED)
            .sphere("ball", at(0.0), 0.1, Rgb::RED)
    }));
    let e = run(&twice).write_gltf(scratch("bad").join("twice.gltf"), &twice);
    assert!(matches!(e, Err(AnimationError::DuplicateName { .. })));
    let nothing = Ball(Box::new(|_| Scene::new()));
    let e = run(&nothing).write_gltf(scratch("bad").join("nothing.gltf"), &nothing);
    assert!(matches!(e, Err(AnimationError::NoShapes)));
    // A folder that cannot be made names the path.
    let e = run(&good).write_gltf("/proc/lagrange/ball.gltf", &good);
    assert!(matches!(&e, Err(AnimationError::Io { .. })));
    assert!(e.unwrap_err().to_string().contains("/proc/lagrange"));
}

/// The Chromium to test the pages with: `$LAGRANGE_CHROMIUM`, or `chromium` (Debian's package),
/// `chromium-browser` or `google-chrome` on the PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("LAGRANGE_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        for dir in std::env::split_paths(&path) {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// Headless Chromium on `url`, with `what` (`--dump-dom` or `--screenshot=…`), in a profile of
/// its own; WebGL by SwiftShader (no GPU).
fn browse(bin: &Path, profile: &Path, what: &str, url: &str) -> std::process::Child {
    Command::new(bin)
        .args([
            "--headless",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--hide-scrollbars",
            "--mute-audio",
            "--no-first-run",
            "--window-size=800,600",
            "--virtual-time-budget=20000",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(what)
        .arg(url)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("chromium starts")
}

/// The page's report (`#lagrange-test`) from a dumped DOM.
fn report(dom: &str) -> Option<serde_json::Value> {
    let start = dom.find("<pre id=\"lagrange-test\"")?;
    let open = start + dom[start..].find('>')? + 1;
    let close = open + dom[open..].find("</pre>")?;
    let text = dom[open..close]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    serde_json::from_str(&text).ok()
}

/// Where a point of the glTF world appears, by the camera the page reports (three.js's
/// `lookAt` with +y up, its perspective projection), in pixels from the top left.
fn project(camera: &serde_json::Value, p: [f64; 3], w: f64, h: f64) -> [f64; 2] {
    let v = |key: &str| -> nalgebra::Vector3<f64> {
        let a: Vec<f64> = camera[key]
            .as_array()
            .expect("a vector")
            .iter()
            .map(|x| x.as_f64().expect("a number"))
            .collect();
        nalgebra::Vector3::new(a[0], a[1], a[2])
    };
    let (eye, target) = (v("position"), v("target"));
    let back = (eye - target).normalize();
    let right = nalgebra::Vector3::y().cross(&back).normalize();
    let up = back.cross(&right);
    let d = nalgebra::Vector3::from(p) - eye;
    let fov = camera["fov_y_deg"].as_f64().expect("a number").to_radians();
    let f = 1.0 / (fov / 2.0).tan();
    let aspect = camera["aspect"].as_f64().expect("a number");
    let depth = -d.dot(&back);
    let (x, y) = (f / aspect * d.dot(&right) / depth, f * d.dot(&up) / depth);
    [(x + 1.0) / 2.0 * w, (1.0 - y) / 2.0 * h]
}

/// The console errors in Chromium's log: uncaught exceptions and failed loads.
fn console_errors(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains("CONSOLE") || l.contains("Uncaught"))
        .filter(|l| {
            let l = l.to_lowercase();
            l.contains("uncaught") || l.contains("error") || l.contains("failed to")
        })
        .collect()
}

/// Each example's page in headless Chromium: at two kept times it renders non-blank frames that
/// differ, each shape's pixel is where the run's position projects by the page's camera (within
/// 3 px), and the console has no errors. The heavy top's screenshots at the two times are
/// non-blank and differ; with `LAGRANGE_UPDATE_FIGURES=1` the first becomes the README's figure.
#[test]
fn pages_play_in_a_browser() {
    let Some(bin) = chromium() else {
        // Written to the process's stderr, not through `eprintln!`, which the test harness
        // captures (and shows only for a failing test).
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "pages_play_in_a_browser: skipped, no Chromium found. Install it (Debian: `apt-get \
             install chromium`) or point LAGRANGE_CHROMIUM at a Chrome or Chromium binary, then \
             run `cargo test --test ensembles animation::`"
        );
        return;
    };
    let dir = scratch("pages");
    let watched: Vec<Watched> = all().expect("the examples' runs");
    // Two kept times of each run (a third and two thirds in), as the run wrote them.
    let mut jobs = Vec::new();
    for w in &watched {
        let times = w.animation.times();
        let pick = |f: f64| {
            let k = ((times.len() - 1) as f64 * f) as usize;
            (k..times.len())
                .map(|k| times[k])
                .find(|&t| (w.scene_at)(t).is_some())
                .expect("a sample")
        };
        let (t1, t2) = (pick(0.33), pick(0.67));
        let page = dir.join(format!("{}.html", w.name));
        w.animation.write_html(&page).expect("the page is written");
        let url = format!("file://{}#t={t1:?},{t2:?}", page.display());
        let profile = dir.join(format!("profile-{}", w.name));
        let child = browse(&bin, &profile, "--dump-dom", &url);
        jobs.push((w, [t1, t2], child));
    }
    // The heavy top's two frames, as screenshots.
    let top = &watched[0];
    let top_page = dir.join("heavy_top.html");
    let times = top.animation.times();
    let shots: Vec<(PathBuf, std::process::Child)> = [0.3, 0.7]
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let t = times[((times.len() - 1) as f64 * f) as usize];
            let png = dir.join(format!("heavy_top_{i}.png"));
            let url = format!("file://{}#t={t:?}", top_page.display());
            let profile = dir.join(format!("profile-shot-{i}"));
            let child = browse(
                &bin,
                &profile,
                &format!("--screenshot={}", png.display()),
                &url,
            );
            (png, child)
        })
        .collect();

    for (w, [t1, t2], child) in jobs {
        let out = child.wait_with_output().expect("chromium ran");
        let dom = String::from_utf8_lossy(&out.stdout);
        let log = String::from_utf8_lossy(&out.stderr);
        let errors = console_errors(&log);
        assert!(
            errors.is_empty(),
            "{}: console errors:\n{}",
            w.name,
            errors.join("\n")
        );
        let Some(r) = report(&dom) else {
            panic!("{}: the page wrote no report; its log:\n{log}", w.name);
        };
        assert!(r.get("error").is_none(), "{}: {}", w.name, r["error"]);
        let page_errors = r["errors"].as_array().expect("the page's error list");
        assert!(page_errors.is_empty(), "{}: {page_errors:?}", w.name);
        let (width, height) = (
            r["width"].as_f64().expect("a width"),
            r["height"].as_f64().expect("a height"),
        );
        // The page's camera is the file's default camera.
        let camera = &r["camera"];
        let c = w.animation.camera();
        for (key, want) in [("position", c.position), ("target", c.target)] {
            for j in 0..3 {
                let got = camera[key][j].as_f64().expect("a number");
                assert!((got - want[j]).abs() < 1e-9, "{}: camera {key}", w.name);
            }
        }
        let frames = r["frames"].as_array().expect("frames");
        assert_eq!(frames.len(), 2);
        let mut hashes = Vec::new();
        for (frame, t) in frames.iter().zip([t1, t2]) {
            let drawn = frame["drawn"].as_f64().expect("a fraction");
            assert!(
                drawn > 0.002,
                "{}: a blank frame at t = {t} ({drawn})",
                w.name
            );
            hashes.push(frame["hash"].as_i64().expect("a hash"));
            let scene = (w.scene_at)(t).expect("a sample");
            for shape in scene
                .shapes
                .iter()
                .filter(|s| s.geometry != Geometry::Trace)
            {
                let got = &frame["shapes"][&shape.name]["pixel"];
                let got = [got[0].as_f64().expect("x"), got[1].as_f64().expect("y")];
                let want = project(camera, w.animation.to_world(shape.position), width, height);
                let off = (got[0] - want[0]).hypot(got[1] - want[1]);
                assert!(
                    off < 3.0,
                    "{}: {} at t = {t} is drawn at {got:?}, the run puts it at {want:?}",
                    w.name,
                    shape.name
                );
            }
        }
        assert_ne!(
            hashes[0], hashes[1],
            "{}: the two times look the same",
            w.name
        );
    }

    let mut pixels = Vec::new();
    for (png, child) in shots {
        let out = child.wait_with_output().expect("chromium ran");
        let log = String::from_utf8_lossy(&out.stderr);
        let errors = console_errors(&log);
        assert!(
            errors.is_empty(),
            "screenshot: console errors:\n{}",
            errors.join("\n")
        );
        let file = std::fs::File::open(&png).expect("a screenshot");
        let mut decoder = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .expect("a PNG");
        let mut buf = vec![0; decoder.output_buffer_size().expect("a size")];
        let info = decoder.next_frame(&mut buf).expect("a frame");
        buf.truncate(info.buffer_size());
        let channels = info.color_type.samples();
        // Non-blank: pixels of the middle of the page that are not the background's colour.
        let bg = [0xf3, 0xf3, 0xef];
        let (w, h) = (info.width as usize, info.height as usize);
        let drawn = (h / 8..h * 7 / 8)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let p = &buf[(y * w + x) * channels..][..3];
                (0..3).map(|j| (p[j] as i32 - bg[j]).abs()).sum::<i32>() > 24
            })
            .count();
        assert!(
            drawn > w * h / 500,
            "{}: a blank screenshot ({drawn} pixels drawn)",
            png.display()
        );
        pixels.push(buf);
    }
    assert_ne!(
        pixels[0], pixels[1],
        "the heavy top's two screenshots are the same"
    );
    if std::env::var_os("LAGRANGE_UPDATE_FIGURES").is_some() {
        let figure =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/figures/heavy_top_animation.png");
        std::fs::copy(dir.join("heavy_top_0.png"), &figure).expect("the figure is written");
    }
}
