// The page of `linx view` (docs/visualization.md): loads the run served by linx from /run/, or a
// run folder dropped onto the page, and plays it in 3D.
import {
  Color,
  Fog,
  DirectionalLight,
  HemisphereLight,
  PCFShadowMap,
  PerspectiveCamera,
  Raycaster,
  Scene,
  Vector2,
  Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { parseRun, RUN_FILES, RunFormatError } from './run.js';
import { buildScene, chooseCamera, runBounds } from './scene.js';

const $ = (id) => document.getElementById(id);
const ui = {
  view: $('view'), play: $('play'), scrub: $('scrub'), time: $('time'), frame: $('frame'),
  speed: $('speed'), joints: $('show-joints'), contacts: $('show-contacts'), loop: $('loop'),
  reset: $('reset-camera'), openInput: $('open-input'), drop: $('drop'), message: $('message'),
  runName: $('run-name'), runInfo: $('run-info'), selection: $('selection'), selName: $('sel-name'),
  selTable: $('sel-table'), selClose: $('sel-close'),
};

// --- renderer, scene, camera, lights ---
const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = PCFShadowMap;
ui.view.appendChild(renderer.domElement);
const scene = new Scene();
scene.background = new Color(0xdfe5ec);
const camera = new PerspectiveCamera(40, 1, 0.01, 1000);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;
controls.dampingFactor = 0.15;
const hemi = new HemisphereLight(0xffffff, 0x5d6675, 1.9);
const sun = new DirectionalLight(0xffffff, 2.0);
sun.castShadow = true;
sun.shadow.mapSize.set(2048, 2048);
scene.add(hemi, sun, sun.target);

const state = {
  run: null, drawn: null, bounds: null, cam: null, frame: 0, playing: false,
  playStartWall: 0, playStartTime: 0, selected: -1, dirty: true, ready: false, error: null,
};

function showMessage(text, isError = false) {
  ui.message.textContent = text;
  ui.message.classList.toggle('error', isError);
  ui.message.hidden = !text;
  if (isError) state.error = text;
}

function resize() {
  const w = ui.view.clientWidth || window.innerWidth;
  const h = ui.view.clientHeight || window.innerHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  state.dirty = true;
}
window.addEventListener('resize', resize);

function resetCamera() {
  const { run, bounds } = state;
  if (!run) return;
  const cam = chooseCamera(run, bounds, camera.aspect || 1);
  state.cam = cam;
  camera.fov = cam.fov;
  camera.up.copy(cam.worldUp);
  camera.position.copy(cam.eye);
  const distance = cam.eye.distanceTo(cam.target);
  const size = Math.max(bounds.radius, 0.05);
  camera.near = Math.max(distance, size) * 1e-3;
  camera.far = (distance + size) * 60;
  camera.updateProjectionMatrix();
  controls.target.copy(cam.target);
  // OrbitControls orbits about camera.up, fixed when it is created: rebuild its frame.
  controls.object.up.copy(cam.worldUp);
  controls._quat?.setFromUnitVectors(cam.worldUp, new Vector3(0, 1, 0));
  controls._quatInverse?.copy(controls._quat).invert();
  controls.update();
  // The sun: above and to the side of the camera, its shadow box around the scene.
  const up = cam.worldUp;
  const toEye = cam.eye.clone().sub(cam.target).normalize();
  const side = new Vector3().crossVectors(up, toEye).normalize();
  sun.position.copy(bounds.center).addScaledVector(up.clone().multiplyScalar(3).add(toEye).addScaledVector(side, 0.8).normalize(), size * 4);
  sun.target.position.copy(bounds.center);
  const sc = sun.shadow.camera;
  sc.left = sc.bottom = -size * 1.6;
  sc.right = sc.top = size * 1.6;
  sc.near = size * 0.5;
  sc.far = size * 8;
  sc.updateProjectionMatrix();
  sun.shadow.bias = -0.0005;
  sun.shadow.normalBias = size * 0.004;
  hemi.position.copy(up);
  // Fade the ground's far edge into the background.
  scene.fog = new Fog(scene.background, distance + size, distance + size * 6);
  state.dirty = true;
}

const fmt = (x, d = 4) => {
  if (!Number.isFinite(x)) return '   —';
  const t = x.toFixed(d);
  return /^-0\.0*$/.test(t) ? ` ${t.slice(1)}` : (x < 0 ? '' : ' ') + t;  // no "-0.000"
};
const fmtVec = (a, o) => `${fmt(a[o])} ${fmt(a[o + 1])} ${fmt(a[o + 2])}`;

function updateSelection() {
  const { run, selected: b, frame: f } = state;
  if (!run || b < 0) {
    ui.selection.hidden = true;
    return;
  }
  const body = run.bodies[b];
  const o = f * run.nb + b;
  const speed = Math.hypot(run.vel[o * 3], run.vel[o * 3 + 1], run.vel[o * 3 + 2]);
  const rows = [
    ['body', `${b}${body.isStatic ? ' (static)' : ''}`],
    ['mass', body.isStatic ? '—' : `${Number(body.mass).toPrecision(4)} kg`],
    ['position', `${fmtVec(run.pos, o * 3)}  m`],
    ['velocity', `${fmtVec(run.vel, o * 3)}  m/s`],
    ['speed', `${fmt(speed)}  m/s`],
    ['ang. vel.', `${fmtVec(run.omega, o * 3)}  rad/s`],
    ['orientation', [0, 1, 2, 3].map((i) => fmt(run.quat[o * 4 + i], 3)).join(' ')],
  ];
  ui.selName.textContent = body.name;
  ui.selTable.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    const td = document.createElement('td');
    th.textContent = k;
    td.textContent = v;
    tr.append(th, td);
    return tr;
  }));
  ui.selection.hidden = false;
}

