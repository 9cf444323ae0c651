// glint serve's page: controls built from the scene document, edits sent to
// the server (which checks them with the loader), frames and state received
// as server-sent events. No framework, no build step, no network but ours.
'use strict';

const $ = (id) => document.getElementById(id);
// For the browser tests and the benchmark: what the page last showed.
const preview = (window.glintPreview = {
  state: null, frame: null, frames: 0, lastEditVersion: 0, lastExplain: null, lastError: '', editsInFlight: 0,
});

// Tells tests and the benchmark that the page changed (state, frame, edit, tree).
const changed = () => window.dispatchEvent(new Event('glintpreview'));

let state = null;
let selectedMaterial = null;
let structure = '';  // what the controls were built for
const controls = new Map();  // path -> {get value from doc, set into inputs}

// --- talking to the server ----------------------------------------------------------

async function post(url, body) {
  const response = await fetch(url, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body || {}),
  });
  const answer = await response.json();
  if (!response.ok) throw new Error(answer.error || response.statusText);
  return answer;
}

function showMessage(text, isError) {
  const m = $('message');
  m.textContent = text;
  m.className = 'banner ' + (isError ? 'error' : 'info');
  m.hidden = !text;
  if (isError) preview.lastError = text;
  clearTimeout(showMessage.timer);
  if (text) showMessage.timer = setTimeout(() => { m.hidden = true; }, isError ? 6000 : 3000);
}

// Edits go one request at a time; while one is in flight the newest edit of
// the same control replaces the waiting one (a dragged slider sends its
// latest value, not every value it passed).
const queue = [];
let sending = false;
function sendEdits(edits, coalesce) {
  const last = queue[queue.length - 1];
  if (last && coalesce && last.coalesce === coalesce) last.edits = edits;
  else queue.push({ edits, coalesce });
  pump();
}
async function pump() {
  if (sending || !queue.length) return;
  sending = true;
  const job = queue.shift();
  preview.editsInFlight++;
  try {
    const r = await post('/api/edit', { edits: job.edits, coalesce: job.coalesce || '' });
    preview.lastEditVersion = r.version;
  } catch (e) {
    showMessage(e.message, true);
    if (state) refreshValues();  // back to the server's values
  } finally {
    preview.editsInFlight--;
    sending = false;
    pump();
    changed();
  }
}
preview.sendEdits = sendEdits;

// --- the document's values --------------------------------------------------------

