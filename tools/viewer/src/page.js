// The page's layout and controls: title and status, the 3-D view with the
// fault banner, the transport bar (play/pause, scrub, speed, follow), the bus
// timeline and log, and the plots. Keyboard: Space play/pause, Left/Right
// step 10 ms (Shift: 100 ms), Home/End, +/- speed, F follow, W walls (pipes
// and meshes cut away / see-through / solid), R reset camera, L back to the live edge.
const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 4, 8];
const WALLS = [['cut', 'walls: cut away'], ['glass', 'walls: see-through'], ['solid', 'walls: solid']];

function el(tag, cls, parent, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  parent?.appendChild(e);
  return e;
}

export function buildPage(body, { hideui }) {
  body.classList.toggle('hideui', hideui);
  const root = el('div', 'cs-root', body);
  const head = el('header', 'cs-head', root);
  const titleEl = el('span', 'cs-title', head, 'chainsim');
  const subEl = el('span', 'cs-sub', head);
  const statusEl = el('span', 'cs-status', head);

  const left = el('div', 'cs-left', root);
  const view3d = el('div', 'cs-view3d', left);
  const bannerEl = el('div', 'cs-banner', view3d);
  const touchEl = el('div', 'cs-touch', view3d);
  const noteEl = el('div', 'cs-note', view3d);
  const help = el('div', 'cs-help', view3d,
    'drag: orbit, right-drag: pan, wheel: zoom | Space play, \u2190/\u2192 step, F follow, W walls, R reset view');

  const bar = el('div', 'cs-bar', left);
  const playBtn = el('button', 'cs-play', bar, '\u25b6');
  playBtn.title = 'play / pause (Space)';
  const slider = el('input', 'cs-scrub', bar);
  Object.assign(slider, { type: 'range', min: 0, max: 1, step: 0.001, value: 0 });
  const timeEl = el('span', 'cs-time', bar, '0.000 / 0.000 s');
  const speedSel = el('select', 'cs-speed', bar);
  for (const s of SPEEDS) speedSel.add(new Option(`${s}\u00d7`, s));
  const followLbl = el('label', 'cs-follow', bar);
  const followBox = el('input', '', followLbl);
  followBox.type = 'checkbox';
  followLbl.append(' follow');
  const wallsSel = el('select', 'cs-walls', bar);
  wallsSel.title = 'pipe and mesh walls: the half facing the camera cut away, see-through, or solid (W)';
  for (const [v, t] of WALLS) wallsSel.add(new Option(t, v));
  const resetBtn = el('button', 'cs-reset', bar, 'reset view');
  const liveBtn = el('button', 'cs-live', bar, 'live');
  liveBtn.hidden = true;

  const timelinePlot = el('div', 'cs-timeline', left);
  const timelineList = el('div', 'cs-buslist', left);

  const right = el('div', 'cs-right', root);
  const plotBar = el('div', 'cs-plotbar', right);
  const plots = el('div', 'cs-plots', right);

  let duration = 0, handlers = {};
  const api = {
    view3d, plots, plotBar, timelinePlot, timelineList,
    title(t, sub) { titleEl.textContent = t; subEl.textContent = sub; document.title = t; },
    status(s) { statusEl.textContent = s; },
    note(s) { noteEl.textContent = s; noteEl.hidden = !s; },
    banner(s) { bannerEl.textContent = s; bannerEl.hidden = !s; },
    touchBadge(s) { touchEl.textContent = s; touchEl.hidden = !s; },
    setTime(t, d) {
      duration = d;
      slider.max = Math.max(d, 0.001);
      if (document.activeElement !== slider) slider.value = t;
      timeEl.textContent = `${t.toFixed(3)} / ${d.toFixed(3)} s`;
    },
    setPlaying(p) { playBtn.textContent = p ? '\u23f8' : '\u25b6'; },
    setSpeed(s) { speedSel.value = SPEEDS.includes(s) ? s : 1; },
    setFollow(f) { followBox.checked = f; },
    setWalls(m) { wallsSel.value = m; },
    liveMode(on) { liveBtn.hidden = !on; },
    onControl(h) { handlers = h; },
  };
  api.note('');
  api.banner('');
  api.touchBadge('');

  playBtn.onclick = () => handlers.play?.();
  slider.oninput = () => handlers.scrub?.(Number(slider.value));
  speedSel.onchange = () => handlers.speed?.(Number(speedSel.value));
  followBox.onchange = () => handlers.follow?.(followBox.checked);
  wallsSel.onchange = () => handlers.walls?.(wallsSel.value);
  resetBtn.onclick = () => handlers.resetCamera?.();
  liveBtn.onclick = () => handlers.live?.();
  window.addEventListener('keydown', (e) => {
    if (e.target.closest?.('input[type=text], select')) return;
    const step = e.shiftKey ? 0.1 : 0.01;
    const k = e.key;
    if (k === ' ') handlers.play?.();
    else if (k === 'ArrowLeft') handlers.step?.(-step);
    else if (k === 'ArrowRight') handlers.step?.(step);
    else if (k === 'Home') handlers.home?.();
    else if (k === 'End') handlers.end?.();
    else if (k === '+' || k === '=' || k === '-') {
      const i = SPEEDS.indexOf(Number(speedSel.value)) + (k === '-' ? -1 : 1);
      speedSel.value = SPEEDS[Math.max(0, Math.min(SPEEDS.length - 1, i))];
      handlers.speed?.(Number(speedSel.value));
    } else if (k === 'f' || k === 'F') {
      followBox.checked = !followBox.checked;
      handlers.follow?.(followBox.checked);
    } else if (k === 'w' || k === 'W') {
      wallsSel.selectedIndex = (wallsSel.selectedIndex + 1) % WALLS.length;
      handlers.walls?.(wallsSel.value);
    } else if (k === 'r' || k === 'R') handlers.resetCamera?.();
    else if (k === 'l' || k === 'L') handlers.live?.();
    else return;
    e.preventDefault();
  });
  return api;
}
