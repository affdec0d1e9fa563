// chainsim viewer: the page of `chainsim view` (a replay with the run's data
// inlined) and of `chainsim run --live` (the run streamed over a WebSocket).
// URL hash options: t=SECONDS (start there), hideui (the 3-D view only, posed
// at t: used for pictures), play, speed=X, follow=0, walls=cut|glass|solid
// (how pipe and mesh walls are drawn), zoom=X (the camera X times farther).
import 'uplot/dist/uPlot.min.css';
import './style.css';
import { RunData, logLines } from './data.js';
import { Scene3D } from './scene3d.js';
import { Plots } from './plots.js';
import { Timeline } from './timeline.js';
import { connectLive } from './live.js';
import { buildPage } from './page.js';
import { buildCompareTable, compareRuns } from './compare.js';

const hash = new URLSearchParams(location.hash.slice(1));
const hideui = hash.has('hideui');
const boot = JSON.parse(document.getElementById('chainsim-data')?.textContent || '{"mode":"none"}');
const data = new RunData();
// `chainsim view A B`: a second run, drawn beside the first, its plots over the first's
const compare = boot.mode === 'compare';
const dataB = compare ? new RunData() : null;
const ui = buildPage(document.body, { hideui });
const duration = () => Math.max(data.duration, dataB?.duration ?? 0);

const view = {
  time: Number(hash.get('t') ?? 0) || 0,
  playing: hash.has('play'),
  speed: Number(hash.get('speed') ?? 1) || 1,
  liveEdge: boot.mode === 'live',  // a live page follows the newest row until the user seeks
  seek(t, ev) {
    view.time = Math.max(0, Math.min(t, duration()));
    view.liveEdge = false;
    changed(ev);
  },
};
const state = { ready: false, rowsReceived: 0, messages: 0, finished: false, status: '', errors: [] };
window.chainsimViewer = { state, view, data, seek: (t) => view.seek(t) };
// what went wrong, for `chainsim view --png` and the tests (registered before
// anything below can throw; async code fails as an unhandled rejection)
window.addEventListener('error', (e) => state.errors.push(String(e.message)));
window.addEventListener('unhandledrejection', (e) => state.errors.push(String(e.reason?.message ?? e.reason)));

// the 3-D view; two panes side by side when comparing, each labelled
function pane(label) {
  const p = document.createElement('div');
  p.className = 'cs-pane';
  ui.view3d.append(p);
  const tag = document.createElement('div');
  tag.className = 'cs-pane-label';
  tag.textContent = label;
  p.append(tag);
  return p;
}
if (compare) ui.view3d.classList.add('cs-split');
const scene3d = new Scene3D(compare ? pane(`A: ${boot.labels[0]}`) : ui.view3d, {
  preserveDrawingBuffer: hideui,
  note: (s) => ui.note(s),
});
const scene3dB = compare ? new Scene3D(pane(`B: ${boot.labels[1]}`), { preserveDrawingBuffer: hideui, note: (s) => ui.note(s) }) : null;
scene3d.follow = hash.get('follow') !== '0';
if (scene3dB) scene3dB.follow = scene3d.follow;
const zoom = Math.min(20, Math.max(0.1, Number(hash.get('zoom') ?? 1) || 1));
scene3d.wallMode = ['cut', 'glass', 'solid'].includes(hash.get('walls')) ? hash.get('walls') : 'cut';
window.chainsimViewer.scene3d = scene3d;
window.chainsimViewer.scene3dB = scene3dB;
window.chainsimViewer.dataB = dataB;
const plots = hideui ? null : new Plots(ui.plots, data, view, compare ? { data: dataB, labels: boot.labels } : null);
const timeline = hideui ? null : new Timeline(ui.timelinePlot, ui.timelineList, data, view);
Object.assign(window.chainsimViewer, { plots, timeline });

