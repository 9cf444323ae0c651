// glint serve in a real browser (Debian's chromium through playwright-core):
// frames equal `glint render`, the ray tree equals `glint explain --json`,
// the file stays the truth, saves re-render byte for byte, foreign origins
// are refused, and a soak of edits from two tabs keeps memory flat.
// Run by tests/browser/run.sh (CTest: Browser.serve). No sleeps: every wait
// is for a condition, bounded by the test's timeout.
'use strict';
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const { spawn, execFileSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const http = require('node:http');
const readline = require('node:readline');
const { chromium } = require('playwright-core');

const GLINT = process.env.GLINT;
// Under AddressSanitizer freed memory sits in a quarantine (up to 256 MB), so
// resident memory says nothing about leaks there: LeakSanitizer at the
// server's clean exit (the last test) does that job instead.
const SANITIZED = process.env.GLINT_SANITIZED === '1';
const SOURCE = process.env.GLINT_SOURCE_DIR;
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'glint-browser-'));
const scenePath = path.join(work, 'scene.json');
// The showcase at 480 x 270 (a coarse frame, then the full one), 1 spp; at a
// quarter of the pixels under the sanitizers, whose renders are 20x slower.
const [W, H] = SANITIZED ? [240, 135] : [480, 270];
const base = JSON.parse(fs.readFileSync(path.join(SOURCE, 'scenes/showcase.json'), 'utf8'));
base.render.width = W;
base.render.height = H;
base.render.samples_per_pixel = 1;
fs.writeFileSync(scenePath, JSON.stringify(base, null, 2));

let server = null, url = null, context = null, page = null, userData = null;
const pageRequests = [];  // every URL the first page asked for
const pageErrors = [];    // console errors and failed requests of the first page
const serverOutput = [];

function startServer(scene) {
  return new Promise((resolve, reject) => {
    const proc = spawn(GLINT, ['serve', scene, '--port', '0', '--threads', '2'], { stdio: ['ignore', 'pipe', 'pipe'] });
    proc.stderr.on('data', (d) => serverOutput.push(String(d)));
    proc.on('exit', (code) => reject(new Error(`glint serve exited (${code}): ${serverOutput.join('')}`)));
    // The printed address is the signal that the port is bound.
    readline.createInterface({ input: proc.stdout }).on('line', (line) => {
      const m = /^glint serve: (http:\/\/\S+)\/$/.exec(line);
      if (m) resolve({ proc, url: m[1] });
    });
  });
}

// Resolves with the exit code (null when it had to be killed).
function stopServer(proc) {
  if (!proc || proc.exitCode !== null || proc.signalCode !== null) return Promise.resolve(proc ? proc.exitCode : null);
  return new Promise((resolve) => {
    const timer = setTimeout(() => proc.kill('SIGKILL'), 20000);
    proc.removeAllListeners('exit');
    proc.on('exit', (code) => { clearTimeout(timer); resolve(code); });
    proc.kill('SIGTERM');
  });
}

before(async () => {
  ({ proc: server, url } = await startServer(scenePath));
  userData = fs.mkdtempSync(path.join(os.tmpdir(), 'glint-chromium-'));
  context = await chromium.launchPersistentContext(userData, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run', '--force-color-profile=srgb'],
    viewport: { width: 1280, height: 800 },
  });
  page = context.pages()[0] || (await context.newPage());
  page.on('dialog', (d) => d.accept());
  page.on('request', (r) => pageRequests.push(r.url()));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  page.on('response', (r) => { if (r.status() >= 400) pageErrors.push(`${r.status()} ${r.url()}`); });
  await page.goto(url + '/');
});

after(async () => {
  // Whatever happened: the browser and the server go, and so do our files.
  try { if (context) await context.close(); } catch (e) { /* already gone */ }
  await stopServer(server);
  fs.rmSync(work, { recursive: true, force: true });
  if (userData) fs.rmSync(userData, { recursive: true, force: true });
});

// --- helpers ---------------------------------------------------------------

