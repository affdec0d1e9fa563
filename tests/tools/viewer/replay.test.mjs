// replay.html of a short run: opens from disk with no console or page errors,
// has the whole trace, plays, scrubs (the picture changes), jumps to a bus
// event when it is clicked, shows a fault and a touch when they happen (a
// fault after the trace's last row at the trace's end), and lists the
// modules' own log lines on the timeline.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { appendFileSync, cpSync, existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { chainsim, launch, makeRun, newPage, tempDir, waitFor, cleanup } from './util.mjs';

let browser, run;

before(async () => {
  run = makeRun(join(tempDir('replay'), 'run'), 2);
  browser = await launch();
});
after(async () => {
  await browser?.close();
  cleanup();
});

async function open(dir, hash = '') {
  const r = chainsim(['view', dir]);
  assert.equal(r.code, 0, r.stderr);
  const html = join(dir, 'replay.html');
  assert.ok(existsSync(html));
  const page = await newPage(browser);
  await page.goto(`file://${html}${hash}`);
  await waitFor(() => page.evaluate(() => window.chainsimViewer?.state.ready), 30000, 'the replay to be ready');
  return page;
}

const canvasShot = (page) => page.locator('.cs-view3d canvas').screenshot();

test('replay.html is one self-contained file that loads without errors', async () => {
  const page = await open(run);
  const html = readFileSync(join(run, 'replay.html'), 'utf8');
  assert.doesNotMatch(html, /<script[^>]+src=|<link[^>]+stylesheet/, 'no external scripts or styles');
  const rows = readFileSync(join(run, 'trace.csv'), 'utf8').trim().split('\n').length - 1;
  const st = await page.evaluate(() => ({ ...window.chainsimViewer.state, dur: window.chainsimViewer.data.duration }));
  assert.equal(st.rowsReceived, rows);
  assert.ok(Math.abs(st.dur - 2) < 0.02, `duration ${st.dur}`);
  // servo, currents, the module's sensor channels, the chain's orientation, its centre of mass, energy
  assert.equal(await page.locator('.plot').count(), 6, 'six plots');
  // the default snake starts upright along +x
  const o = await page.evaluate(() => Array.from(window.chainsimViewer.data.orientationSeries().roll.slice(0, 1)));
  assert.ok(Math.abs(o[0]) < 5, `an upright chain's roll ${o[0]}`);
  assert.ok((await page.locator('.cs-buslist .ev').count()) > 0, 'bus log lines listed');
  // choose another module and joint for the plots
  await page.selectOption('.sel-module', '3');
  await page.selectOption('.sel-joint', '1');
  assert.match(await page.locator('.plot .u-title').first().textContent(), /module 3: yaw_servo/);
  // play for a while
  await page.click('.cs-play');
  await page.waitForTimeout(600);
  await page.keyboard.press(' ');
  const t = await page.evaluate(() => window.chainsimViewer.view.time);
  assert.ok(t > 0.2, `played to ${t}`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test("the modules' log lines are on the timeline, each with its endpoint", async () => {
  const page = await open(run, '#t=0.01');
  // the central control (endpoint 8 of the 8-module default scene) logs the chain it found
  const logs = await page.evaluate(() =>
    window.chainsimViewer.data.events.filter((e) => e.kind === 'log').map((e) => [e.module, e.t, e.text]));
  const central = readFileSync(join(run, 'modules', '08-central.log'), 'utf8').trim().split('\n');
  assert.equal(logs.filter((l) => l[0] === 8).length, central.length, 'every line of the central control\'s log');
  const chain = logs.find((l) => /^chain: RRRRRRRR \(8 modules\)$/.test(l[2]));
  assert.ok(chain, `no 'chain:' line among ${JSON.stringify(logs.slice(0, 5))}`);
  assert.equal(chain[0], 8);
  assert.equal(chain[1], Number(central[0].split(' ')[0]));  // at the time the log file says
  // listed with the bus lines, in its own lane; clicking it jumps to its time
  const row = page.locator('.cs-buslist .ev-log', { hasText: 'chain: RRRRRRRR' });
  assert.equal(await row.count(), 1);
  assert.match(await row.textContent(), /^\d+\.\d{6} \[8\] chain: RRRRRRRR \(8 modules\)$/);
  await row.click();
  assert.equal(await page.evaluate(() => window.chainsimViewer.view.time), chain[1]);
  const lanes = await page.evaluate(() => window.chainsimViewer.timeline.u.series.map((x) => x.label));
  assert.ok(lanes.includes('log'), `lanes ${lanes}`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test("a stopped run's fault, after the trace's last row, shows at the trace's end", async () => {
  const dir = join(tempDir('fault-end'), 'run');
  cpSync(run, dir, { recursive: true });
  // as a run stopped by a fault writes it: the fault a little after the last row
  appendFileSync(join(dir, 'bus.log'), '2000500 fault module 5 (rotation, pid 4242) ended: signal 11 (Segmentation fault) at t=2.000500 s\n');
  const page = await open(dir, '#t=1.9');
  const states = () => page.evaluate(() => window.chainsimViewer.scene3d.modules.map((m) => m.state));
  const banner = page.locator('.cs-banner');
  assert.equal(await banner.isVisible(), false, 'no fault before the end');
  assert.notEqual((await states())[5], 'fault');
  await page.keyboard.press('End');
  const end = await page.evaluate(() => [window.chainsimViewer.view.time, window.chainsimViewer.data.duration]);
  assert.equal(end[0], end[1]);
  assert.ok(end[1] < 2.0005, `the trace ends at ${end[1]}, before the fault`);
  assert.equal(await banner.isVisible(), true, 'the fault banner at the end');
  assert.match(await banner.textContent(), /FAULT at t=2\.001 s: module 5/);
  assert.equal((await states())[5], 'fault');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('scrubbing to another time changes the picture', async () => {
  const page = await open(run, '#t=0.3');
  const a = await canvasShot(page);
  await page.locator('.cs-scrub').fill('1.7');
  assert.ok(Math.abs((await page.evaluate(() => window.chainsimViewer.view.time)) - 1.7) < 1e-6);
  await page.waitForTimeout(100);
  const b = await canvasShot(page);
  assert.notDeepEqual(a, b, 'the 3-D view is the same at t=0.3 and t=1.7');
  // step keys move by 10 ms
  await page.keyboard.press('ArrowRight');
  assert.ok(Math.abs((await page.evaluate(() => window.chainsimViewer.view.time)) - 1.71) < 1e-6);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('clicking a bus event jumps to its time; faults and touches are highlighted', async () => {
  const dir = join(tempDir('fault'), 'run');
  cpSync(run, dir, { recursive: true });
  appendFileSync(join(dir, 'bus.log'),
    '800000 touch endpoint=2 level=1\n1100000 touch endpoint=2 level=0\n' +
    '1500000 fault module 3 (rotation, pid 4242) ended: killed by signal 9 at t=1.500 s\n');
  const page = await open(dir, '#t=0.5');
  const banner = page.locator('.cs-banner');
  assert.equal(await banner.isVisible(), false, 'no fault banner before the fault');
  // the fault's line in the bus list
  await page.locator('.cs-buslist .ev-fault').click();
  assert.equal(await page.evaluate(() => window.chainsimViewer.view.time), 1.5);
  assert.equal(await banner.isVisible(), true);
  assert.match(await banner.textContent(), /FAULT at t=1\.500 s: module 3/);
  const states = () => page.evaluate(() => window.chainsimViewer.scene3d.modules.map((m) => m.state));
  assert.equal((await states())[3], 'fault');
  // a point of the timeline: the touch, in its lane
  await page.locator('.cs-buslist .ev-touch').first().click();
  assert.equal(await page.evaluate(() => window.chainsimViewer.view.time), 0.8);
  assert.equal((await states())[2], 'touch');
  assert.equal(await page.locator('.cs-touch').isVisible(), true);
  assert.equal(await banner.isVisible(), false);
  // clicking in the timeline plot near the fault marker jumps to the fault
  const box = await page.locator('.cs-timeline .u-over').boundingBox();
  const [x, y] = await page.evaluate(() => {
    const u = window.chainsimViewer.timeline.u;
    return [u.valToPos(1.5, 'x'), u.valToPos(4, 'y')];  // lane 4: faults
  });
  await page.mouse.click(box.x + x + 3, box.y + y);
  assert.equal(await page.evaluate(() => window.chainsimViewer.view.time), 1.5);
  assert.deepEqual(page.problems, []);
  await page.close();
});

// every module type a colour and a line of the legend (types of one's own
// too); the chain's heading, pitch and roll plotted, a chain placed on its
// side reads 90 degrees of roll and is drawn with the stripe of its modules'
// tops on the side; every sensor channel of trace.csv in the module's plot
test('module types have a legend, the roll is plotted and drawn, every sensor channel is plotted', async () => {
  const dir = tempDir('replay-roll');
  const scene = join(dir, 'side.yaml');
  const rot = readFileSync(new URL('../../../scenes/modules/rotation.yaml', import.meta.url), 'utf8');
  appendFileSync(join(dir, 'mine.yaml'), rot.replace(/\ntype: rotation/, '\ntype: mine'));
  appendFileSync(scene, [
    'name: on-its-side',
    'duration_s: 0.3',
    'chain:',
    '  - {type: rotation}',
    '  - {type: mine, firmware: fw-rotation}',
    '  - {type: rotation}',
    'module_types: {mine: mine.yaml}',
    'placement: {position_m: [0, 0, 0.02], roll_deg: 90}',
    'central: {params: {gait: 0}}',
    ''].join('\n'));
  const r = chainsim(['run', scene, '--out', join(dir, 'run'), '--quiet']);
  assert.equal(r.code, 0, r.stderr);
  const page = await open(join(dir, 'run'));
  const legend = await page.locator('.cs-legend').textContent();
  assert.match(legend, /rotation ×2/);
  assert.match(legend, /mine ×1/);
  const colors = await page.evaluate(() => window.chainsimViewer.data.scene.modules.map((m) => m.color));
  assert.notEqual(colors[1], colors[0], 'a type of its own has a colour of its own');
  const o = await page.evaluate(() => {
    const s = window.chainsimViewer.data.orientationSeries();
    return { roll: Array.from(s.roll), heading: Array.from(s.heading) };
  });
  assert.ok(Math.abs(Math.abs(o.roll[0]) - 90) < 5, `roll at the start ${o.roll[0]}`);
  assert.ok(Math.abs(o.heading[0]) < 5, `heading ${o.heading[0]}`);
  const titles = await page.locator('.plot .u-title').allTextContents();
  assert.ok(titles.some((x) => /chain: heading, pitch and roll/.test(x)), titles.join(' | '));
  const channels = await page.evaluate(() => window.chainsimViewer.data.sensorColumns(0));
  const header = readFileSync(join(dir, 'run', 'trace.csv'), 'utf8').split('\n')[0].split(',');
  for (const h of header.filter((h) => /^m0\.[a-z_]+\.counts$/.test(h))) assert.ok(channels.includes(h), `${h} not plotted`);
  assert.ok(channels.length > 0, 'the rotation module has sensor channels');
  // the stripes of the modules' tops: on the side of a chain on its side
  const side = await page.evaluate(() => {
    const v = window.chainsimViewer.scene3d;
    const out = [];
    v.scene.traverse((o) => {
      if (o.userData?.stripe) {
        const p = o.getWorldPosition(new o.position.constructor());
        const c = o.parent.getWorldPosition(new o.position.constructor());
        out.push([p.x - c.x, p.y - c.y, p.z - c.z]);
      }
    });
    return out;
  });
  assert.ok(side.length >= 3, `stripes ${side.length}`);
  for (const [x, y, z] of side) assert.ok(Math.abs(y) > Math.abs(z), `a stripe at ${[x, y, z]} is not on the side`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

// `chainsim view A B`: two runs side by side, in step; their plots overlaid;
// the table of their summaries' differences, the log lines that differ and
// where they first differ. A run against a copy of itself: nothing differs.
test('two runs of a scene compared side by side', async () => {
  const dir = tempDir('compare');
  const a = join(dir, 'seed1'), b = join(dir, 'seed2'), same = join(dir, 'copy');
  for (const [out, seed] of [[a, 1], [b, 2]]) {
    const r = chainsim(['run', '--duration', '1', '--seed', String(seed), '--out', out, '--quiet']);
    assert.equal(r.code, 0, r.stderr);
  }
  cpSync(a, same, { recursive: true });
  const r = chainsim(['view', a, b]);
  assert.equal(r.code, 0, r.stderr);
  const html = join(a, 'compare.html');
  assert.ok(existsSync(html));
  const page = await newPage(browser);
  await page.goto(`file://${html}`);
  await waitFor(() => page.evaluate(() => window.chainsimViewer?.state.ready), 30000, 'the comparison to be ready');
  assert.equal(await page.locator('.cs-view3d canvas').count(), 2, 'two 3-D views');
  const labels = await page.locator('.cs-pane-label').allTextContents();
  assert.deepEqual(labels, ['A: seed1', 'B: seed2']);
  const c = await page.evaluate(() => window.chainsimViewer.comparison);
  const row = (name) => c.rows.find((x) => x[0] === name);
  const sa = JSON.parse(readFileSync(join(a, 'summary.json'), 'utf8'));
  const sb = JSON.parse(readFileSync(join(b, 'summary.json'), 'utf8'));
  assert.deepEqual(row('distance (m)').slice(1), [sa.chain.distance_m, sb.chain.distance_m]);
  assert.ok(c.trace, 'two seeds: the traces differ somewhere');
  assert.ok(c.trace.t >= 0 && c.trace.t <= 1, `first difference at ${c.trace.t}`);
  assert.match(await page.locator('.cs-compare').textContent(), /traces first differ at t=/);
  // in step: seeking moves both views
  await page.evaluate(() => window.chainsimViewer.seek(0.7));
  const poses = await page.evaluate(() => [window.chainsimViewer.scene3d, window.chainsimViewer.scene3dB]
    .map((s) => s.modules[0].bodies[0].mesh.position.x));
  assert.ok(poses.every((x) => Number.isFinite(x)), `${poses}`);
  // overlaid: the servo plot has A's two series and B's two
  const series = await page.evaluate(() => window.chainsimViewer.plots.plots.servo.u.series.map((s) => s.label));
  assert.deepEqual(series.slice(1), ['set-point', 'angle', 'set-point (B)', 'angle (B)']);
  assert.deepEqual(page.problems, []);
  await page.close();

  // the same run twice: no difference anywhere
  assert.equal(chainsim(['view', a, same, '-o', join(dir, 'same.html')]).code, 0);
  const p2 = await newPage(browser);
  await p2.goto(`file://${join(dir, 'same.html')}`);
  await waitFor(() => p2.evaluate(() => window.chainsimViewer?.state.ready), 30000, 'the comparison to be ready');
  const c2 = await p2.evaluate(() => window.chainsimViewer.comparison);
  assert.equal(c2.trace, null);
  assert.equal(c2.first, null);
  assert.deepEqual([c2.logOnlyA.length, c2.logOnlyB.length], [0, 0]);
  assert.match(await p2.locator('.cs-compare').textContent(), /no divergence on any channel/);
  assert.deepEqual(p2.problems, []);
  await p2.close();
});
