// Benchmark of glint serve through Chromium (not part of the test suite):
//  - input event -> painted coarse frame, median of 20 slider moves of the
//    showcase (800 x 450), each from an idle page;
//  - the full frame's render phase against `glint render`'s (same scene).
// usage: tests/browser/run.sh sets up playwright-core; then
//   NODE_PATH=build/tests/browser/node_modules node bench/serve-latency.cjs build/glint scenes/showcase.json
'use strict';
const { spawn, spawnSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const readline = require('node:readline');
const { chromium } = require('playwright-core');

const [glint, scene] = process.argv.slice(2);
const median = (a) => { const s = [...a].sort((x, y) => x - y); return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2; };

(async () => {
  const server = spawn(glint, ['serve', scene, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  const url = await new Promise((resolve, reject) => {
    server.on('exit', () => reject(new Error('glint serve exited')));
    readline.createInterface({ input: server.stdout }).on('line', (l) => { const m = /^glint serve: (\S+)\/$/.exec(l); if (m) resolve(m[1]); });
  });
  const userData = fs.mkdtempSync(path.join(os.tmpdir(), 'glint-bench-'));
  let context;
  try {
    context = await chromium.launchPersistentContext(userData, {
      executablePath: '/usr/bin/chromium', headless: true, viewport: { width: 1400, height: 900 },
      args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
        '--disable-sync', '--no-first-run', '--force-color-profile=srgb'],
    });
    const page = context.pages()[0] || (await context.newPage());
    await page.goto(url + '/');
    // Idle: the full frame of the newest scene on screen (checked at each
    // change the page announces; the page's CSP forbids waitForFunction's eval).
    const idle = () => page.evaluate(() => new Promise((resolve) => {
      const check = () => {
        const g = window.glintPreview, s = g.state, f = g.frame;
        if (s && f && g.editsInFlight === 0 && !f.coarse && f.scene_version === s.scene_version && !s.rendering) {
          window.removeEventListener('glintpreview', check);
          resolve();
        }
      };
      window.addEventListener('glintpreview', check);
      check();
    }));
    await idle();
    const material = await page.evaluate(() => Object.keys(window.glintPreview.state.scene.materials)[0]);
    const latencies = [], fulls = [];
    for (let i = 0; i < 20; ++i) {
      const ms = await page.evaluate(async ({ material, value }) => {
        const g = window.glintPreview;
        const slider = document.querySelector(`input[type=range][data-path="materials.${material}.shininess"]`);
        const before = g.state.scene_version;
        const t0 = performance.now();
        slider.value = value;
        slider.dispatchEvent(new Event('input', { bubbles: true }));
        // The first frame of the new scene on the canvas, then the next paint.
        await new Promise((resolve) => {
          const check = () => { if (g.frame && g.frame.scene_version > before) { window.removeEventListener('glintpreview', check); resolve(); } };
          window.addEventListener('glintpreview', check);
        });
        await new Promise((resolve) => requestAnimationFrame(() => resolve()));
        return { ms: performance.now() - t0, coarse: g.frame.coarse };
      }, { material, value: 10 + 20 * i });
      latencies.push(ms.ms);
      await idle();
      fulls.push(await page.evaluate(() => window.glintPreview.frame.render_ms));
    }
    const state = await page.evaluate(() => window.glintPreview.state);
    const file = path.join(userData, 'bench-scene.json');
    fs.writeFileSync(file, JSON.stringify(state.scene));
    // glint render's own render phase: its statistics line "... render X s (total ...".
    const renders = [];
    for (let i = 0; i < 5; ++i) {
      const r = spawnSync(glint, ['render', file, '-o', path.join(userData, 'o.png')], { encoding: 'utf8' });
      const m = /: render ([\d.]+) s/.exec(r.stderr);
      if (m) renders.push(1000 * Number(m[1]));
    }
    console.log(`scene ${scene}: ${state.width} x ${state.height}`);
    console.log(`input -> painted first frame: median ${median(latencies).toFixed(1)} ms (min ${Math.min(...latencies).toFixed(1)}, max ${Math.max(...latencies).toFixed(1)})`);
    console.log(`full frame render phase (server): median ${median(fulls.slice(1)).toFixed(1)} ms`);
    console.log(`glint render's render phase: median ${median(renders).toFixed(1)} ms (ratio ${(median(fulls.slice(1)) / median(renders)).toFixed(3)})`);
  } finally {
    if (context) await context.close();
    server.kill('SIGTERM');
    fs.rmSync(userData, { recursive: true, force: true });
  }
})().catch((e) => { console.error(e); process.exitCode = 1; });
