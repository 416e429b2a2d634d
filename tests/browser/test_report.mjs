// Headless-browser test of OUT/report.html (issue 8): the report of the bundled ground-truth twin,
// opened from disk (file://) and served by `photoscene view`, in the system chromium driven by
// playwright-core. Checks: no console errors, the glTF loaded (window.__twinLoaded), the WebGL
// canvas is not blank, "Go to input view 0" moves the camera and changes the picture. Saves
// screenshots to --out. Exit 77 (ctest SKIP_RETURN_CODE) when chromium or node_modules are absent.
//
//   node tests/browser/test_report.mjs --photoscene build/bin/photoscene \
//        --sample samples/data/living-room --node-modules third_party/web/node_modules --out build/browser_test
//        [--spp N]   samples per pixel of the render the report shows (default 16)
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const SKIP = 77;
const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const t0 = Date.now();
const log = (...m) => console.log(`[${((Date.now() - t0) / 1000).toFixed(1)}s]`, ...m);
const fail = (msg) => { console.error('FAIL:', msg); process.exitCode = 1; };

const chromiumPath = [process.env.PS_CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser',
                      '/usr/bin/google-chrome'].find((p) => p && fs.existsSync(p));
if (!chromiumPath) { console.log('SKIP: no chromium (scripts/setup.sh installs it)'); process.exit(SKIP); }
const pwEntry = path.join(args['node-modules'] || '', 'playwright-core', 'index.mjs');
if (!fs.existsSync(pwEntry)) { console.log(`SKIP: ${pwEntry} missing (scripts/setup.sh runs npm ci)`); process.exit(SKIP); }
for (const k of ['photoscene', 'sample', 'out']) {
  if (!args[k]) { console.error(`missing --${k}`); process.exit(2); }
}
const { chromium } = await import(pathToFileURL(pwEntry).href);

// ---- a twin output folder as `photoscene run` leaves it: photos, geometry inside OUT
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'ps_browser_'));
const out = path.join(tmp, 'twin');
fs.cpSync(path.join(args.sample, 'gt', 'twin'), out, { recursive: true });
const scene = JSON.parse(fs.readFileSync(path.join(out, 'scene.json'), 'utf8'));
const sceneDir = path.join(args.sample, 'gt', 'twin');
fs.copyFileSync(path.resolve(sceneDir, scene.geometry), path.join(out, 'room.obj'));
scene.geometry = 'room.obj';
fs.mkdirSync(path.join(out, 'photos'));
fs.mkdirSync(path.join(out, 'segments'));
scene.views.forEach((v, i) => {
  fs.copyFileSync(path.resolve(sceneDir, v.image), path.join(out, 'photos', `view${i}.png`));
  v.image = `photos/view${i}.png`;
  if (v.segments) {
    fs.copyFileSync(path.resolve(sceneDir, v.segments), path.join(out, 'segments', `view${i}.png`));
    v.segments = `segments/view${i}.png`;
  }
});
fs.writeFileSync(path.join(out, 'scene.json'), JSON.stringify(scene, null, 1));
fs.mkdirSync(args.out, { recursive: true });

const run = (cmdArgs, timeout = 60000) => {
  const r = spawnSync(args.photoscene, cmdArgs, { encoding: 'utf8', timeout });
  return { code: r.status, text: (r.stdout || '') + (r.stderr || '') };
};
// renders/view<i>.png: a quick path-traced render when this build has the renderer
fs.mkdirSync(path.join(out, 'renders'));
let r = run(['-q', 'render', out, '--spp', args.spp || '16', '-o', path.join(out, 'renders', 'view0.png')]);
if (r.code !== 0 || !fs.existsSync(path.join(out, 'renders', 'view0.png'))) {
  log('render not available here; the report shows the photo as the render', r.text.trim().split('\n').pop());
  fs.copyFileSync(path.join(out, 'photos', 'view0.png'), path.join(out, 'renders', 'view0.png'));
}
r = run(['-q', 'report', out]);
if (r.code !== 0) { fail(`photoscene report exited ${r.code}:\n${r.text}`); process.exit(1); }
for (const f of ['report.html', 'twin.gltf', 'twin.bin', 'viewer/photoscene-viewer.js', 'viewer/twin_data.js',
                 'renders/view0_diff.png']) {
  if (!fs.existsSync(path.join(out, f))) fail(`${f} was not written`);
}
log('report written:', path.join(out, 'report.html'));