// Waits until `fn(arg)`, run in the page, is true: checked again at each
// change the page announces (its "glintpreview" event), never by sleeping.
// (Not page.waitForFunction: it evaluates strings, which the page's
// Content-Security-Policy forbids.)
async function until(p, fn, arg, timeout = 20000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    if (await p.evaluate(fn, arg)) return;
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${fn} ${JSON.stringify(arg)}`);
    // The next change, or a second at most (a guard against a missed event).
    await p.evaluate(() => new Promise((resolve) => {
      window.addEventListener('glintpreview', resolve, { once: true });
      setTimeout(resolve, 1000);
    }));
  }
}

// The page is settled: no edit in flight and a full frame of the newest
// scene and view on screen; `want` maps state paths ("scene.render.background",
// "view.exposure", "dirty") to the values they must have.
function settled(p = page, want = {}) {
  return until(p, (want) => {
    const g = window.glintPreview, s = g.state, f = g.frame;
    if (!(s && f && g.editsInFlight === 0 && !f.coarse && s.version >= g.lastEditVersion &&
      f.scene_version === s.scene_version && f.pass === s.view.pass && f.exposure === s.view.exposure &&
      f.tonemap === s.view.tonemap && !s.rendering)) return false;
    for (const [path, value] of Object.entries(want)) {
      let x = s;
      for (const key of path.split('.')) x = x === undefined || x === null ? undefined : x[key];
      if (JSON.stringify(x) !== JSON.stringify(value)) return false;
    }
    return true;
  }, want);
}

// A range input moved as a user would: its value, then the input event.
const setRange = (selector, value, p = page) => p.locator(selector).evaluate((el, v) => {
  el.value = v;
  el.dispatchEvent(new Event('input', { bubbles: true }));
}, String(value));

// Rendered images go to a folder of their own: files appearing in the
// scene's folder would wake the watcher (it watches folders, and ignores
// names it does not watch).
const renderFolder = path.join(work, 'renders');
fs.mkdirSync(renderFolder);
function glintRender(scene, extra = []) {
  const out = path.join(renderFolder, `expected-${Date.now()}-${Math.random().toString(36).slice(2)}.png`);
  execFileSync(GLINT, ['render', scene, '-o', out, '-q', ...extra]);
  return out;
}

function writeScene(doc, name = 'variant.json') {
  const file = path.join(work, name);
  fs.writeFileSync(file, JSON.stringify(doc));
  return file;
}

// How many bytes of the canvas differ from the PNG file (decoded by the browser).
async function diffWithPng(pngFile, p = page) {
  const b64 = fs.readFileSync(pngFile).toString('base64');
  return p.evaluate(async (data) => {
    const bytes = Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
    const bmp = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const off = new OffscreenCanvas(bmp.width, bmp.height);
    const octx = off.getContext('2d');
    octx.drawImage(bmp, 0, 0);
    const want = octx.getImageData(0, 0, bmp.width, bmp.height).data;
    const canvas = document.getElementById('frame');
    if (canvas.width !== bmp.width || canvas.height !== bmp.height) return -1;
    const got = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    let diff = 0;
    for (let i = 0; i < got.length; ++i) if (got[i] !== want[i]) ++diff;
    return diff;
  }, b64);
}

const canvasHash = (p = page) => p.evaluate(() => {
  const c = document.getElementById('frame');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let h = 2166136261;
  for (let i = 0; i < d.length; ++i) h = Math.imul(h ^ d[i], 16777619);
  return h >>> 0;
});

function request(pathname, { method = 'GET', headers = {}, body } = {}, base = url) {
  const u = new URL(base);
  return new Promise((resolve, reject) => {
    const req = http.request({ host: u.hostname, port: u.port, path: pathname, method, headers }, (res) => {
      let text = '';
      res.on('data', (d) => { text += d; });
      res.on('end', () => resolve({ status: res.statusCode, text }));
    });
    req.on('error', reject);
    if (body) req.write(body);
    req.end();
  });
}

const serverState = async (base = url) => JSON.parse((await request('/api/state', {}, base)).text);

// Asks the server for its state until `fn(state)` holds: each answer is an
// event, and nothing else would tell (a tab's stream would count as a tab).
async function untilState(fn, base = url, timeout = 20000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const s = await serverState(base);
    if (fn(s)) return s;
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${fn}`);
    await new Promise(setImmediate);
  }
}

// --- is the server asleep? (/proc of its process) ----------------------------

// Whether a thread is blocked in a system call without a timeout (it runs
// again only when something happens), from /proc/PID/task/TID/syscall: the
// call's number and arguments, x86-64 numbering.
function blockedForGood(line) {
  const parts = line.trim().split(/\s+/);
  if (parts.length < 7 || !/^\d+$/.test(parts[0])) return false;  // "running", or not in a call
  const arg = (i) => BigInt(parts[1 + i]);
  const infinite = (v) => (v & 0xffffffffn) >= 0x80000000n;  // an int timeout < 0
  switch (Number(parts[0])) {
    case 202: return arg(3) === 0n;                 // futex, no timeout
    case 7: return infinite(arg(2));                // poll
    case 271: return arg(2) === 0n;                 // ppoll
    case 232: case 281: return infinite(arg(3));    // epoll_wait, epoll_pwait
    case 23: case 270: return arg(4) === 0n;        // select, pselect6
    case 0: case 43: case 45: case 288: return true;  // read, accept, recvfrom, accept4
    case 128: return arg(2) === 0n;                 // rt_sigtimedwait (sigwait)
    default: return false;
  }
}