function at(path) {
  let v = state && state.scene;
  for (const key of path.replace(/\[(\d+)\]/g, '.$1').split('.')) {
    if (v === undefined || v === null) return undefined;
    v = v[key];
  }
  return v;
}
const asColor = (v, d) => (v === undefined ? [d, d, d] : Array.isArray(v) ? v.slice() : [v, v, v]);
// A material path as the server's paths name it (names with dots in brackets).
const materialPath = (name) => (/[.\[\]"]/.test(name) ? `materials["${name}"]` : `materials.${name}`);

// --- controls ----------------------------------------------------------------------

function row(parent, label, input) {
  const r = document.createElement('div');
  r.className = 'row';
  const l = document.createElement('label');
  l.textContent = label;
  l.title = label;
  r.append(l, input);
  parent.append(r);
  return r;
}

function numberInput(step) {
  const n = document.createElement('input');
  n.type = 'number';
  n.step = step;
  return n;
}

// A number with a slider: `read()` gives the current value from the document.
function sliderControl(parent, label, path, { min, max, step, read, write, integer }) {
  const box = document.createElement('div');
  box.className = 'slider';
  const range = document.createElement('input');
  range.type = 'range';
  range.min = min; range.max = max; range.step = step;
  range.dataset.path = path;
  const num = numberInput(step);
  num.dataset.path = path;
  box.append(range, num);
  row(parent, label, box);
  const send = (v) => {
    v = integer ? Math.round(v) : v;
    if (!Number.isFinite(v)) return;
    if (write) write(v); else sendEdits([{ op: 'set', path, value: v }], path);
  };
  range.addEventListener('input', () => { num.value = range.value; send(parseFloat(range.value)); });
  num.addEventListener('change', () => { range.value = num.value; send(parseFloat(num.value)); });
  controls.set(path, () => {
    const v = read();
    if (document.activeElement !== range) range.value = v;
    if (document.activeElement !== num) num.value = +(+v).toPrecision(6);
  });
}

function colorControl(parent, label, path, { read, write, max = 1 }) {
  const box = document.createElement('div');
  box.className = 'triple';
  const inputs = [0, 1, 2].map((c) => {
    const s = document.createElement('input');
    s.type = 'range'; s.min = 0; s.max = max; s.step = 0.005;
    s.title = 'RGB'[c];
    s.dataset.path = path;
    s.dataset.channel = c;
    return s;
  });
  const swatch = document.createElement('div');
  swatch.className = 'swatch';
  box.append(...inputs, swatch);
  row(parent, label, box);
  const paint = (c) => {
    const g = (x) => Math.round(255 * Math.min(1, Math.max(0, x)) ** (1 / 2.2));
    swatch.style.background = `rgb(${g(c[0])},${g(c[1])},${g(c[2])})`;
  };
  for (const s of inputs) {
    s.addEventListener('input', () => {
      const c = inputs.map((i) => parseFloat(i.value));
      paint(c);
      write(c);
    });
  }
  controls.set(path, () => {
    const c = read();
    inputs.forEach((s, i) => { if (document.activeElement !== s) s.value = c[i]; s.title = 'RGB'[i] + ' ' + c[i]; });
    paint(c);
  });
}

function vectorControl(parent, label, path, { read, write }) {
  const box = document.createElement('div');
  box.className = 'triple';
  const inputs = [0, 1, 2].map(() => numberInput(0.1));
  inputs.forEach((i) => { i.dataset.path = path; });
  box.append(...inputs);
  row(parent, label, box);
  for (const i of inputs)
    i.addEventListener('change', () => write(inputs.map((x) => parseFloat(x.value))));
  controls.set(path, () => {
    const v = read();
    inputs.forEach((x, k) => { if (document.activeElement !== x) x.value = +(+v[k]).toPrecision(6); });
  });
}

function selectControl(parent, label, path, options, { read, write }) {
  const s = document.createElement('select');
  s.dataset.path = path;
  for (const o of options) s.append(new Option(o, o));
  row(parent, label, s);
  s.addEventListener('change', () => write(s.value));
  controls.set(path, () => { s.value = read(); });
  return s;
}

function checkControl(parent, label, path, { read, write }) {
  const c = document.createElement('input');
  c.type = 'checkbox';
  c.dataset.path = path;
  row(parent, label, c);
  c.addEventListener('change', () => write(c.checked));
  controls.set(path, () => { c.checked = !!read(); });
}

const set = (path, coalesce) => (value) => sendEdits([{ op: 'set', path, value }], coalesce || path);

function buildView(parent) {
  sliderControl(parent, 'exposure (EV)', 'view.exposure', {
    min: -6, max: 6, step: 0.1, read: () => state.view.exposure,
    write: (v) => post('/api/view', { exposure: v }).catch((e) => showMessage(e.message, true)),
  });
  selectControl(parent, 'tone map', 'view.tonemap', ['clamp', 'reinhard', 'aces'], {
    read: () => state.view.tonemap, write: (v) => post('/api/view', { tonemap: v }),
  });
  selectControl(parent, 'pass', 'view.pass',
    ['image', 'ambient', 'diffuse', 'specular', 'reflection', 'transmission', 'normal', 'depth', 'albedo'], {
      read: () => state.view.pass, write: (v) => post('/api/view', { pass: v }),
    });
}

function buildRender(parent) {
  selectControl(parent, 'shading', 'render.shading_model', ['phong', 'blinn-phong'], {
    read: () => at('render.shading_model') || 'phong', write: set('render.shading_model'),
  });
  colorControl(parent, 'background', 'render.background', {
    read: () => asColor(at('render.background'), 0), write: set('render.background'),
  });
  sliderControl(parent, 'max depth', 'render.max_depth', {
    min: 1, max: 16, step: 1, integer: true, read: () => at('render.max_depth') ?? 5,
  });
  sliderControl(parent, 'samples/pixel', 'render.samples_per_pixel', {
    min: 1, max: 64, step: 1, integer: true, read: () => at('render.samples_per_pixel') ?? 1,
  });
}

// Keys that belong to one camera type (the loader refuses them on others).
const CAMERA_KEYS = { perspective: ['fov_y', 'aperture', 'focus_distance'], orthographic: ['view_height'],
  fisheye: ['fov'], equirectangular: [] };
let focusOnClick = false;

function buildCamera(parent) {
  const cam = (key, d) => () => at('camera.' + key) ?? d;
  const type = at('camera.type') || 'perspective';
  selectControl(parent, 'type', 'camera.type', Object.keys(CAMERA_KEYS), {
    read: cam('type', 'perspective'),
    write: (v) => {
      // The other types' keys go first, in the same edit (each step is checked).
      const edits = [];
      for (const [t, keys] of Object.entries(CAMERA_KEYS))
        if (t !== v) for (const k of keys) if (at('camera.' + k) !== undefined) edits.push({ op: 'erase', path: 'camera.' + k });
      edits.push({ op: 'set', path: 'camera.type', value: v });
      sendEdits(edits, 'camera.type');
    },
  });
  vectorControl(parent, 'position', 'camera.position', { read: cam('position', [0, 0, 0]), write: set('camera.position') });
  vectorControl(parent, 'look at', 'camera.look_at', { read: cam('look_at', [0, 0, -1]), write: set('camera.look_at') });
  vectorControl(parent, 'up', 'camera.up', { read: cam('up', [0, 1, 0]), write: set('camera.up') });
  if (type === 'perspective') {
    sliderControl(parent, 'fov y (°)', 'camera.fov_y', { min: 5, max: 120, step: 0.5, read: cam('fov_y', 45) });
    sliderControl(parent, 'aperture', 'camera.aperture', { min: 0, max: 1, step: 0.005, read: cam('aperture', 0) });
    const { pos, look } = cameraNow();
    sliderControl(parent, 'focus distance', 'camera.focus_distance', {
      min: 0.1, max: Math.max(20, 4 * Math.hypot(...sub(look, pos))), step: 0.01,
      read: () => at('camera.focus_distance') ?? Math.hypot(...sub(at('camera.look_at') || [0, 0, -1], at('camera.position') || [0, 0, 0])),
    });
    checkControl(parent, 'click to focus', 'view.focus_click', { read: () => focusOnClick, write: (v) => { focusOnClick = v; } });
  } else if (type === 'orthographic') {
    sliderControl(parent, 'view height', 'camera.view_height', { min: 0.1, max: 100, step: 0.1, read: cam('view_height', 2) });
  } else if (type === 'fisheye') {
    sliderControl(parent, 'fov (°)', 'camera.fov', { min: 1, max: 360, step: 1, read: cam('fov', 180) });
  }
}

// Fog and the environment (render.fog, render.environment).
function buildAtmosphere(parent) {
  const fogType = at('render.fog.type') || 'none';
  selectControl(parent, 'fog', 'render.fog.type', ['none', 'linear', 'exp', 'exp2'], {
    read: () => at('render.fog.type') || 'none',
    write: (v) => {
      if (v === 'none') {
        if (at('render.fog') !== undefined) sendEdits([{ op: 'erase', path: 'render.fog' }], 'render.fog');
        return;
      }
      const { pos, look } = cameraNow();
      const d = Math.hypot(...sub(look, pos));
      const fog = { type: v, color: asColor(at('render.fog.color') ?? at('render.background'), 0.5) };
      if (v === 'linear') Object.assign(fog, { start: 0, end: 3 * d });
      else fog.density = 0.5 / d;
      sendEdits([{ op: 'set', path: 'render.fog', value: fog }], 'render.fog');
    },
  });
  if (fogType !== 'none') {
    colorControl(parent, 'fog color', 'render.fog.color', {
      read: () => asColor(at('render.fog.color') ?? at('render.background'), 0), write: set('render.fog.color'),
    });
    if (fogType === 'linear') {
      sliderControl(parent, 'fog start', 'render.fog.start', { min: 0, max: 200, step: 0.1, read: () => at('render.fog.start') ?? 0 });
      sliderControl(parent, 'fog end', 'render.fog.end', { min: 0.1, max: 400, step: 0.1, read: () => at('render.fog.end') });
    } else {
      sliderControl(parent, 'fog density', 'render.fog.density', { min: 0.001, max: 2, step: 0.001, read: () => at('render.fog.density') });
    }
  }
  if (at('render.environment') !== undefined) {
    sliderControl(parent, 'sky rotate (°)', 'render.environment.rotate', {
      min: -180, max: 180, step: 1, read: () => at('render.environment.rotate') ?? 0,
    });
    colorControl(parent, 'sky scale', 'render.environment.scale', {
      read: () => asColor(at('render.environment.scale'), 1), write: set('render.environment.scale'), max: 4,
    });
  }
}

function buildMaterial(parent, name) {
  if (!name) return;
  const base = materialPath(name);
  const m = (key, d) => () => { const v = at(`materials.${name}`); return v && v[key] !== undefined ? v[key] : d; };
  for (const [key, d] of [['ambient', 0], ['diffuse', 0.8], ['specular', 0], ['reflectivity', 0]])
    colorControl(parent, key, `${base}.${key}`, { read: () => asColor(m(key, d)(), d), write: set(`${base}.${key}`) });
  sliderControl(parent, 'shininess α', `${base}.shininess`, { min: 1, max: 1000, step: 1, read: m('shininess', 32) });
  sliderControl(parent, 'transparency', `${base}.transparency`, { min: 0, max: 1, step: 0.01, read: m('transparency', 0) });
  sliderControl(parent, 'ior', `${base}.ior`, { min: 1, max: 3, step: 0.01, read: m('ior', 1.5) });
  checkControl(parent, 'fresnel', `${base}.fresnel`, { read: m('fresnel', false), write: set(`${base}.fresnel`) });
}

// A light's color: a `color` key stands for diffuse and specular (L_a for an
// ambient light); editing one of those splits it into its own keys.
function lightColorWrite(i, light, key) {
  return (value) => {
    const p = `lights[${i}]`;
    const edits = [];
    if (light.color !== undefined) {
      edits.push({ op: 'erase', path: `${p}.color` });
      if (light.type !== 'ambient')
        for (const k of ['diffuse', 'specular']) if (k !== key) edits.push({ op: 'set', path: `${p}.${k}`, value: light.color });
    }
    edits.push({ op: 'set', path: `${p}.${key}`, value });
    sendEdits(edits, `${p}.${key}`);
  };
}

function buildLights(parent) {
  (at('lights') || []).forEach((light, i) => {
    const box = document.createElement('div');
    box.className = 'light';
    const h = document.createElement('h3');
    h.textContent = `${i}: ${light.type}${light.name ? ' "' + light.name + '"' : ''}`;
    box.append(h);
    parent.append(box);
    const p = `lights[${i}]`;
    const get = (key, d) => () => { const v = at(p); return v && v[key] !== undefined ? v[key] : d; };
    const colorOf = (key, d) => () => {
      const v = at(p) || {};
      if (v.color !== undefined && (v.type === 'ambient' ? key === 'ambient' : key !== 'ambient')) return asColor(v.color, d);
      return asColor(v[key], d);
    };
    const t = light.type;
    if (t === 'point' || t === 'spot') vectorControl(box, 'position', `${p}.position`, { read: get('position', [0, 0, 0]), write: set(`${p}.position`) });
    if (t === 'directional' || t === 'spot') vectorControl(box, 'direction', `${p}.direction`, { read: get('direction', [0, -1, 0]), write: set(`${p}.direction`) });
    if (t === 'area') {
      for (const key of ['corner', 'edge_u', 'edge_v'])
        vectorControl(box, key, `${p}.${key}`, { read: get(key, [0, 0, 0]), write: set(`${p}.${key}`) });
      sliderControl(box, 'samples', `${p}.samples`, { min: 1, max: 256, step: 1, integer: true, read: get('samples', 16) });
    }
    const keys = t === 'ambient' ? [['ambient', 0]] : [['ambient', 0], ['diffuse', 1], ['specular', 1]];
    for (const [key, d] of keys)
      colorControl(box, 'L ' + key.slice(0, 1) + ' ' + key, `${p}.${key}`, { read: colorOf(key, d), write: lightColorWrite(i, light, key), max: 2 });
    if (t === 'spot') {
      sliderControl(box, 'cutoff (°)', `${p}.cutoff`, { min: 0, max: 90, step: 0.5, read: get('cutoff', 180) });
      sliderControl(box, 'falloff', `${p}.falloff`, { min: 0, max: 64, step: 0.5, read: get('falloff', 0) });
    }
    if (t === 'point' || t === 'spot' || t === 'area')
      vectorControl(box, 'attenuation', `${p}.attenuation`, { read: get('attenuation', [1, 0, 0]), write: set(`${p}.attenuation`) });
  });
}

function rebuild() {
  controls.clear();
  for (const id of ['view-controls', 'render-controls', 'camera-controls', 'material-controls', 'light-controls']) $(id).textContent = '';
  const names = Object.keys(at('materials') || {});
  if (!names.includes(selectedMaterial)) selectedMaterial = names[0] || null;
  const sel = $('material-select');
  sel.textContent = '';
  for (const n of names) sel.append(new Option(n, n));
  sel.value = selectedMaterial || '';
  buildView($('view-controls'));
  buildRender($('render-controls'));
  buildAtmosphere($('render-controls'));
  buildCamera($('camera-controls'));
  buildMaterial($('material-controls'), selectedMaterial);
  buildLights($('light-controls'));
}

function refreshValues() {
  for (const update of controls.values()) update();
}

$('material-select').addEventListener('change', (e) => { selectMaterial(e.target.value); });
$('material-select').addEventListener('click', (e) => e.stopPropagation());
function selectMaterial(name) {
  selectedMaterial = name;
  structure = '';
  applyState(state);
}

// --- state and frames from the server ------------------------------------------------

function applyState(s) {
  state = preview.state = s;
  $('file').textContent = s.file;
  document.title = `glint · ${s.file}${s.dirty ? ' ●' : ''}`;
  $('dirty').hidden = !s.dirty;
  const error = $('error');
  error.textContent = s.error;
  error.hidden = !s.error;
  $('conflict').hidden = !s.conflict;
  $('undo').disabled = !s.can_undo;
  $('redo').disabled = !s.can_redo;
  $('save').disabled = !s.can_overwrite;
  setStatus();
  if (s.notice_seq !== applyState.noticeSeq) {
    if (applyState.noticeSeq !== undefined && s.notice) showMessage(s.notice, false);
    applyState.noticeSeq = s.notice_seq;
  }
  const lights = (s.scene.lights || []).map((l) => l.type + (l.color !== undefined ? 'c' : '')).join(',');
  // Controls that depend on a type are built again when it changes.
  const kinds = [(s.scene.camera || {}).type, ((s.scene.render || {}).fog || {}).type, !!(s.scene.render || {}).environment];
  const shape = [Object.keys(s.scene.materials || {}).join('|'), lights, selectedMaterial, ...kinds].join('/');
  if (shape !== structure) {
    structure = shape;
    rebuild();
  }
  refreshValues();
  const canvas = $('frame');
  if (canvas.width !== s.width || canvas.height !== s.height) {
    canvas.width = s.width;
    canvas.height = s.height;
  }
  changed();
}

let lastFrameTime = 0;
function setStatus() {
  const st = $('status');
  const busy = state && (state.rendering || preview.editsInFlight > 0);
  st.textContent = busy ? 'rendering…' : preview.frame ? `ready · ${preview.frame.render_ms.toFixed(0)} ms` : 'waiting…';
  st.classList.toggle('busy', !!busy);
}

let drawnSeq = 0;
async function showFrame(f) {
  const response = await fetch(`/frame/${f.seq}.png`);
  if (!response.ok || f.seq <= drawnSeq) return;
  const bitmap = await createImageBitmap(await response.blob());
  if (f.seq <= drawnSeq) return;
  drawnSeq = f.seq;
  const canvas = $('frame');
  const ctx = canvas.getContext('2d', { willReadFrequently: true });
  // A coarse frame is scaled up with its pixels visible (no smoothing).
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
  bitmap.close();
  preview.frame = f;
  preview.frames++;
  lastFrameTime = performance.now();
  preview.lastFrameTime = lastFrameTime;
  if (!f.coarse) {
    $('download-png').href = `/frame/${f.seq}.png?download`;
    $('download-pfm').href = `/frame/${f.seq}.pfm`;
  }
  setStatus();
  changed();
}

// One event stream while the tab is visible: a hidden tab costs the server
// nothing (it renders only for open streams).
let events = null;
function connect() {
  if (events || document.hidden) return;
  events = new EventSource('/events');
  events.addEventListener('state', (e) => applyState(JSON.parse(e.data)));
  events.addEventListener('frame', (e) => showFrame(JSON.parse(e.data)));
  events.onerror = () => { $('status').textContent = 'disconnected: retrying…'; };
}
function disconnect() {
  if (events) events.close();
  events = null;
}
document.addEventListener('visibilitychange', () => (document.hidden ? disconnect() : connect()));
connect();

// --- buttons and keys ---------------------------------------------------------------

const act = (fn) => () => fn().catch((e) => showMessage(e.message, true));
$('undo').addEventListener('click', act(() => post('/api/undo', {})));
$('redo').addEventListener('click', act(() => post('/api/undo', { redo: true })));
$('reset').addEventListener('click', act(() => post('/api/reset', {})));
const save = act(async () => {
  if (!confirm(`Overwrite ${state.file} with the edited scene?`)) return;
  await post('/api/save', { mode: 'overwrite' });
});
$('save').addEventListener('click', save);
$('save-new').addEventListener('click', act(() => post('/api/save', { mode: 'new' })));
$('take-file').addEventListener('click', act(() => post('/api/resolve', { keep: 'file' })));
$('keep-mine').addEventListener('click', act(() => post('/api/resolve', { keep: 'mine' })));
document.addEventListener('keydown', (e) => {
  if (!(e.ctrlKey || e.metaKey)) return;
  const k = e.key.toLowerCase();
  if (k === 'z' && !e.shiftKey) { e.preventDefault(); $('undo').click(); }
  else if ((k === 'z' && e.shiftKey) || k === 'y') { e.preventDefault(); $('redo').click(); }
  else if (k === 's') { e.preventDefault(); if (state && state.can_overwrite) save(); else $('save-new').click(); }
});

// --- the camera by mouse, and a click explains a pixel --------------------------------

const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const scale = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => scale(a, 1 / Math.hypot(...a));

function cameraNow() {
  return { pos: at('camera.position') || [0, 0, 0], look: at('camera.look_at') || [0, 0, -1], up: at('camera.up') || [0, 1, 0] };
}
function sendCamera(pos, look) {
  sendEdits([{ op: 'set', path: 'camera.position', value: pos }, { op: 'set', path: 'camera.look_at', value: look }], 'camera');
}

const canvas = $('frame');
let drag = null;
canvas.addEventListener('contextmenu', (e) => e.preventDefault());
canvas.addEventListener('pointerdown', (e) => {
  if (!state) return;
  canvas.setPointerCapture(e.pointerId);
  drag = { x: e.clientX, y: e.clientY, moved: false, pan: e.shiftKey || e.button !== 0, cam: cameraNow() };
});
canvas.addEventListener('pointermove', (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  if (!drag.moved && Math.hypot(dx, dy) < 4) return;
  drag.moved = true;
  const { pos, look, up } = drag.cam;
  const offset = sub(pos, look);
  const dist = Math.hypot(...offset);
  if (drag.pan) {
    const forward = norm(scale(offset, -1));
    const right = norm(cross(forward, up));
    const camUp = cross(right, forward);
    const k = dist * 0.0025;
    const move = add(scale(right, -dx * k), scale(camUp, dy * k));
    sendCamera(add(pos, move), add(look, move));
  } else {
    // Orbit around look_at: azimuth about the up axis, elevation kept off the poles.
    const u = norm(up);
    const height = dot(offset, u);
    const flat = sub(offset, scale(u, height));
    let azimuth = -dx * 0.008;
    let elevation = Math.atan2(height, Math.hypot(...flat)) + dy * 0.008;
    elevation = Math.max(-1.5, Math.min(1.5, elevation));
    const f = Math.hypot(...flat) > 1e-9 ? norm(flat) : norm(cross(u, [1, 0, 0]));
    const side = cross(u, f);
    const dir = add(scale(f, Math.cos(azimuth)), scale(side, Math.sin(azimuth)));
    const o = add(scale(dir, dist * Math.cos(elevation)), scale(u, dist * Math.sin(elevation)));
    sendCamera(add(look, o), look);
  }
});
canvas.addEventListener('pointerup', (e) => {
  const d = drag;
  drag = null;
  if (!d || d.moved || !state) return;
  const r = canvas.getBoundingClientRect();
  const x = Math.floor(((e.clientX - r.left) / r.width) * canvas.width);
  const y = Math.floor(((e.clientY - r.top) / r.height) * canvas.height);
  explainPixel(x, y);
});
canvas.addEventListener('wheel', (e) => {
  if (!state) return;
  e.preventDefault();
  const { pos, look } = cameraNow();
  const k = Math.exp(Math.max(-0.5, Math.min(0.5, e.deltaY * 0.001)));
  sendCamera(add(look, scale(sub(pos, look), k)), look);
}, { passive: false });

// --- the ray tree ------------------------------------------------------------------

const fmt = (x) => (x === null || x === undefined ? '–' : typeof x === 'number' ? String(+x.toPrecision(6)) : String(x));
const fmtRgb = (c) => (c ? `[${c.map(fmt).join(', ')}]` : '–');
function chip(c) {
  const s = document.createElement('span');
  s.className = 'chip';
  const g = (x) => Math.round(255 * Math.min(1, Math.max(0, x)) ** (1 / 2.2));
  if (c) s.style.background = `rgb(${g(c[0])},${g(c[1])},${g(c[2])})`;
  return s;
}
function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (cls) e.className = cls;
  return e;
}

function nodeView(node, label) {
  const d = document.createElement('details');
  d.open = node.depth <= 2;
  const s = document.createElement('summary');
  s.append(chip(node.color), `${label} · depth ${node.depth} · `);
  if (!node.hit) s.append(node.environment ? `miss (environment at uv ${fmtRgb(node.environment.uv)}) ` : 'miss (background) ');
  else s.append(`hit ${node.hit.name ? '"' + node.hit.name + '"' : '#' + node.hit.object} (${node.hit.type || 'object'}), material ${node.hit.material}, t = ${fmt(node.hit.t)} `);
  s.append(el('span', `color ${fmtRgb(node.color)}`, 'rgb'));
  d.append(s);
  const h = node.hit;
  if (!h) return d;
  d.append(el('div', `point ${fmtRgb(h.point)} · normal ${fmtRgb(h.normal)}`, 'muted'));
  if (h.csg) d.append(el('div', `csg solid #${h.csg.child}${h.csg.name ? ' "' + h.csg.name + '"' : ''}${h.csg.flipped ? ' (subtracted)' : ''}`, 'muted'));
  if (node.fog) d.append(el('div', `fog: f ${fmt(node.fog.f)} of the shaded color, the rest ${fmtRgb(node.fog.color)}`, 'muted'));
  for (const l of h.lights || [])
    if (l.occlusion) d.append(el('div', `ambient occlusion (light ${l.index}): ${fmt(l.occlusion.visibility)} of ${l.occlusion.samples} directions open`, 'muted'));
  const table = document.createElement('table');
  const head = document.createElement('tr');
  for (const t of ['light', 'type', 'l·n', 'shadowed', 'spec cos', 'ambient', 'diffuse', 'specular']) head.append(el('th', t));
  table.append(head);
  for (const l of h.lights || []) {
    const tr = document.createElement('tr');
    tr.dataset.light = l.index;
    const cells = [l.index, l.type, fmt(l.n_dot_l), l.shadowed ? `yes, by #${l.blocker}` : 'no', fmt(l.specular_cos),
      fmtRgb(l.ambient), fmtRgb(l.diffuse), fmtRgb(l.specular)];
    for (const c of cells) tr.append(el('td', String(c)));
    table.append(tr);
  }
  d.append(table);
  if (h.reflection) d.append(nodeView(h.reflection.ray, `reflection × ${fmtRgb(h.reflection.weight)}`));
  if (h.refraction) d.append(nodeView(h.refraction.ray, `refraction × ${fmtRgb(h.refraction.weight)}`));
  return d;
}

async function explainPixel(x, y) {
  try {
    const tree = await post('/api/explain', { x, y });
    preview.lastExplain = tree;
    const box = $('tree');
    box.textContent = '';
    box.classList.remove('muted');
    box.append(el('div', `pixel (${x}, ${y}) · color ${fmtRgb(tree.color)}`));
    box.append(nodeView(tree.ray, 'camera ray'));
    // Click to focus: the plane in focus through the point hit.
    if (focusOnClick && tree.ray.hit && (at('camera.type') || 'perspective') === 'perspective') {
      const { pos, look } = cameraNow();
      const d = dot(sub(tree.ray.hit.point, pos), norm(sub(look, pos)));
      if (d > 0) sendEdits([{ op: 'set', path: 'camera.focus_distance', value: d }], 'camera.focus_distance');
    }
    // Clicking an object selects its material.
    if (tree.ray.hit && tree.ray.hit.material && tree.ray.hit.material !== selectedMaterial &&
        (state.scene.materials || {})[tree.ray.hit.material] !== undefined)
      selectMaterial(tree.ray.hit.material);
  } catch (e) {
    showMessage(e.message, true);
  }
  changed();
}
preview.explainPixel = explainPixel;
