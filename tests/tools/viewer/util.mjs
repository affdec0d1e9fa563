// Helpers of the viewer tests: chainsim runs, headless Chromium through
// playwright-core (Debian's /usr/bin/chromium, nothing downloaded), and pixel
// statistics of PNG files (decoded by the browser itself).
import { spawn, spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { createRequire } from 'node:module';
import { mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { join } from 'node:path';

export const CHAINSIM = process.env.CHAINSIM_EXE;
export const CHROMIUM = process.env.CHAINSIM_CHROMIUM || '/usr/bin/chromium';
const require = createRequire(join(process.env.VIEWER_NODE_MODULES, 'noop.js'));
const { chromium } = require('playwright-core');

export const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

const made = [];
export function tempDir(name) {
  const base = process.env.VIEWER_TEST_TMP || '/tmp';
  mkdirSync(base, { recursive: true });
  made.push(mkdtempSync(join(base, `${name}-`)));
  return made[made.length - 1];
}

// removes the temporary directories (kept when VIEWER_TEST_KEEP is set)
export function cleanup() {
  if (!process.env.VIEWER_TEST_KEEP) for (const d of made.splice(0)) rmSync(d, { recursive: true, force: true });
}

// chainsim with args; resolves {code, stdout, stderr}
export function chainsim(args, opts = {}) {
  const r = spawnSync(CHAINSIM, args, { encoding: 'utf8', timeout: 180000, ...opts });
  if (r.error) throw r.error;
  return { code: r.status, stdout: r.stdout, stderr: r.stderr };
}

// a run of the default scene into dir (duration s)
export function makeRun(dir, duration = 2) {
  const r = chainsim(['run', '--duration', String(duration), '--out', dir, '--quiet']);
  if (r.code !== 0) throw new Error(`chainsim run failed (${r.code}): ${r.stderr}`);
  return dir;
}

// chainsim started in the background; stderr collected
export function startChainsim(args) {
  const p = spawn(CHAINSIM, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  p.stderrText = '';
  p.stderr.on('data', (d) => (p.stderrText += d));
  p.exited = new Promise((res) => p.on('exit', (code) => res(code)));
  return p;
}

export async function waitFor(pred, timeoutMs, what) {
  const t0 = Date.now();
  for (;;) {
    const v = await pred();
    if (v) return v;
    if (Date.now() - t0 > timeoutMs) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

// the value of promise, or `fallback` after ms (the timer does not keep node alive)
export function within(promise, ms, fallback = 'timed out') {
  let timer;
  const t = new Promise((r) => { timer = setTimeout(() => r(fallback), ms); });
  return Promise.race([promise, t]).finally(() => clearTimeout(timer));
}

export function sha256File(path) {
  return createHash('sha256').update(readFileSync(path)).digest('hex');
}

// Chromium with CHROMIUM_ARGS and extra ones
export async function launch(extraArgs = []) {
  return chromium.launch({ executablePath: CHROMIUM, args: [...CHROMIUM_ARGS, ...extraArgs] });
}

// a page that records console errors and page errors
export async function newPage(browser, viewport = { width: 1280, height: 800 }) {
  const page = await browser.newPage({ viewport });
  page.problems = [];
  page.on('console', (m) => {
    if (m.type() === 'error') page.problems.push(`console error: ${m.text()}`);
  });
  page.on('pageerror', (e) => page.problems.push(`page error: ${e.message}`));
  return page;
}

// is (r, g, b) the rotation modules' colour #e4572e, lit or in shade?
// (hue within 18 degrees of its 11, well saturated)
export const IS_ROTATION = `(r, g, b) => {
  const max = Math.max(r, g, b), min = Math.min(r, g, b);
  if (max < 40 || max !== r) return false;
  const s = (max - min) / max;
  const h = 60 * ((g - b) / (max - min));
  return s > 0.45 && h > -7 && h < 29;
}`;

// pixel predicates (r, g, b) => bool of the environments' colours (tools/viewer/src/env_*.js)
// by hue, lit or in shade: the pipe (and mesh) walls #3fa3b6, the terrain #c8a86b
// under its grid texture
const hueSat = `(r, g, b) => {
  const max = Math.max(r, g, b), min = Math.min(r, g, b);
  if (max < 30 || max === min) return [0, 0];
  let h = max === r ? 60 * ((g - b) / (max - min)) : max === g ? 60 * (2 + (b - r) / (max - min)) : 60 * (4 + (r - g) / (max - min));
  if (h < 0) h += 360;
  return [h, (max - min) / max];
}`;
export const IS_PIPE = `(r, g, b) => { const [h, s] = (${hueSat})(r, g, b); return s > 0.35 && h > 176 && h < 204; }`;
export const IS_TERRAIN = `(r, g, b) => { const [h, s] = (${hueSat})(r, g, b); return s > 0.3 && h > 31 && h < 48; }`;

// how many pixels of a PNG match each predicate: {name: count, width, height}
export function pngColours(browser, png, predicates) {
  return pngStats(browser, png, null, predicates);
}

// pixel statistics of a PNG: {width, height} and, per predicate, the pixels
// that match it (default: {rotation: pixels of the rotation colour}); with
// other, {changed: pixels that differ by more than 24 in a channel}
export async function pngStats(browser, png, other, predicates = { rotation: IS_ROTATION }) {
  const page = await browser.newPage();
  const b64 = (f) => (f ? readFileSync(f).toString('base64') : null);
  const stats = await page.evaluate(async ({ a, b, preds }) => {
    const load = async (data) => {
      const img = new Image();
      img.src = `data:image/png;base64,${data}`;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      return g.getImageData(0, 0, c.width, c.height);
    };
    const A = await load(a);
    const out = { width: A.width, height: A.height };
    for (const [name, src] of Object.entries(preds)) {
      const is = eval(src);
      let n = 0;
      for (let i = 0; i < A.data.length; i += 4) if (is(A.data[i], A.data[i + 1], A.data[i + 2])) n++;
      out[name] = n;
    }
    if (b) {
      const B = await load(b);
      let changed = 0;
      for (let i = 0; i < A.data.length; i += 4)
        for (let k = 0; k < 3; k++)
          if (Math.abs(A.data[i + k] - B.data[i + k]) > 24) { changed++; break; }
      out.changed = changed;
    }
    return out;
  }, { a: b64(png), b: b64(other), preds: predicates });
  await page.close();
  return stats;
}