// per module: 'fault' after its fault event, 'touch' while its touch input is high.
// A fault that stopped the run comes after the trace's last row (a tick
// after it, or between two rows): once the run is over it is shown from the
// trace's end on, so the last frame of a stopped run shows it.
function moduleStates(t, d = data) {
  const states = {};
  let fault = null, lastFaultT = -1, touch = null;
  const end = d.duration;
  const at = (e) => (e.kind === 'fault' && state.finished ? Math.min(e.t, end) : e.t);
  for (const e of d.marks) {
    if (at(e) > t) break;
    if (e.kind === 'fault') {
      fault = e;
      lastFaultT = at(e);
      if (e.module >= 0) states[e.module] = 'fault';
    } else if (e.kind === 'touch' && e.module >= 0 && states[e.module] !== 'fault') {
      states[e.module] = e.level ? 'touch' : 'ok';
      if (e.level) touch = e;
    }
  }
  // a fault flashes (in wall-clock time, also while paused) for 2 s of simulated time
  const flashing = lastFaultT >= 0 && t - lastFaultT < 2;
  let phase = flashing ? 0.5 + 0.5 * Math.cos((performance.now() / 1000) * 2 * Math.PI * 2.5) : 0.35;
  if (hideui && flashing) phase = 1;  // a picture: the same every time
  return { states, fault, touch, phase, flashing };
}

let lastUi = 0;
function changed(selected) {
  scene3d.pose(data, view.time);
  const ms = moduleStates(view.time);
  scene3d.highlight(ms.states, ms.phase);
  if (scene3dB && dataB.rows) {
    scene3dB.pose(dataB, Math.min(view.time, dataB.duration));
    const mb = moduleStates(view.time, dataB);
    scene3dB.highlight(mb.states, mb.phase);
  }
  state.flashing = ms.flashing;
  ui.banner(ms.fault ? `FAULT at t=${ms.fault.t.toFixed(3)} s: ${ms.fault.text}` : '', 'fault');
  ui.touchBadge(ms.touch && view.time - ms.touch.t < 0.5 ? `touch: module ${ms.touch.module}` : '');
  ui.setTime(view.time, duration());
  const now = performance.now();
  if (selected !== undefined || now - lastUi > 80) {
    lastUi = now;
    plots?.redrawMarkers();
    timeline?.follow(view.time);
  }
}

let lastFrame = performance.now();
function frame(now) {
  const dt = Math.min(0.1, (now - lastFrame) / 1000);
  lastFrame = now;
  if (data.rows) {
    if (view.liveEdge) {
      view.time = data.duration;
      changed();
    } else if (view.playing) {
      view.time += dt * view.speed;
      if (view.time >= duration()) {
        view.time = duration();
        if (boot.mode !== 'live' || state.finished) view.playing = false;
      }
      changed();
      ui.setPlaying(view.playing);
    } else if (state.flashing) {
      changed();
    }
  }
  scene3d.render();
  scene3dB?.render();
  requestAnimationFrame(frame);
}

// the scene is known: build the 3-D view, the plots, the timeline
function onScene(files) {
  scene3d.build(data.scene, files ?? {});
  ui.title(`chainsim: ${data.scene.scene}`, `${data.scene.modules?.length ?? 0} modules, environment ${data.scene.environment?.type ?? '?'}`);
  if (plots) { plots.controls(ui.plotBar); plots.rebuild(); }
}

// new rows or events: refresh what depends on them (plots at most 4 times a second)
let refreshTimer = null;
function onData(immediate) {
  const go = () => {
    refreshTimer = null;
    plots?.update();
    timeline?.update();
    changed();
  };
  if (immediate) go();
  else if (!refreshTimer) refreshTimer = setTimeout(go, 250);
}

let posed = false;
async function firstPose() {
  if (posed) return;
  posed = true;
  view.time = Math.max(0, Math.min(view.time, duration()));
  scene3d.pose(data, view.time);
  scene3d.resetCamera(scene3d.span() * zoom);
  if (scene3dB) {
    scene3dB.pose(dataB, Math.min(view.time, dataB.duration));
    scene3dB.resetCamera(scene3dB.span() * zoom);
  }
  changed();
  scene3d.render(true);
  scene3dB?.render(true);
  await scene3d.envReady;  // meshes are parsed asynchronously
  await scene3dB?.envReady;
  scene3d.render(true);
  scene3dB?.render(true);
  state.ready = true;
  document.body.dataset.ready = '1';
}