function threadsAwake(pid) {
  const awake = [];
  for (const tid of fs.readdirSync(`/proc/${pid}/task`)) {
    let line, name;
    try {
      line = fs.readFileSync(`/proc/${pid}/task/${tid}/syscall`, 'utf8');
      name = fs.readFileSync(`/proc/${pid}/task/${tid}/comm`, 'utf8').trim();
    } catch (e) {
      continue;  // the thread ended meanwhile
    }
    if (!blockedForGood(line)) awake.push(`${tid} ${name}: ${line.trim()}`);
  }
  return awake;
}

// Until every thread of the server sleeps for good: those that served the
// last requests get back to their queue a moment after the answers left.
async function untilAsleep(pid, timeout = 15000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const awake = threadsAwake(pid);
    if (!awake.length) return;
    if (Date.now() > deadline) throw new Error('threads of glint serve still awake: ' + awake.join('; '));
    await new Promise(setImmediate);
  }
}

// The CPU time (clock ticks, user and system) and the context switches of
// every thread of a process: a thread that runs at all changes the latter.
function cpuUse(pid) {
  const stat = fs.readFileSync(`/proc/${pid}/stat`, 'utf8');
  const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
  const use = { ticks: Number(fields[11]) + Number(fields[12]), switches: 0 };
  for (const tid of fs.readdirSync(`/proc/${pid}/task`)) {
    const status = fs.readFileSync(`/proc/${pid}/task/${tid}/status`, 'utf8');
    for (const m of status.matchAll(/^(?:non)?voluntary_ctxt_switches:\s+(\d+)$/gm)) use.switches += Number(m[1]);
  }
  return use;
}

// A page of its own for a test, its dialogs accepted.
async function newPage(address) {
  const p = await context.newPage();
  p.on('dialog', (d) => d.accept());
  await p.goto(address + '/');
  return p;
}

const rss = () => {
  const m = /VmRSS:\s+(\d+) kB/.exec(fs.readFileSync(`/proc/${server.pid}/status`, 'utf8'));
  return Number(m[1]) * 1024;
};

// --- the tests (in order: each starts from the state the one before left) ---

test('the page shows the scene as glint render draws it', async () => {
  await settled();
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
  const title = await page.textContent('#file');
  assert.equal(title, 'scene.json');
  // Everything the page needs comes from glint itself: no CDN, no network.
  assert.ok(pageRequests.length >= 4, pageRequests.join(' '));
  for (const r of pageRequests) assert.ok(r.startsWith(url + '/'), r);
  // Loaded with nothing in the console: no missing icon, no failed request.
  assert.deepEqual(pageErrors, []);
  const svg = await fetch(url + '/favicon.svg');
  assert.equal(svg.status, 200);
  assert.equal(svg.headers.get('content-type'), 'image/svg+xml');
  assert.equal((await fetch(url + '/favicon.ico')).status, 204);
});

test('the file stays the truth: in place, by rename, broken', async () => {
  const before = await canvasHash();
  // In place.
  const a = structuredClone(base);
  a.render.background = [0.3, 0.1, 0.1];
  fs.writeFileSync(scenePath, JSON.stringify(a, null, 2));
  await settled(page, { 'scene.render.background': [0.3, 0.1, 0.1] });
  assert.notEqual(await canvasHash(), before);
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
  // By rename, as editors save.
  const b = structuredClone(base);
  b.materials.red.diffuse = [0.1, 0.8, 0.1];
  const tmp = path.join(work, '.scene.json.swp');
  fs.writeFileSync(tmp, JSON.stringify(b, null, 2));
  fs.renameSync(tmp, scenePath);
  await settled(page, { 'scene.materials.red.diffuse': [0.1, 0.8, 0.1] });
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
  // Broken: the loader's error, the last good image kept.
  const good = await canvasHash();
  fs.writeFileSync(scenePath, `{\n  "render": { "width": ${W}, "height": -5 }\n}\n`);
  await until(page, () => !document.getElementById('error').hidden);
  const error = await page.textContent('#error');
  assert.match(error, /^error: .*scene\.json:2:\d+: /);
  assert.equal(await canvasHash(), good);
  // Fixed again.
  fs.writeFileSync(scenePath, JSON.stringify(base, null, 2));
  await until(page, () => document.getElementById('error').hidden);
  await settled(page, { 'scene.materials.red.diffuse': [0.8, 0.15, 0.12] });
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
});

