// `chainsim run --live`: the page served on 127.0.0.1 gets trace frames while
// the simulation runs, then `finished`; the trace is byte-identical to that of
// a run without the live view, and chainsim exits once the page has the end.
// Only that page may read the run: another Host (DNS rebinding) or another
// Origin (a WebSocket opened by another site's page), or none, gets 403.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { randomBytes } from 'node:crypto';
import http from 'node:http';
import { spawnSync } from 'node:child_process';
import { dirname, join } from 'node:path';
import { launch, makeRun, newPage, sha256File, startChainsim, tempDir, waitFor, within, cleanup } from './util.mjs';
import { cpSync, existsSync, readFileSync, writeFileSync } from 'node:fs';

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

// one request to the live server on a real connection, with exactly these
// headers (Host too: none when host is null); resolves {status, body}, or
// {status: 101, socket} when it is upgraded to a WebSocket
function request(port, { path = '/', host, origin, upgrade = false }) {
  const headers = {};
  if (host !== null) headers.Host = host;
  if (origin !== undefined) headers.Origin = origin;
  if (upgrade) {
    Object.assign(headers, { Connection: 'Upgrade', Upgrade: 'websocket', 'Sec-WebSocket-Version': '13',
      'Sec-WebSocket-Key': randomBytes(16).toString('base64') });
  }
  return new Promise((resolve, reject) => {
    const req = http.request({ host: '127.0.0.1', port, path, headers, setHost: false, agent: false });
    req.on('response', (res) => {
      let body = '';
      res.setEncoding('utf8');
      res.on('data', (d) => (body += d));
      res.on('end', () => resolve({ status: res.statusCode, body }));
    });
    req.on('upgrade', (res, socket, head) => resolve({ status: res.statusCode, socket, head }));
    req.on('error', reject);
    req.end();
  });
}

test('only the live page may read the run: another Host or Origin gets 403', async () => {
  const out = join(dir, 'guarded');
  const cs = startChainsim(['run', '--duration', '0.5', '--out', out, '--live', '--live-wait', '120']);
  const url = await waitFor(() => /live view at (http:\/\/127\.0\.0\.1:\d+\/)/.exec(cs.stderrText)?.[1], 30000,
    'the live URL on stderr');
  const port = Number(new URL(url).port);
  const ours = `127.0.0.1:${port}`, local = `localhost:${port}`;

  // refused, each with its reason and nothing of the run
  const refused = [
    [{ host: `rebind.test:${port}` }, /Host 'rebind\.test:\d+' is not this live view/],
    [{ host: `127.0.0.1:${port + 1}` }, /Host '127\.0\.0\.1:\d+' is not this live view/],
    [{ host: null }, /no Host header/],
    [{ host: `rebind.test:${port}`, origin: `http://rebind.test:${port}`, path: '/ws', upgrade: true },
      /Host 'rebind\.test:\d+'/],
    [{ host: ours, origin: 'http://evil.test', path: '/ws', upgrade: true }, /Origin 'http:\/\/evil\.test' is not the live page/],
    [{ host: ours, origin: `http://127.0.0.1:${port + 1}`, path: '/ws', upgrade: true }, /Origin .* is not the live page/],
    [{ host: ours, origin: `https://127.0.0.1:${port}`, path: '/ws', upgrade: true }, /Origin .* is not the live page/],
    [{ host: ours, origin: 'null', path: '/ws', upgrade: true }, /Origin 'null' is not the live page/],
    [{ host: ours, path: '/ws', upgrade: true }, /a WebSocket without an Origin header/],
    [{ host: ours, origin: 'http://evil.test' }, /Origin 'http:\/\/evil\.test' is not the live page/],
  ];
  for (const [req, why] of refused) {
    const r = await request(port, req);
    assert.equal(r.status, 403, JSON.stringify(req));
    assert.match(r.body, /^forbidden: /, JSON.stringify(req));
    assert.match(r.body, why, JSON.stringify(req));
    assert.doesNotMatch(r.body, /<html|chainsim live|"type"/i, JSON.stringify(req));
  }
  assert.match(cs.stderrText, /live view: refused a request: /);

  // a real browser: a name of another site resolved to 127.0.0.1 (DNS
  // rebinding) gets 403; a page of another site (another port) that opens a
  // WebSocket to the live view gets no connection and no message
  const other = await launch(['--host-resolver-rules=MAP rebind.test 127.0.0.1']);
  const site = http.createServer((req, res) => {
    res.writeHead(200, { 'Content-Type': 'text/html' });
    res.end(`<script>
      window.result = new Promise((resolve) => {
        const ws = new WebSocket('ws://127.0.0.1:${port}/ws');
        let messages = 0;
        ws.onmessage = () => messages++;
        ws.onopen = () => resolve('open');
        ws.onerror = () => resolve('error, ' + messages + ' messages');
      });
    </script>`);
  });
  await new Promise((r) => site.listen(0, '127.0.0.1', r));
  try {
    const page = await other.newPage();
    const res = await page.goto(`http://rebind.test:${port}/`);
    assert.equal(res.status(), 403);
    assert.match(await page.content(), /Host 'rebind\.test:\d+' is not this live view/);
    await page.goto(`http://127.0.0.1:${site.address().port}/`);
    assert.equal(await page.evaluate(() => window.result), 'error, 0 messages');
  } finally {
    await other.close();
    site.close();
  }
  // none of these was a page: the run still waits for one
  assert.equal(existsSync(join(out, 'trace.csv')), false, 'the run started: a refused request counted as a page');

  // the right ones: the page by either name, and its WebSocket
  for (const host of [ours, local]) {
    const r = await request(port, { host });
    assert.equal(r.status, 200);
    assert.match(r.body, /<html/i);
  }
  const ws = await request(port, { host: local, origin: `http://localhost:${port}`, path: '/ws', upgrade: true });
  assert.equal(ws.status, 101);
  let got = ws.head.toString('latin1');
  ws.socket.on('data', (d) => (got += d.toString('latin1')));
  await waitFor(() => got.includes('"type":"started"'), 60000, 'the run on the WebSocket');
  ws.socket.destroy();
  const code = await within(cs.exited, 60000, 'still running');
  assert.equal(code, 0, cs.stderrText);
});