function select(b) {
  if (!state.drawn) return;
  if (state.selected >= 0) state.drawn.highlight(state.selected, false);
  state.selected = b;
  if (b >= 0) state.drawn.highlight(b, true);
  updateSelection();
  state.dirty = true;
}

function setFrame(f) {
  const { run } = state;
  if (!run) return;
  f = Math.max(0, Math.min(run.nf - 1, Math.round(f)));
  state.frame = f;
  state.drawn.update(f);
  ui.scrub.value = String(f);
  ui.time.textContent = `t = ${run.times[f].toFixed(3)} s`;
  ui.frame.textContent = `frame ${f} / ${run.nf - 1}`;
  updateSelection();
  state.dirty = true;
}

function setPlaying(on) {
  const { run } = state;
  if (!run) on = false;
  if (on && state.frame >= run.nf - 1) setFrame(0);
  state.playing = on;
  if (on) {
    state.playStartWall = performance.now();
    state.playStartTime = run.times[state.frame];
  }
  ui.play.textContent = on ? '\u275A\u275A' : '\u25B6';
  ui.play.setAttribute('aria-label', on ? 'Pause' : 'Play');
}

function frameAtTime(t) {
  const { times } = state.run;
  let lo = 0;
  let hi = times.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

function advance(now) {
  const { run } = state;
  const speed = Number(ui.speed.value) || 1;
  const t = state.playStartTime + ((now - state.playStartWall) / 1000) * speed;
  const end = run.times[run.nf - 1];
  if (t > end) {
    if (ui.loop.checked && run.nf > 1) {
      setFrame(0);
      state.playStartWall = now;
      state.playStartTime = run.times[0];
    } else {
      setFrame(run.nf - 1);
      setPlaying(false);
    }
    return;
  }
  const f = frameAtTime(t);
  if (f !== state.frame) setFrame(f);
}

function applyToggles() {
  if (!state.drawn) return;
  state.drawn.joints.visible = ui.joints.checked;
  state.drawn.contacts.visible = ui.contacts.checked && !!state.run.contacts;
  state.dirty = true;
}

function load(files, name) {
  let run;
  try {
    run = parseRun(files, name);
  } catch (e) {
    showMessage(e instanceof RunFormatError ? `Cannot show this run:\n${e.message}` : String(e), true);
    return false;
  }
  if (state.drawn) {
    scene.remove(state.drawn.root);
    state.drawn.dispose();
  }
  setPlaying(false);
  state.run = run;
  state.selected = -1;
  state.error = null;
  state.bounds = runBounds(run);
  state.drawn = buildScene(run, state.bounds);
  scene.add(state.drawn.root);
  ui.scrub.max = String(run.nf - 1);
  ui.contacts.disabled = !run.contacts;
  ui.joints.disabled = !run.joints.length;
  ui.contacts.parentElement.title = run.contacts ? 'Contact points and forces' : 'No contacts.csv in this run (linx run --contacts)';
  ui.runName.textContent = name;
  ui.runName.title = run.source ? `${name} (from ${run.source})` : name;
  const end = run.times[run.nf - 1];
  ui.runInfo.textContent = `${run.nb} bodies · ${run.joints.length} joints · ${run.nf} frames · ${end.toFixed(3)} s` +
    (run.contacts ? ' · contacts' : '');
  document.title = `${name} — linx view`;
  showMessage('');
  applyToggles();
  resize();
  resetCamera();
  setFrame(0);
  updateSelection();
  return true;
}

// --- the run served by linx view ---
async function loadFromServer() {
  let manifest;
  try {
    const res = await fetch('run/manifest.json', { cache: 'no-store' });
    if (!res.ok) throw new Error(res.statusText);
    manifest = await res.json();
  } catch {
    showMessage('Drop a linx run output folder here (or use "open…").');
    return;
  }
  const files = {};
  await Promise.all(manifest.files.filter((f) => RUN_FILES.includes(f)).map(async (f) => {
    const res = await fetch(`run/${f}`, { cache: 'no-store' });
    if (res.ok) files[f] = await res.text();
  }));
  load(files, manifest.name || 'run');
}

// --- a run folder (or its files) dropped on the page or opened ---
async function entryFiles(entry, path, out) {
  if (entry.isFile) {
    const file = await new Promise((resolve, reject) => entry.file(resolve, reject));
    out.push({ path: path + entry.name, file });
  } else if (entry.isDirectory && path.split('/').length < 4) {
    const reader = entry.createReader();
    for (;;) {
      const batch = await new Promise((resolve, reject) => reader.readEntries(resolve, reject));
      if (!batch.length) break;
      for (const e of batch) await entryFiles(e, `${path}${entry.name}/`, out);
    }
  }
}

// Picks the folder holding scene.json among the files (the first one) and reads its run files.
async function loadFiles(list, fallbackName) {
  const byDir = new Map();
  for (const { path, file } of list) {
    const cut = path.lastIndexOf('/');
    const dir = cut < 0 ? '' : path.slice(0, cut);
    const name = path.slice(cut + 1);
    if (!RUN_FILES.includes(name)) continue;
    if (!byDir.has(dir)) byDir.set(dir, {});
    byDir.get(dir)[name] = file;
  }
  const dirs = [...byDir.keys()].sort();
  const dir = dirs.find((d) => byDir.get(d)['scene.json']);
  if (dir === undefined) {
    showMessage('Cannot show this: no scene.json among the dropped files.\nDrop the output folder of linx run (it needs a linx that writes scene.json).', true);
    return false;
  }
  const found = byDir.get(dir);
  const files = {};
  await Promise.all(Object.entries(found).map(async ([name, file]) => { files[name] = await file.text(); }));
  const name = dir ? dir.slice(dir.lastIndexOf('/') + 1) : fallbackName;
  return load(files, name);
}

let dragDepth = 0;
window.addEventListener('dragenter', (e) => {
  e.preventDefault();
  dragDepth++;
  ui.drop.hidden = false;
});
window.addEventListener('dragleave', () => {
  dragDepth = Math.max(0, dragDepth - 1);
  if (!dragDepth) ui.drop.hidden = true;
});
window.addEventListener('dragover', (e) => {
  e.preventDefault();
  if (e.dataTransfer) e.dataTransfer.dropEffect = 'copy';
});
window.addEventListener('drop', async (e) => {
  e.preventDefault();
  dragDepth = 0;
  ui.drop.hidden = true;
  const dt = e.dataTransfer;
  if (!dt) return;
  const list = [];
  const entries = [...(dt.items || [])].map((it) => (it.kind === 'file' && it.webkitGetAsEntry ? it.webkitGetAsEntry() : null));
  if (entries.length && entries.every(Boolean)) {
    for (const entry of entries) await entryFiles(entry, '', list);
  } else {
    for (const file of dt.files) list.push({ path: file.webkitRelativePath || file.name, file });
  }
  await loadFiles(list, 'dropped run');
});
ui.openInput.addEventListener('change', async () => {
  const list = [...ui.openInput.files].map((file) => ({ path: file.webkitRelativePath || file.name, file }));
  ui.openInput.value = '';
  if (list.length) await loadFiles(list, 'opened run');
});

// --- controls ---
ui.play.addEventListener('click', () => {
  setPlaying(!state.playing);
  ui.play.blur();
});
ui.scrub.addEventListener('input', () => {
  setFrame(Number(ui.scrub.value));
  if (state.playing) setPlaying(true);  // continue from here
});
ui.speed.addEventListener('change', () => {
  if (state.playing) setPlaying(true);
});
ui.joints.addEventListener('change', applyToggles);
ui.contacts.addEventListener('change', applyToggles);
ui.reset.addEventListener('click', () => {
  resetCamera();
  ui.reset.blur();
});
ui.selClose.addEventListener('click', () => select(-1));
controls.addEventListener('change', () => {
  state.dirty = true;
});
window.addEventListener('keydown', (e) => {
  if (!state.run || e.target === ui.speed || e.ctrlKey || e.metaKey || e.altKey) return;
  const keys = {
    ' ': () => setPlaying(!state.playing),
    ArrowRight: () => setFrame(state.frame + 1),
    ArrowLeft: () => setFrame(state.frame - 1),
    Home: () => setFrame(0),
    End: () => setFrame(state.run.nf - 1),
    r: resetCamera,
    Escape: () => select(-1),
  };
  const action = keys[e.key];
  if (!action) return;
  e.preventDefault();
  if (e.key.startsWith('Arrow') || e.key === 'Home' || e.key === 'End') setPlaying(false);
  action();
});

// Picking: a click (not a drag) on a body selects it, on nothing clears the selection.
const raycaster = new Raycaster();
let down = null;
renderer.domElement.addEventListener('pointerdown', (e) => {
  down = { x: e.clientX, y: e.clientY };
});
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4 || !state.drawn) return;
  down = null;
  const r = renderer.domElement.getBoundingClientRect();
  const ndc = new Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  const hit = raycaster.intersectObjects(state.drawn.pickables, false)[0];
  select(hit ? hit.object.userData.body : -1);
});