// ---- the browser
const browser = await chromium.launch({
  executablePath: chromiumPath,
  headless: true,
  args: ['--no-sandbox', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--ignore-gpu-blocklist'],
});

/** Mean and variance of the viewer canvas' luminance (0-255), and a coarse 16x12 thumbnail. */
const canvasStats = (page) => page.evaluate(() => {
  const src = document.querySelector('#viewer canvas');
  if (!src) return null;
  const w = 160, h = 120;
  const c = document.createElement('canvas');
  c.width = w; c.height = h;
  const ctx = c.getContext('2d');
  ctx.drawImage(src, 0, 0, w, h);
  const d = ctx.getImageData(0, 0, w, h).data;
  let s = 0, s2 = 0;
  const lum = [];
  for (let i = 0; i < d.length; i += 4) {
    const y = 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];
    s += y; s2 += y * y; lum.push(y);
  }
  const n = lum.length, mean = s / n;
  return { mean, variance: s2 / n - mean * mean, lum };
});
const nextFrames = (page) => page.evaluate(() => new Promise((res) => requestAnimationFrame(() => requestAnimationFrame(res))));

async function check(url, label, screenshots) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (q) => errors.push(`request failed: ${q.url()} ${q.failure() && q.failure().errorText}`));
  await page.goto(url);
  try {
    await page.waitForFunction(() => window.__twinLoaded === true || window.__twinLoadError, null, { timeout: 45000 });
  } catch (e) {
    fail(`${label}: the twin did not load in 45 s`);
  }
  const loadError = await page.evaluate(() => window.__twinLoadError || null);
  if (loadError) fail(`${label}: glTF load error: ${loadError}`);
  await nextFrames(page);
  const before = await canvasStats(page);
  if (!before) fail(`${label}: no viewer canvas`);
  else if (!(before.variance > 50)) fail(`${label}: the canvas looks blank (luminance variance ${before.variance.toFixed(1)})`);
  else log(`${label}: overview canvas mean ${before.mean.toFixed(1)}, variance ${before.variance.toFixed(1)}`);
  if (screenshots) {
    await page.screenshot({ path: path.join(args.out, 'report_full.png'), fullPage: true });
    await page.screenshot({ path: path.join(args.out, 'report.png'), fullPage: true,
                            clip: { x: 0, y: 0, width: 1280, height: 1560 } });
    await page.locator('#viewer').screenshot({ path: path.join(args.out, 'viewer_overview.png') });
  }
  const camBefore = await page.evaluate(() => window.__psViewer.camera.position.toArray());
  await page.getByRole('button', { name: 'Go to input view 0' }).click();
  await nextFrames(page);
  const after = await canvasStats(page);
  const camAfter = await page.evaluate(() => window.__psViewer.camera.position.toArray());
  const moved = Math.hypot(...camAfter.map((v, i) => v - camBefore[i]));
  if (!(moved > 0.1)) fail(`${label}: the camera did not move (${moved})`);
  if (before && after) {
    let diff = 0;
    for (let i = 0; i < after.lum.length; i += 1) diff += Math.abs(after.lum[i] - before.lum[i]);
    diff /= after.lum.length;
    if (!(diff > 5)) fail(`${label}: the picture did not change after "Go to input view 0" (${diff.toFixed(2)})`);
    if (!(after.variance > 50)) fail(`${label}: the view-0 canvas looks blank`);
    log(`${label}: view 0: camera moved ${moved.toFixed(2)} m, mean |change| ${diff.toFixed(1)}/255`);
  }
  if (screenshots) await page.locator('#viewer').screenshot({ path: path.join(args.out, 'viewer_view0.png') });
  // the wipe slider moves the clip
  const clip = await page.evaluate(() => {
    const w = document.querySelector('.wipe input');
    if (!w) return null;
    w.value = 20; w.dispatchEvent(new Event('input'));
    return document.querySelector('.wipe .over').style.clipPath;
  });
  if (clip !== 'inset(0px 0px 0px 20%)' && clip !== 'inset(0 0 0 20%)') fail(`${label}: the wipe slider did not move (${clip})`);
  if (errors.length) fail(`${label}: console errors:\n  ${errors.join('\n  ')}`);
  await page.close();
}

try {
  await check(pathToFileURL(path.join(out, 'report.html')).href, 'file://', true);
  // served over HTTP by `photoscene view`
  const server = spawn(args.photoscene, ['view', out, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  const url = await new Promise((resolve, reject) => {
    let buf = '';
    const timer = setTimeout(() => reject(new Error('photoscene view printed no URL in 15 s')), 15000);
    server.stdout.on('data', (d) => {
      buf += d;
      const m = buf.match(/http:\/\/127\.0\.0\.1:\d+\/report\.html/);
      if (m) { clearTimeout(timer); resolve(m[0]); }
    });
    server.on('exit', (code) => reject(new Error(`photoscene view exited ${code}`)));
  });
  log('served at', url);
  try {
    await check(url, 'http', false);
  } finally {
    server.kill('SIGINT');
  }
} catch (e) {
  fail(e.stack || String(e));
} finally {
  await browser.close();
  if (!process.exitCode) fs.rmSync(tmp, { recursive: true, force: true });
}
log(process.exitCode ? 'FAILED' : 'OK', `screenshots in ${args.out}`);