ui.onControl({
  play: () => {
    if (view.time >= data.duration && !view.liveEdge) view.time = 0;
    view.playing = !view.playing;
    view.liveEdge = false;
    ui.setPlaying(view.playing);
  },
  scrub: (t) => view.seek(t),
  step: (d) => view.seek(view.time + d),
  speed: (s) => (view.speed = s),
  follow: (on) => { scene3d.follow = on; if (scene3dB) scene3dB.follow = on; },
  walls: (mode) => { scene3d.setWallMode(mode); scene3dB?.setWallMode(mode); },
  resetCamera: () => {
    scene3d.resetCamera(scene3d.span() * zoom);
    scene3dB?.resetCamera(scene3dB.span() * zoom);
  },
  live: () => { view.liveEdge = true; view.playing = false; },
  home: () => view.seek(0),
  end: () => view.seek(duration()),
});
ui.setPlaying(view.playing);
ui.setSpeed(view.speed);
ui.setFollow(scene3d.follow);
ui.setWalls(scene3d.wallMode);

// a run's files, inlined in the page, into d
function loadReplay(d, b) {
  const nl = b.trace.indexOf('\n');
  d.setScene(b.scene, nl < 0 ? b.trace : b.trace.slice(0, nl));
  d.addRows(nl < 0 ? '' : b.trace.slice(nl + 1));
  d.addBus(b.bus ?? '');
  d.addBus((b.logs ?? []).map((l) => logLines(l.endpoint, l.text)).join(''));
  if (b.summary) d.setSummary(b.summary);
}

if (compare) {
  loadReplay(data, boot.a);
  loadReplay(dataB, boot.b);
  state.rowsReceived = data.rows;
  state.finished = true;
  ui.status(`comparing A: ${boot.labels[0]} (${data.duration.toFixed(2)} s) and B: ${boot.labels[1]} ` +
    `(${dataB.duration.toFixed(2)} s)`);
  onScene(boot.a.mesh_files);
  scene3dB.build(dataB.scene, boot.b.mesh_files ?? {});
  ui.title(`chainsim: ${boot.labels[0]} vs ${boot.labels[1]}`, `${data.scene.scene}`);
  const c = compareRuns(boot, data, dataB);
  window.chainsimViewer.comparison = c;
  if (!hideui) buildCompareTable(ui.plots.parentElement, c);
  onData(true);
  firstPose();
} else if (boot.mode === 'replay') {
  loadReplay(data, boot);
  state.rowsReceived = data.rows;
  state.finished = true;
  ui.status(`replay: ${data.duration.toFixed(2)} s, ${data.rows} frames, ${data.events.length} events`);
  onScene(boot.mesh_files);
  onData(true);
  firstPose();
} else if (boot.mode === 'live') {
  ui.status('connecting');
  const why = sessionStorage.getItem('chainsim-reload');
  if (why) {
    sessionStorage.removeItem('chainsim-reload');
    ui.note(`reloaded: ${why}`);
    state.reloadedFor = why;
  }
  ui.liveMode(true);
  connectLive({
    status: (s) => { state.status = s; ui.status(`live: ${s}`); },
    started: (scene, header, files) => { data.setScene(scene, header); onScene(files); },
    rows: (csv) => {
      const before = data.rows;
      data.addRows(csv);
      state.rowsReceived += data.rows - before;
      state.messages++;
      if (!state.ready && data.rows) firstPose();
      onData(false);
    },
    bus: (lines) => { data.addBus(lines); onData(false); },
    gap: (n) => ui.note(`this page missed ${n} trace rows (it was too slow to receive them)`),
    // `chainsim run --watch` rebuilt and runs again: the next run from its start
    reload: (why) => {
      sessionStorage.setItem('chainsim-reload', why);
      location.reload();
    },
    finished: (summary) => {
      data.setSummary(summary);
      state.messagesAtFinish = state.messages;  // rows messages that came while the run went on
      state.finished = true;
      if (!state.ready) firstPose();
      onData(true);
      ui.liveMode(false);
    },
  });
} else {
  ui.status('no run data in this page');
}
requestAnimationFrame(frame);