test('a slider changes the frame to glint render of the same parameters', async () => {
  const before = await canvasHash();
  // The material panel shows the one chosen in its list.
  await page.selectOption('#material-select', 'red');
  await setRange('input[type=range][data-path="materials.red.shininess"]', 7);
  await settled(page, { 'scene.materials.red.shininess': 7 });
  assert.notEqual(await canvasHash(), before);
  const edited = structuredClone(base);
  edited.materials.red.shininess = 7;
  assert.equal(await diffWithPng(glintRender(writeScene(edited))), 0);
  // Exposure and tone map are the view's: as glint render --exposure --tonemap.
  await setRange('input[type=range][data-path="view.exposure"]', 1.5);
  await page.selectOption('select[data-path="view.tonemap"]', 'reinhard');
  await settled(page, { 'view.exposure': 1.5, 'view.tonemap': 'reinhard' });
  assert.equal(await diffWithPng(glintRender(writeScene(edited), ['--exposure', '1.5', '--tonemap', 'reinhard'])), 0);
  await setRange('input[type=range][data-path="view.exposure"]', 0);
  await page.selectOption('select[data-path="view.tonemap"]', 'clamp');
  // A pass: as glint render --passes writes its file.
  await page.selectOption('select[data-path="view.pass"]', 'normal');
  await settled(page, { 'view.pass': 'normal', 'view.exposure': 0, 'view.tonemap': 'clamp' });
  const withPasses = glintRender(writeScene(edited), ['--passes', 'normal']);
  assert.equal(await diffWithPng(withPasses.replace(/\.png$/, '.normal.png')), 0);
  await page.selectOption('select[data-path="view.pass"]', 'image');
  // A bad value is refused with the loader's message; the scene is unchanged.
  const r = await page.evaluate(() => fetch('/api/edit', { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ edits: [{ op: 'set', path: 'materials.red.shininess', value: -3 }] }) })
    .then(async (x) => ({ status: x.status, body: await x.json() })));
  assert.equal(r.status, 400);
  assert.match(r.body.error, /materials\.red\.shininess: must be > 0/);
  await settled(page, { 'view.exposure': 0, 'view.tonemap': 'clamp', 'scene.materials.red.shininess': 7 });
});

test('clicking a pixel shows the tree of glint explain --json and selects its material', async () => {
  const [x, y] = [Math.round(140 * W / 480), Math.round(170 * H / 270)];  // on the red ball
  const box = await page.locator('#frame').boundingBox();
  await page.mouse.click(box.x + (x + 0.5) * box.width / W, box.y + (y + 0.5) * box.height / H);
  await until(page, () => window.glintPreview.lastExplain !== null);
  const shown = await page.evaluate(() => window.glintPreview.lastExplain);
  const edited = structuredClone(base);
  edited.materials.red.shininess = 7;
  const expected = JSON.parse(execFileSync(GLINT, ['explain', writeScene(edited), '--pixel', String(x), String(y), '--json']));
  assert.deepEqual(shown, expected);
  assert.equal(expected.ray.hit.material, 'red');
  assert.equal(await page.inputValue('#material-select'), 'red');
  // The tree on the page shows the numbers: l·n of the point light.
  const nDotL = expected.ray.hit.lights[1].n_dot_l;
  const row = await page.textContent('#tree tr[data-light="1"]');
  assert.ok(row.includes(String(+nDotL.toPrecision(6))), row);
});

test('undo, redo and reset by the keyboard and buttons; the downloads are the frame', async () => {
  const edited = structuredClone(base);
  edited.materials.red.shininess = 7;
  const editedPng = glintRender(writeScene(edited, 'undo-edited.json'));
  const filePng = glintRender(scenePath);
  await page.locator('#frame').focus();
  await page.keyboard.press('Control+z');
  await settled(page, { 'scene.materials.red.shininess': base.materials.red.shininess, dirty: false, can_redo: true });
  assert.equal(await diffWithPng(filePng), 0);
  await page.keyboard.press('Control+Shift+z');
  await settled(page, { 'scene.materials.red.shininess': 7, dirty: true, can_redo: false });
  assert.equal(await diffWithPng(editedPng), 0);
  await page.click('#reset');
  await settled(page, { 'scene.materials.red.shininess': base.materials.red.shininess, dirty: false });
  assert.equal(await diffWithPng(filePng), 0);
  await page.click('#undo');  // the reset is a step too
  await settled(page, { 'scene.materials.red.shininess': 7, dirty: true });
  assert.equal(await diffWithPng(editedPng), 0);
  // The download links: the frame on screen as PNG, its exact values as PFM,
  // the files glint render writes, byte for byte.
  const links = await page.evaluate(() => [document.getElementById('download-png').href, document.getElementById('download-pfm').href]);
  const png = await page.evaluate((u) => fetch(u).then(async (r) => [r.headers.get('content-disposition'), [...new Uint8Array(await r.arrayBuffer())]]), links[0]);
  assert.match(png[0], /attachment; filename="glint\.png"/);
  assert.deepEqual(Buffer.from(png[1]), fs.readFileSync(editedPng));
  const pfmFile = editedPng.replace(/\.png$/, '.pfm');
  execFileSync(GLINT, ['render', path.join(work, 'undo-edited.json'), '-o', pfmFile, '-q']);
  const pfm = await page.evaluate((u) => fetch(u).then(async (r) => [...new Uint8Array(await r.arrayBuffer())]), links[1]);
  assert.deepEqual(Buffer.from(pfm), fs.readFileSync(pfmFile));
});

