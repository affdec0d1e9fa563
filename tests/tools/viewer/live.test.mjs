// `chainsim run --live`: the page served on 127.0.0.1 gets trace frames while
// the simulation runs, then `finished`; the trace is byte-identical to that of
// a run without the live view, and chainsim exits once the page has the end.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launch, makeRun, newPage, sha256File, startChainsim, tempDir, waitFor, within, cleanup } from './util.mjs';
import { readFileSync } from 'node:fs';

let browser, dir;
const DURATION = 6;  // about a second of wall time: many 40 ms frames

before(async () => {
  dir = tempDir('live');
  browser = await launch();
});
after(async () => {
  await browser?.close();
  cleanup();
});

test('the live page receives frames during the run; the trace is unchanged', async () => {
  const cs = startChainsim(['run', '--duration', String(DURATION), '--out', join(dir, 'live'), '--live',
    '--live-wait', '60']);
  const url = await waitFor(() => /live view at (http:\/\/127\.0\.0\.1:\d+\/)/.exec(cs.stderrText)?.[1], 30000,
    'the live URL on stderr');
  const res = await fetch(url + 'nothing-here');
  assert.equal(res.status, 404);
  const page = await newPage(browser);
  await page.goto(url);
  const state = () => page.evaluate(() => ({ ...window.chainsimViewer.state }));
  await waitFor(async () => (await state()).finished, 120000, 'finished');
  const code = await within(cs.exited, 15000, 'still running');
  assert.equal(code, 0, cs.stderrText);
  const st = await state();
  const rows = readFileSync(join(dir, 'live', 'trace.csv'), 'utf8').trim().split('\n').length - 1;
  assert.equal(st.rowsReceived, rows, 'every trace row reached the page');
  // frames arrive while the run is still going: the server sends what the
  // run produced every 40 ms, so a run of about a second (24 sends here) comes
  // in many messages before 'finished', counted by the page itself (not by
  // polling it); a machine 8 times faster than this one would still send 3
  assert.ok(st.messagesAtFinish >= 3, `only ${st.messagesAtFinish} messages of rows before the end of the run`);
  assert.ok(await page.evaluate(() => window.chainsimViewer.data.summary?.trace_sha256), 'summary received');
  assert.deepEqual(page.problems, []);
  await page.close();

  const plain = makeRun(join(dir, 'plain'), DURATION);
  const live = join(dir, 'live', 'trace.csv');
  assert.equal(sha256File(live), sha256File(join(plain, 'trace.csv')), 'the live view changed the trace');
  const summary = JSON.parse(readFileSync(join(dir, 'live', 'summary.json'), 'utf8'));
  assert.equal(summary.trace_sha256, sha256File(live));
});

test('with no page connected, chainsim exits after a short grace period', async () => {
  const t0 = Date.now();
  const cs = startChainsim(['run', '--duration', '0.5', '--out', join(dir, 'alone'), '--live']);
  const code = await within(cs.exited, 60000, 'still running');
  assert.equal(code, 0, cs.stderrText);
  assert.match(cs.stderrText, /live view at http:\/\/127\.0\.0\.1:\d+\//);
  assert.ok(Date.now() - t0 < 30000);
});
