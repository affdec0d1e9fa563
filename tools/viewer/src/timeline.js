// The bus-log timeline: one lane per kind of event (I2C frames, Sin/Sout
// edges, address assignments, touch, faults, the modules' own log lines)
// drawn as points by uPlot, and the lines around the replay time as a list
// (a module's log line as "[E] text", E its endpoint). Clicking an event (a
// point or a line) jumps the replay to its time.
import uPlot from 'uplot';
import { onClick } from './plots.js';

export const LANES = [
  { kind: 'i2c', label: 'I2C', color: '#29335c' },
  { kind: 'sync', label: 'Sin/Sout', color: '#669bbc' },
  { kind: 'addr', label: 'address', color: '#8e5572' },
  { kind: 'touch', label: 'touch', color: '#2ecc40' },
  { kind: 'fault', label: 'fault', color: '#ff1a1a' },
  { kind: 'log', label: 'log', color: '#6a4c93' },
  { kind: 'other', label: 'other', color: '#888888' },
];
const LIST_ROWS = 60;

export class Timeline {
  constructor(plotEl, listEl, data, view) {
    this.plotEl = plotEl;
    this.listEl = listEl;
    this.data = data;
    this.view = view;
    this.events = [];
    this.listStart = -1;
    const lanes = LANES.map((l, k) => ({
      label: l.label, stroke: l.color, fill: l.color, paths: () => null,
      points: { show: true, size: l.kind === 'fault' ? 11 : 6, width: 1, fill: l.color, stroke: l.color },
      value: (u, v) => (v == null ? '' : l.label), lane: k,
    }));
    const yLabels = LANES.map((l) => l.label);
    this.u = new uPlot({
      width: 600, height: 150,
      scales: { x: { time: false }, y: { range: [-0.7, LANES.length - 0.3] } },
      cursor: { sync: { key: 'chainsim' }, drag: { x: true, y: false }, points: { show: false } },
      legend: { show: false },
      series: [{ label: 't (s)' }, ...lanes],
      axes: [
        { label: 'bus log: t (s)', size: 34 },
        { size: 70, splits: () => LANES.map((_, k) => k), values: (u, vals) => vals.map((v) => yLabels[v] ?? '') },
      ],
      plugins: [{
        hooks: {
          draw: [(u) => {
            const x = u.valToPos(this.view.time, 'x', true);
            if (!Number.isFinite(x)) return;
            u.ctx.save();
            u.ctx.strokeStyle = '#d00';
            u.ctx.lineWidth = 1.5 * devicePixelRatio;
            u.ctx.beginPath();
            u.ctx.moveTo(x, u.bbox.top);
            u.ctx.lineTo(x, u.bbox.top + u.bbox.height);
            u.ctx.stroke();
            u.ctx.restore();
          }],
          ready: [(u) => onClick(u.over, () => this.clickPlot(u))],
        },
      }],
    }, [[], ...lanes.map(() => [])], plotEl);
    listEl.addEventListener('click', (e) => {
      const row = e.target.closest('[data-t]');
      if (row) this.view.seek(Number(row.dataset.t));
    });
    new ResizeObserver(() => this.u.setSize({ width: Math.max(200, plotEl.clientWidth - 8), height: 150 })).observe(plotEl);
  }

  // the event nearest to the click in the lane under it
  clickPlot(u) {
    const { left, top } = u.cursor;
    if (left < 0) return;
    const t = u.posToVal(left, 'x');
    const lane = Math.round(u.posToVal(top, 'y'));
    const kind = LANES[Math.max(0, Math.min(LANES.length - 1, lane))].kind;
    let best = null;
    for (const e of this.events)
      if (e.kind === kind && (!best || Math.abs(e.t - t) < Math.abs(best.t - t))) best = e;
    const px = best ? Math.abs(u.valToPos(best.t, 'x') - left) : Infinity;
    this.view.seek(px < 12 ? best.t : t, best && px < 12 ? best : null);
  }

  // new events: one x column of every event time, a lane value where the event is of that lane
  update() {
    const end = Math.max(this.data.duration, 0.001);
    if (this.events === this.data.events && this.shown === this.events.length) {
      if (end !== this.end) this.u.setScale('x', { min: 0, max: (this.end = end) });
      return;
    }
    this.events = this.data.events;
    this.shown = this.events.length;
    const n = this.events.length;
    const xs = new Float64Array(n);
    const ys = LANES.map(() => new Array(n).fill(null));
    this.events.forEach((e, i) => {
      xs[i] = e.t;
      const k = LANES.findIndex((l) => l.kind === e.kind);
      ys[k][i] = k;
    });
    this.end = Math.max(end, n ? this.events[n - 1].t : 0);
    this.u.setData([xs, ...ys], false);
    this.u.setScale('x', { min: 0, max: this.end });
    this.listStart = -1;
    this.follow(this.view.time);
  }

  // the list shows the lines around time t; the first line at or after t is marked
  follow(t) {
    const ev = this.events;
    let k = this.data.eventAt(t);
    if (k >= ev.length) k = ev.length - 1;
    const start = Math.max(0, k - LIST_ROWS / 2);
    if (start !== this.listStart) {
      this.listStart = start;
      this.listEl.replaceChildren(...ev.slice(start, start + LIST_ROWS).map((e) => {
        const row = document.createElement('div');
        row.className = `ev ev-${e.kind}`;
        row.dataset.t = e.t;
        row.textContent = e.line;
        return row;
      }));
    }
    for (const row of this.listEl.children) row.classList.toggle('now', Number(row.dataset.t) === ev[k]?.t);
    // keep the marked line in the middle of the list (scrolling the list only, never the page)
    const now = this.listEl.querySelector('.now');
    if (now) this.listEl.scrollTop = now.offsetTop - this.listEl.clientHeight / 2;
    this.u.redraw(false, false);
  }
}