test('save over the file and as a new file: glint render gives the image on screen', async () => {
  await settled();
  await page.click('#save');  // the dialog is accepted
  await until(page, () => !window.glintPreview.state.dirty && /saved scene\.json/.test(window.glintPreview.state.notice));
  assert.equal(JSON.parse(fs.readFileSync(scenePath, 'utf8')).materials.red.shininess, 7);
  // (the watcher sees the saved file: it holds what is on screen, so no frame is rendered again)
  await settled(page, { dirty: false });
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
  await page.click('#save-new');
  await until(page, () => /saved as scene-edited\.json/.test(window.glintPreview.state.notice));
  await settled();
  assert.equal(await diffWithPng(glintRender(path.join(work, 'scene-edited.json'))), 0);
  await settled();
});

test('unsaved edits and a changed file: the page asks', async () => {
  await setRange('input[type=range][data-path="materials.red.shininess"]', 20);
  await settled(page, { dirty: true });
  const changed = JSON.parse(fs.readFileSync(scenePath, 'utf8'));
  changed.render.background = [0, 0.3, 0];
  fs.writeFileSync(scenePath, JSON.stringify(changed));
  await until(page, () => !document.getElementById('conflict').hidden);
  await page.click('#take-file');
  await settled(page, { conflict: false, dirty: false, 'scene.render.background': [0, 0.3, 0] });
  assert.equal(await diffWithPng(glintRender(scenePath)), 0);
});

test('no CPU while nothing changes, with a tab open or with none', async (t) => {
  if (process.arch !== 'x64') return t.skip('the system call numbers are x86-64\'s');
  await settled();
  const doc = (await serverState()).scene;
  const file = writeScene(doc);
  // A tab is open and nothing changes: every thread of the server sleeps in
  // a call without a timeout (so only an event can wake it)...
  await untilAsleep(server.pid);
  // ...and stays asleep: not a clock tick, not one context switch, across
  // the window in which glint render draws the same scene (into another
  // folder than the scene's, whose changes the watcher would look at).
  const quiet = cpuUse(server.pid);
  const start = Date.now();
  const expected = glintRender(file);
  const window1 = Date.now() - start;
  assert.deepEqual(cpuUse(server.pid), quiet);
  assert.equal(await diffWithPng(expected), 0);
  // No tab: its stream is let go of at once. A change of the file is read,
  // not rendered, and then the server sleeps again.
  const renders = (await serverState()).stats.renders;
  await page.goto('about:blank');
  const before = await untilState((s) => s.stats.tabs === 0);
  const changed = structuredClone(doc);
  changed.render.background = [0.2, 0.2, 0.3];
  fs.writeFileSync(scenePath, JSON.stringify(changed, null, 2));
  await untilState((s) => s.scene_version > before.scene_version);
  await untilAsleep(server.pid);
  const idle = cpuUse(server.pid);
  const start2 = Date.now();
  const expectedChanged = glintRender(scenePath);
  const window2 = Date.now() - start2;
  assert.deepEqual(cpuUse(server.pid), idle);
  assert.equal((await serverState()).stats.renders, renders);
  // A tab again: the file as it is now.
  await page.goto(url + '/');
  await settled(page, { 'scene.render.background': [0.2, 0.2, 0.3] });
  assert.equal(await diffWithPng(expectedChanged), 0);
  t.diagnostic(`asleep: no tick and no context switch in ${window1} ms with a tab, ${window2} ms without`);
});

