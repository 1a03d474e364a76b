// The player of a lagrange animation: three.js loads the embedded glTF document (the same one
// `write_gltf` writes), an AnimationMixer poses its nodes at the time shown, OrbitControls turn
// the camera. This file is lagrange's; three.js is embedded from its published package.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const hook = document.getElementById('lagrange-test');
const fail = (what) => {
  console.error('lagrange: ' + what);
  hook.textContent = JSON.stringify({ error: String(what) });
  document.title = 'lagrange-failed';
};

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(window.innerWidth, window.innerHeight);
document.body.prepend(renderer.domElement);
const world = new THREE.Scene();
world.background = new THREE.Color(0xf3f3ef);
world.add(new THREE.HemisphereLight(0xffffff, 0x777777, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 2.0);
sun.position.set(4, 10, 7);
world.add(sun);

const text = document.getElementById('lagrange-gltf').textContent;
new GLTFLoader().parse(text, '', start, (e) => fail('the animation could not be read: ' + e));

function start(gltf) {
  const info = gltf.scene.userData.lagrange;
  world.add(gltf.scene);
  const c = info.camera;
  const camera = new THREE.PerspectiveCamera(c.fov_y_deg, window.innerWidth / window.innerHeight, c.near, c.far);
  camera.position.fromArray(c.position);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.fromArray(c.target);
  controls.update();

  const mixer = new THREE.AnimationMixer(gltf.scene);
  const clip = gltf.animations[0];
  const action = clip ? mixer.clipAction(clip) : null;
  if (action) {
    action.setLoop(THREE.LoopOnce, 1);
    action.clampWhenFinished = true;
    action.play();
  }
  const times = clip ? clip.tracks[0].times : new Float32Array([0]);
  const duration = times[times.length - 1];

  // Shapes and traces, by name.
  const shapes = [];
  const traces = [];
  gltf.scene.traverse((o) => {
    const kind = o.userData && o.userData.lagrange_kind;
    if (!kind) return;
    if (kind === 'trace') traces.push(o); else shapes.push(o);
  });
  const traceSelect = document.getElementById('trace');
  for (const tr of traces) {
    const opt = document.createElement('option');
    opt.value = tr.name;
    opt.textContent = tr.userData.lagrange_name;
    traceSelect.appendChild(opt);
  }
  const lineOf = (o) => { let line = null; o.traverse((m) => { if (m.isLine) line = m; }); return line; };

  let time = 0; // since the run's start
  let playing = true;
  const slider = document.getElementById('time');
  const clock = document.getElementById('clock');
  const play = document.getElementById('play');
  const speed = document.getElementById('speed');

  function pose(tc) {
    time = Math.min(Math.max(tc, 0), duration);
    if (action) {
      action.enabled = true;
      action.paused = false;
      action.time = time;
      mixer.update(0);
    }
    // How many kept states are at or before the time: the trace drawn so far.
    let lo = 0, hi = times.length;
    while (lo < hi) { const mid = (lo + hi) >> 1; if (times[mid] <= time + 1e-9) lo = mid + 1; else hi = mid; }
    for (const tr of traces) {
      const shown = traceSelect.value === '(all)' || traceSelect.value === tr.name;
      tr.visible = shown;
      const line = lineOf(tr);
      if (line) line.geometry.setDrawRange(0, lo);
    }
    slider.value = duration > 0 ? Math.round(1000 * time / duration) : 0;
    clock.textContent = 't = ' + (info.t0 + time).toFixed(3);
  }

  play.onclick = () => { playing = !playing; play.textContent = playing ? 'pause' : 'play'; };
  slider.oninput = () => { playing = false; play.textContent = 'play'; pose(duration * slider.value / 1000); render(); };
  traceSelect.onchange = () => { pose(time); render(); };
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });
  const render = () => renderer.render(world, camera);

  // The test hook: `page.html#t=1.25,3.5` shows each time in turn, paused, and writes into
  // #lagrange-test each shape's pixel (from this camera) and the frame's pixel statistics.
  const wanted = /(?:^|[#&])t=([^&]*)/.exec(window.location.hash);
  if (wanted) {
    playing = false;
    play.textContent = 'play';
    const w = renderer.domElement.width, h = renderer.domElement.height;
    const frames = [];
    for (const s of wanted[1].split(',')) {
      const t = parseFloat(s);
      pose(t - info.t0);
      controls.update();
      render();
      const gl = renderer.getContext();
      const px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const bg = [px[0], px[1], px[2]];
      let drawn = 0, hash = 0;
      for (let i = 0; i < px.length; i += 4) {
        if (Math.abs(px[i] - bg[0]) + Math.abs(px[i + 1] - bg[1]) + Math.abs(px[i + 2] - bg[2]) > 24) drawn++;
        hash = (Math.imul(hash, 31) + px[i] + 7 * px[i + 1] + 13 * px[i + 2]) | 0;
      }
      const at = {};
      for (const o of shapes) {
        const p = new THREE.Vector3();
        o.getWorldPosition(p);
        const world = p.toArray();
        p.project(camera);
        at[o.userData.lagrange_name] = { world, pixel: [(p.x + 1) / 2 * w, (1 - p.y) / 2 * h] };
      }
      frames.push({ t, drawn: drawn / (w * h), hash, shapes: at });
    }
    hook.textContent = JSON.stringify({
      width: w, height: h,
      camera: { position: camera.position.toArray(), target: controls.target.toArray(), fov_y_deg: camera.fov, aspect: camera.aspect, near: camera.near, far: camera.far },
      frames,
      errors: window.lagrangeErrors || [],
    });
    document.title = 'lagrange-ready';
    // Keep showing the last time asked for (a screenshot is taken of the composited page).
    renderer.setAnimationLoop(render);
    return;
  }

  const timer = new THREE.Timer();
  renderer.setAnimationLoop((stamp) => {
    timer.update(stamp);
    if (playing) {
      let next = time + timer.getDelta() * parseFloat(speed.value);
      if (next > duration) next = 0;
      pose(next);
    }
    controls.update();
    render();
  });
}