// `chainsim run --watch`: an out-of-tree program (the example project) run
// live; its source edited, chainsim rebuilds it with CMake, runs again, and
// the open page reloads and shows the new run; Ctrl-C ends it with 130.
test('run --watch rebuilds a changed program, reruns, and the open page reloads', async () => {
  const proj = join(dir, 'watch-project');
  cpSync(new URL('../../../firmware/examples/triangle-wave', import.meta.url), proj, { recursive: true });
  const buildTree = dirname(dirname(process.env.CHAINSIM_EXE));
  for (const args of [['-S', proj, '-B', join(proj, 'build'), `-Dchainsim_DIR=${buildTree}`], ['--build', join(proj, 'build')]]) {
    const r = spawnSync('cmake', args, { encoding: 'utf8' });
    assert.equal(r.status, 0, r.stdout + r.stderr);
  }
  const cs = startChainsim(['run', join(proj, 'scene.yaml'), '--watch', '--firmware-dir', join(proj, 'build'),
    '--duration', '0.5', '--out', join(dir, 'watch-run'), '-q']);
  const url = await waitFor(() => /live view at (http:\/\/127\.0\.0\.1:\d+\/)/.exec(cs.stderrText)?.[1], 30000,
    'the live URL on stderr');
  const page = await newPage(browser);
  await page.goto(url);
  const logs = () => page.evaluate(() => window.chainsimViewer.data.events.filter((e) => e.kind === 'log').map((e) => e.text));
  await waitFor(async () => (await page.evaluate(() => window.chainsimViewer?.state.finished)), 60000, 'the first run');
  assert.ok((await logs()).some((t) => t.startsWith('triangle: start')), (await logs()).join(' | '));
  // the program changed: rebuilt, run again, the page reloaded with the new run
  const src = join(proj, 'triangle_wave.c');
  writeFileSync(src, readFileSync(src, 'utf8').replace('"triangle: start amp_cdeg="', '"triangle v2: start amp_cdeg="'));
  await waitFor(async () => {
    try {
      const st = await page.evaluate(() => ({ r: window.chainsimViewer?.state.reloadedFor, f: window.chainsimViewer?.state.finished }));
      return st.r && st.f;
    } catch { return false; }  // the page is reloading
  }, 120000, 'the page to reload with the second run');
  assert.match(await page.evaluate(() => window.chainsimViewer.state.reloadedFor), /rebuilt: .*triangle_wave\.c/);
  assert.ok((await logs()).some((t) => t.startsWith('triangle v2: start')), (await logs()).join(' | '));
  assert.match(cs.stderrText, /--watch: building: cmake --build /);
  assert.deepEqual(page.problems, []);
  await page.close();
  cs.kill('SIGINT');
  assert.equal(await within(cs.exited, 15000, 'still watching after SIGINT'), 130, cs.stderrText);
});