test('meshes and textures are read once; a changed one is read again and shown', async () => {
  const dir = path.join(work, 'textures');
  fs.mkdirSync(dir);
  for (const f of ['torus.obj', 'torus.mtl', 'bricks.png', 'uv-grid.png'])
    fs.copyFileSync(path.join(SOURCE, 'scenes/textures', f), path.join(dir, f));
  const doc = JSON.parse(fs.readFileSync(path.join(SOURCE, 'scenes/textures/textures.json'), 'utf8'));
  delete doc.$schema;
  doc.render.width = W * 2 / 3;
  doc.render.height = H * 2 / 3;
  doc.render.samples_per_pixel = 1;
  const file = path.join(dir, 'textures.json');
  fs.writeFileSync(file, JSON.stringify(doc, null, 2));
  const { proc, url: address } = await startServer(file);
  let p = null;
  try {
    p = await newPage(address);
    await settled(p);
    const look = () => p.evaluate(() => ({ reads: window.glintPreview.state.stats.file_reads,
      builds: window.glintPreview.state.stats.builds,
      version: window.glintPreview.state.scene_version, scene: window.glintPreview.state.scene }));
    // torus.obj (with its .mtl), bricks.png, uv-grid.png.
    assert.equal((await look()).reads, 3);
    assert.equal(await diffWithPng(glintRender(file), p), 0);
    // A material, the camera and a light: another frame, no file read.
    const first = await canvasHash(p);
    await p.selectOption('#material-select', 'uv grid');
    await setRange('input[type=range][data-path="materials.uv grid.shininess"]', 5, p);
    await setRange('input[type=range][data-path="camera.fov_y"]', 50, p);
    await setRange('input[type=range][data-path="lights[1].diffuse"][data-channel="0"]', 0.3, p);
    await settled(p, { 'scene.materials.uv grid.shininess': 5, 'scene.camera.fov_y': 50, 'scene.lights.1.diffuse': [0.3, 0.88, 0.8] });
    assert.notEqual(await canvasHash(p), first);
    let now = await look();
    assert.equal(now.reads, 3);
    assert.equal(now.builds, 1);  // the prepared geometry kept
    // What glint render draws of the edited scene (beside the files it names).
    const edited = path.join(dir, 'expected.json');
    fs.writeFileSync(edited, JSON.stringify(now.scene));
    assert.equal(await diffWithPng(glintRender(edited), p), 0);
    // The .mtl changes on disk (the page holds unsaved edits, the scene file
    // is unchanged): shown under the edits, the mesh read again, the textures not.
    const mtl = fs.readFileSync(path.join(dir, 'torus.mtl'), 'utf8');
    fs.writeFileSync(path.join(dir, 'torus.mtl'), mtl.replace('Ks 0.15 0.15 0.15', 'Ks 0.9 0.9 0.9').replace('Ns 20', 'Ns 6'));
    await until(p, (v) => window.glintPreview.state.scene_version > v, now.version);
    await settled(p, { dirty: true, conflict: false });
    now = await look();
    assert.equal(now.reads, 4);
    assert.equal(now.builds, 1);  // new materials, the same triangles
    const afterMtl = await canvasHash(p);
    assert.equal(await diffWithPng(glintRender(edited), p), 0);
    // The mesh, renamed over by an editor: read again, the frame follows.
    const obj = fs.readFileSync(path.join(dir, 'torus.obj'), 'utf8')
      .replace(/^v (\S+) (\S+) (\S+)$/gm, (m, x, y, z) => `v ${x} ${(1.6 * Number(y)).toFixed(5)} ${z}`);
    fs.writeFileSync(path.join(dir, '.torus.obj.tmp'), obj);
    fs.renameSync(path.join(dir, '.torus.obj.tmp'), path.join(dir, 'torus.obj'));
    await until(p, (v) => window.glintPreview.state.scene_version > v, now.version);
    await settled(p, { dirty: true });
    now = await look();
    assert.equal(now.reads, 5);
    assert.equal(now.builds, 2);
    assert.notEqual(await canvasHash(p), afterMtl);
    assert.equal(await diffWithPng(glintRender(edited), p), 0);
    // A texture rewritten in place: read again, alone.
    fs.copyFileSync(path.join(dir, 'uv-grid.png'), path.join(dir, 'bricks.png'));
    await until(p, (v) => window.glintPreview.state.scene_version > v, now.version);
    await settled(p, { dirty: true });
    assert.equal((await look()).reads, 6);
    assert.equal(await diffWithPng(glintRender(edited), p), 0);
  } finally {
    if (p) await p.close();
    assert.equal(await stopServer(proc), 0);
  }
});

test('a model file is a scene: framed as glint render frames it, saved as a scene that renders the same', async () => {
  const dir = path.join(work, 'model');
  fs.mkdirSync(dir);
  const model = path.join(dir, 'model.obj');
  fs.writeFileSync(path.join(dir, 'model.mtl'), 'newmtl gold\nKa 0.1 0.08 0.02\nKd 0.8 0.6 0.2\nKs 0.6 0.6 0.5\nNs 40\nillum 2\n');
  // An octahedron, and the same stretched (written over it later).
  const octahedron = (h) => 'mtllib model.mtl\nv 1 0 0\nv -1 0 0\nv 0 ' + h + ' 0\nv 0 ' + -h + ' 0\nv 0 0 1\nv 0 0 -1\nusemtl gold\n' +
    'f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n';
  fs.writeFileSync(model, octahedron(1));
  const { proc, url: address } = await startServer(model);
  let p = null;
  try {
    p = await newPage(address);
    await settled(p);
    assert.equal(await p.textContent('#file'), 'model.obj');
    assert.equal(await p.isDisabled('#save'), true);  // a model is never overwritten by a scene
    assert.equal(await diffWithPng(glintRender(model), p), 0);
    // The model changes on disk: framed again, as glint render frames it.
    const first = await canvasHash(p);
    const version = await p.evaluate(() => window.glintPreview.state.scene_version);
    fs.writeFileSync(model, octahedron(1.8));
    await until(p, (v) => window.glintPreview.state.scene_version > v, version);
    await settled(p, { dirty: false });
    assert.notEqual(await canvasHash(p), first);
    assert.equal(await diffWithPng(glintRender(model), p), 0);
    // The key light's L_d, moved on the page; then saved as a scene.
    await setRange('input[type=range][data-path="lights[1].diffuse"][data-channel="0"]', 0.4, p);
    await settled(p, { dirty: true, 'scene.lights.1.diffuse': [0.4, 0.9, 0.9] });
    await p.click('#save-new');
    await until(p, () => /saved as model-edited\.json/.test(window.glintPreview.state.notice));
    await settled(p);
    const saved = path.join(dir, 'model-edited.json');
    const scene = JSON.parse(fs.readFileSync(saved, 'utf8'));
    assert.equal(scene.objects[0].file, 'model.obj');
    assert.deepEqual(scene.lights[1].diffuse, [0.4, 0.9, 0.9]);
    assert.equal(await diffWithPng(glintRender(saved), p), 0);
    assert.deepEqual(fs.readdirSync(dir).sort(), ['model-edited.json', 'model.mtl', 'model.obj']);
  } finally {
    if (p) await p.close();
    assert.equal(await stopServer(proc), 0);
  }
});

