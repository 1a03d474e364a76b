//! The self-contained web page: the glTF document and the player (`assets/viewer.js`) in one
//! HTML file with three.js embedded (`assets/three/`, from its published npm package; see
//! `assets/three/SOURCE.md`), every module loaded from a `data:` URL through an import map, so
//! the page opens from disk with no network.

use base64::Engine;

use super::Animation;

const THREE_CORE: &str = include_str!("../../assets/three/three.core.min.js");
const THREE_MODULE: &str = include_str!("../../assets/three/three.module.min.js");
const ORBIT_CONTROLS: &str = include_str!("../../assets/three/OrbitControls.js");
const GLTF_LOADER: &str = include_str!("../../assets/three/GLTFLoader.js");
const GEOMETRY_UTILS: &str = include_str!("../../assets/three/BufferGeometryUtils.js");
const LICENSE: &str = include_str!("../../assets/three/LICENSE");
const VIEWER: &str = include_str!("../../assets/viewer.js");

/// The modules of the import map: each name and its source, with the two relative imports of
/// the published files turned into the map's names (a `data:` URL has no base to resolve a
/// relative path against).
fn modules() -> [(&'static str, String); 5] {
    [
        ("three/core", THREE_CORE.to_owned()),
        (
            "three",
            THREE_MODULE.replace("\"./three.core.min.js\"", "\"three/core\""),
        ),
        (
            "three/addons/controls/OrbitControls.js",
            ORBIT_CONTROLS.to_owned(),
        ),
        (
            "three/addons/loaders/GLTFLoader.js",
            GLTF_LOADER.replace(
                "'../utils/BufferGeometryUtils.js'",
                "'three/addons/utils/BufferGeometryUtils.js'",
            ),
        ),
        (
            "three/addons/utils/BufferGeometryUtils.js",
            GEOMETRY_UTILS.to_owned(),
        ),
    ]
}

/// Escapes text for HTML element content.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The page of `anim`, its glTF document `gltf`.
pub(super) fn html(anim: &Animation, gltf: &str) -> String {
    let b64 = &base64::engine::general_purpose::STANDARD;
    let imports: serde_json::Map<String, serde_json::Value> = modules()
        .into_iter()
        .map(|(name, source)| {
            let url = format!("data:text/javascript;base64,{}", b64.encode(source));
            (name.to_owned(), serde_json::Value::String(url))
        })
        .collect();
    let import_map = serde_json::json!({ "imports": imports }).to_string();
    // JSON inside a <script> element: `</` could close it; `<\/` is the same JSON string.
    let gltf = gltf.replace("</", "<\\/");
    let title = escape(&anim.title);
    let license = escape(LICENSE);
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<!-- Written by lagrange. The player embeds three.js r180 (https://threejs.org, from the npm
package three@0.180.0), under its licence:
{license}-->
<style>
html, body {{ margin: 0; height: 100%; overflow: hidden; font: 13px system-ui, sans-serif; }}
canvas {{ display: block; }}
#bar {{ position: fixed; left: 0; right: 0; bottom: 0; display: flex; gap: 10px; align-items: center;
  padding: 6px 12px; background: rgba(255, 255, 255, 0.85); }}
#time {{ flex: 1; }}
#clock {{ min-width: 7em; font-variant-numeric: tabular-nums; }}
#title {{ position: fixed; left: 12px; top: 8px; color: #333; }}
</style>
<script>
// Errors of the page, for its test report (#lagrange-test); they still reach the console.
window.lagrangeErrors = [];
addEventListener('error', (e) => lagrangeErrors.push(String(e.message || e)));
addEventListener('unhandledrejection', (e) => lagrangeErrors.push(String(e.reason)));
const lagrangeConsoleError = console.error.bind(console);
console.error = (...a) => {{ lagrangeErrors.push(a.map(String).join(' ')); lagrangeConsoleError(...a); }};
</script>
<script type="importmap">{import_map}</script>
</head>
<body>
<div id="title">{title} · drag to turn, wheel to zoom, right-drag to pan</div>
<div id="bar">
<button id="play">pause</button>
<input id="time" type="range" min="0" max="1000" value="0" aria-label="time">
<span id="clock">t = 0</span>
<label>speed <select id="speed"><option value="0.25">¼×</option><option value="0.5">½×</option><option value="1" selected>1×</option><option value="2">2×</option><option value="4">4×</option></select></label>
<label>trace <select id="trace"><option value="(all)">all</option><option value="(none)">none</option></select></label>
</div>
<pre id="lagrange-test" hidden></pre>
<script type="application/json" id="lagrange-gltf">{gltf}</script>
<script type="module">
{VIEWER}
</script>
</body>
</html>
"#
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two relative imports of the published files are found and replaced: a new three.js
    /// that moved them would otherwise load nothing.
    #[test]
    fn relative_imports_are_mapped() {
        for (name, source) in modules() {
            assert!(
                !source.contains("from\"./"),
                "{name} imports a relative path"
            );
            assert!(
                !source.contains("from './"),
                "{name} imports a relative path"
            );
            assert!(
                !source.contains("from '../"),
                "{name} imports a relative path"
            );
        }
        assert!(THREE_MODULE.contains("\"./three.core.min.js\""));
        assert!(GLTF_LOADER.contains("'../utils/BufferGeometryUtils.js'"));
    }
}
