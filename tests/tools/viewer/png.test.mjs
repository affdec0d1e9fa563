// `chainsim view RUN --png T`: the picture shows the modules (pixels of the
// rotation colour #e4572e; none in a picture of a scene without modules), it
// changes with the time, several renders at once on a busy machine all give
// the same picture (the page says when it is drawn; no guessed delay), and a
// missing or broken Chromium, or a page that throws, is named in the error.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { chmodSync, existsSync } from 'node:fs';
import { chainsim, launch, makeRun, pngStats, startChainsim, tempDir, cleanup } from './util.mjs';

let browser, run, dir;

before(async () => {
  dir = tempDir('png');
  run = makeRun(join(dir, 'run'), 2);
  browser = await launch();
});
after(async () => {
  await browser?.close();
  cleanup();
});

function png(runDir, t, name, extra = []) {
  const out = join(dir, name);
  const r = chainsim(['view', runDir, '--png', String(t), '--out', out, '--size', '640x400', ...extra]);
  assert.equal(r.code, 0, r.stderr);
  return out;
}

test('the picture shows the modules in their colour', async () => {
  const s = await pngStats(browser, png(run, 1.0, 'a.png'));
  assert.equal(s.width, 640);
  assert.equal(s.height, 400);
  assert.ok(s.rotation > 2000, `only ${s.rotation} pixels of the rotation colour`);
});

test('a scene without modules has none of their colour', async () => {
  const empty = join(dir, 'empty');
  mkdirSync(empty, { recursive: true });
  const scene = JSON.parse(readFileSync(join(run, 'scene.json'), 'utf8'));
  scene.modules = [];
  writeFileSync(join(empty, 'scene.json'), JSON.stringify(scene));
  writeFileSync(join(empty, 'trace.csv'), 't_s\n0\n0.01\n0.02\n');
  writeFileSync(join(empty, 'bus.log'), '');
  const s = await pngStats(browser, png(empty, 0.01, 'empty.png'));
  assert.equal(s.rotation, 0);
});

test('the picture changes with the time', async () => {
  const a = png(run, 0.4, 't04.png');
  const b = png(run, 1.8, 't18.png');
  const s = await pngStats(browser, a, b);
  assert.ok(s.changed > 0.01 * s.width * s.height, `only ${s.changed} pixels changed`);
  const still = png(run, 0.4, 't04-again.png');
  const same = await pngStats(browser, a, still);
  assert.ok(same.changed < 0.002 * s.width * s.height, `the same time rendered differently: ${same.changed} pixels`);
});

test('a missing Chromium is named in the error', () => {
  const r = chainsim(['view', run, '--png', '1', '--out', join(dir, 'x.png')],
    { env: { ...process.env, CHAINSIM_CHROMIUM: '/nonexistent/chromium' } });
  assert.notEqual(r.code, 0);
  assert.match(r.stderr, /Debian package 'chromium'/);
});

test('four renders at once on two cores all give the same picture', async () => {
  const ref = png(run, 1.0, 'busy-ref.png');
  const outs = [0, 1, 2, 3].map((k) => join(dir, `busy-${k}.png`));
  const procs = outs.map((o) => startChainsim(['view', run, '--png', '1.0', '--out', o, '--size', '640x400']));
  const codes = await Promise.all(procs.map((p) => p.exited));
  codes.forEach((c, k) => assert.equal(c, 0, procs[k].stderrText));
  for (const o of outs) {
    const s = await pngStats(browser, o, ref);
    assert.ok(s.rotation > 2000, `${o}: only ${s.rotation} pixels of the rotation colour`);
    assert.ok(s.changed < 0.002 * s.width * s.height, `${o}: ${s.changed} pixels differ from the picture made alone`);
  }
});

test('a program that is not Chromium: an error naming it, no picture', () => {
  const out = join(dir, 'not-chromium.png');
  const r = chainsim(['view', run, '--png', '1', '--out', out], { env: { ...process.env, CHAINSIM_CHROMIUM: '/bin/true' } });
  assert.equal(r.code, 3, r.stderr);
  assert.match(r.stderr, /Chromium did not render .*\/bin\/true closed its DevTools pipe \(exit status 0\)/);
  assert.ok(!existsSync(out));
});

test('a page that cannot draw: the exception it threw, at once, no picture', () => {
  // Chromium without WebGL: the viewer's renderer throws while the page loads
  const wrapper = join(dir, 'chromium-no-webgl.sh');
  writeFileSync(wrapper, `#!/bin/sh\nexec ${process.env.CHAINSIM_CHROMIUM || '/usr/bin/chromium'} --disable-3d-apis "$@"\n`);
  chmodSync(wrapper, 0o755);
  const out = join(dir, 'no-webgl.png');
  const r = chainsim(['view', run, '--png', '1', '--out', out], { env: { ...process.env, CHAINSIM_CHROMIUM: wrapper } });
  assert.equal(r.code, 3, r.stderr);
  assert.match(r.stderr, /waiting for the page to be drawn.*the page threw .*WebGL/s);
  assert.ok(!existsSync(out));  // and not "no answer in time": it stopped on the exception
});