test('camera type, click to focus, lens and fog are controls; the frame is glint render of the scene', async () => {
  const scene = () => page.evaluate(() => window.glintPreview.state.scene);
  const errorsBefore = pageErrors.length;
  // A fisheye: its own fov control replaces fov y.
  await page.selectOption('select[data-path="camera.type"]', 'fisheye');
  await until(page, () => window.glintPreview.state.scene.camera.type === 'fisheye' &&
    document.querySelector('input[type=range][data-path="camera.fov"]') !== null);
  await setRange('input[type=range][data-path="camera.fov"]', 200);
  await settled(page, { 'scene.camera.fov': 200 });
  assert.equal(await diffWithPng(glintRender(writeScene(await scene()))), 0);
  // Back to perspective: the fisheye's key goes with the change.
  await page.selectOption('select[data-path="camera.type"]', 'perspective');
  await until(page, () => window.glintPreview.state.scene.camera.type === 'perspective' &&
    window.glintPreview.state.scene.camera.fov === undefined);
  // Click to focus: the plane in focus passes through the point clicked.
  await page.check('input[data-path="view.focus_click"]');
  const [x, y] = [Math.round(140 * W / 480), Math.round(170 * H / 270)];  // on the red ball
  const box = await page.locator('#frame').boundingBox();
  await page.mouse.click(box.x + (x + 0.5) * box.width / W, box.y + (y + 0.5) * box.height / H);
  await until(page, () => window.glintPreview.state.scene.camera.focus_distance !== undefined);
  const doc = await scene();
  const tree = JSON.parse(execFileSync(GLINT, ['explain', writeScene(doc), '--pixel', String(x), String(y), '--json']));
  const forward = doc.camera.look_at.map((v, i) => v - doc.camera.position[i]);
  const len = Math.hypot(...forward);
  const want = tree.ray.hit.point.reduce((acc, v, i) => acc + (v - doc.camera.position[i]) * forward[i] / len, 0);
  assert.ok(Math.abs(doc.camera.focus_distance - want) < 1e-9, `${doc.camera.focus_distance} vs ${want}`);
  await page.uncheck('input[data-path="view.focus_click"]');
  // A lens and fog: still glint render's image, pixel for pixel.
  await setRange('input[type=range][data-path="camera.aperture"]', 0.1);
  await page.selectOption('select[data-path="render.fog.type"]', 'exp');
  await until(page, () => document.querySelector('input[type=range][data-path="render.fog.density"]') !== null);
  await setRange('input[type=range][data-path="render.fog.density"]', 0.05);
  await settled(page, { 'scene.camera.aperture': 0.1, 'scene.render.fog.density': 0.05 });
  assert.equal(await diffWithPng(glintRender(writeScene(await scene()))), 0);
  // No fog again: the key is gone.
  await page.selectOption('select[data-path="render.fog.type"]', 'none');
  await until(page, () => window.glintPreview.state.scene.render.fog === undefined);
  await settled(page);
  assert.deepEqual(pageErrors.slice(errorsBefore), []);  // every edit above was accepted
});