// --- the loop: draw only when something changed ---
function tick(now) {
  requestAnimationFrame(tick);
  if (state.playing) advance(now);
  if (controls.update()) state.dirty = true;
  if (!state.dirty) return;
  state.dirty = false;
  renderer.render(scene, camera);
  if (state.run && !state.ready) state.ready = true;
}

// --- for tests and scripts: a small read-only view of what is drawn ---
function bodyObject(name) {
  if (!state.run) return null;
  const b = state.run.bodies.findIndex((x) => x.name === name);
  return b < 0 ? null : state.drawn.bodies[b].group;
}
window.linxViewer = Object.freeze({
  get ready() { return state.ready; },
  get error() { return state.error; },
  get runName() { return state.run ? state.run.name : null; },
  get frameCount() { return state.run ? state.run.nf : 0; },
  get frame() { return state.frame; },
  get time() { return state.run ? state.run.times[state.frame] : NaN; },
  get playing() { return state.playing; },
  get selected() { return state.selected >= 0 ? state.run.bodies[state.selected].name : null; },
  setFrame(i) {
    setPlaying(false);
    setFrame(i);
  },
  bodyNames() { return state.run ? state.run.bodies.map((b) => b.name) : []; },
  /// Where body `name`'s frame (its centre of mass) is drawn, from the drawn object.
  bodyWorldPosition(name) {
    const o = bodyObject(name);
    if (!o) return null;
    o.updateWorldMatrix(true, false);
    const p = new Vector3().setFromMatrixPosition(o.matrixWorld);
    return [p.x, p.y, p.z];
  },
  /// Where it lands on the page (CSS pixels), for clicking.
  bodyScreenPosition(name) {
    const o = bodyObject(name);
    if (!o) return null;
    o.updateWorldMatrix(true, false);
    camera.updateMatrixWorld();
    const p = new Vector3().setFromMatrixPosition(o.matrixWorld).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
  },
  layers() {
    const d = state.drawn;
    return {
      joints: !!d && d.joints.visible,
      contacts: !!d && d.contacts.visible,
      jointMarkers: d ? d.jointMarkers() : 0,
      contactPoints: d ? d.contactsDrawn() : 0,
    };
  },
});

resize();
requestAnimationFrame(tick);
loadFromServer();