test('requests from elsewhere are refused', async () => {
  const port = new URL(url).port;
  const edit = JSON.stringify({ edits: [{ op: 'set', path: 'render.max_depth', value: 1 }] });
  const json = { 'Content-Type': 'application/json' };
  // A page on another origin.
  let r = await request('/api/edit', { method: 'POST', body: edit, headers: { ...json, Origin: 'http://evil.example' } });
  assert.equal(r.status, 403);
  r = await request('/api/save', { method: 'POST', body: '{"mode":"overwrite"}', headers: { ...json, Origin: 'null' } });
  assert.equal(r.status, 403);
  // DNS rebinding: our address under another name.
  r = await request('/', { headers: { Host: `evil.example:${port}` } });
  assert.equal(r.status, 403);
  // A form post cannot send JSON.
  r = await request('/api/edit', { method: 'POST', body: edit, headers: { 'Content-Type': 'text/plain' } });
  assert.equal(r.status, 415);
  // Only our own files: no path reaches the file system.
  for (const p of ['/../scene.json', '/scene.json', '/etc/passwd', '/frame/999999.png', '/app.js/../../x']) {
    r = await request(p);
    assert.ok(r.status === 404 || r.status === 400, `${p}: ${r.status}`);
  }
  // Bodies are capped.
  // (the server may close the connection before the body is sent: refused too)
  r = await request('/api/edit', { method: 'POST', body: 'x'.repeat(2 << 20), headers: json })
    .catch((e) => ({ status: 'closed: ' + e.code }));
  assert.ok(r.status === 413 || r.status === 400 || /^closed/.test(r.status), String(r.status));
  // A cross-origin fetch from a page elsewhere fails in the browser too.
  const other = await context.newPage();
  await other.goto('about:blank');
  const outcome = await other.evaluate((u) => fetch(u + '/api/edit', { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: '{"edits":[{"op":"set","path":"render.max_depth","value":1}]}' }).then((x) => 'status ' + x.status, (e) => 'failed'), url);
  assert.notEqual(outcome, 'status 200');
  await other.close();
  const state = JSON.parse((await request('/api/state')).text);
  assert.notEqual(state.scene.render.max_depth, 1);
});

test('--host other than this machine: a warning, and its address', async () => {
  const proc = spawn(GLINT, ['serve', scenePath, '--port', '0', '--host', '0.0.0.0', '--threads', '1'], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  proc.stderr.on('data', (d) => { stderr += d; });
  const address = await new Promise((resolve, reject) => {
    proc.on('exit', (code) => reject(new Error(`glint serve exited (${code}): ${stderr}`)));
    readline.createInterface({ input: proc.stdout }).on('line', (line) => {
      const m = /^glint serve: (http:\/\/\S+)\/$/.exec(line);
      if (m) resolve(m[1]);
    });
  });
  try {
    assert.match(address, /^http:\/\/0\.0\.0\.0:\d+$/);
    assert.match(stderr, /^warning: listening on 0\.0\.0\.0: anyone who can reach this address can see and edit the scene/);
    // Reached by an address of this machine (an IP literal is never a rebinding name).
    const port = new URL(address).port;
    const r = await request('/api/state', { headers: { Host: `127.0.0.1:${port}` } }, `http://127.0.0.1:${port}`);
    assert.equal(r.status, 200);
    const refused = await request('/api/state', { headers: { Host: `rebind.example:${port}` } }, `http://127.0.0.1:${port}`);
    assert.equal(refused.status, 403);
  } finally {
    assert.equal(await stopServer(proc), 0);
  }
});

test('soak: random edits from two tabs keep memory flat and frames correct', async (t) => {
  const second = await context.newPage();
  await second.goto(url + '/');
  await settled(second);
  const tabs = [page, second];
  const edit = (p, i) => p.evaluate((k) => {
    const paths = ['materials.red.shininess', 'materials.floor.reflectivity', 'lights[1].position', 'camera.fov_y', 'materials.blue.diffuse'];
    const r = (k * 7919) % 1000 / 1000;
    const values = [1 + 200 * r, r * 0.5, [-4 + 2 * r, 6, 5], 30 + 20 * r, [r, 0.3, 0.8]];
    const j = k % paths.length;
    return fetch('/api/edit', { method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ edits: [{ op: 'set', path: paths[j], value: values[j] }] }) }).then((x) => x.status);
  }, i);
  const round = async (from, to) => {
    for (let i = from; i < to; i += 2) {
      const s = await Promise.all([edit(tabs[0], i), edit(tabs[1], i + 1)]);
      assert.deepEqual(s, [200, 200]);
    }
  };
  await round(0, 100);
  await settled(page);
  const start = rss();
  await round(100, 400);
  await settled(page);
  await settled(second);
  const growth = rss() - start;
  if (SANITIZED) t.diagnostic(`sanitized build: resident memory grew by ${growth} bytes (not checked; LeakSanitizer checks at exit)`);
  else assert.ok(growth < 16 * 1024 * 1024, `resident memory grew by ${growth} bytes`);
  // Both tabs show the one scene state, as glint render draws it.
  const doc = JSON.parse((await request('/api/state')).text).scene;
  const expected = glintRender(writeScene(doc));
  assert.equal(await diffWithPng(expected, page), 0);
  assert.equal(await diffWithPng(expected, second), 0);
  await second.close();
});

test('SIGTERM stops the server cleanly (exit 0; under ASan, LeakSanitizer found no leak)', async () => {
  const code = await stopServer(server);
  assert.equal(code, 0, `glint serve exited with ${code}: ${serverOutput.join('').slice(-2000)}`);
});
