// The plots under the 3-D view (uPlot): servo set-point vs angle of one joint,
// the motor currents of one module, chain distance and speed, energy per
// module. All share the time axis: a cursor synced between them, a line at
// the replay time, and a click jumps the replay there.
import uPlot from 'uplot';

const PALETTE = ['#e4572e', '#29335c', '#f3a712', '#669bbc', '#a8c686', '#8e5572', '#2a9d8f', '#264653',
  '#e76f51', '#6d597a', '#b56576', '#355070'];

// a click that is not the end of a drag (a drag zooms)
export function onClick(el, f) {
  let down = null;
  el.addEventListener('mousedown', (e) => (down = [e.clientX, e.clientY]));
  el.addEventListener('click', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) f(e);
  });
}

// a uPlot plugin: a vertical line at the replay time; click to seek
function timeMarker(view) {
  return {
    hooks: {
      draw: [(u) => {
        const x = u.valToPos(view.time, 'x', true);
        if (!Number.isFinite(x)) return;
        const { ctx } = u;
        ctx.save();
        ctx.strokeStyle = '#d00';
        ctx.lineWidth = 1.5 * devicePixelRatio;
        ctx.beginPath();
        ctx.moveTo(x, u.bbox.top);
        ctx.lineTo(x, u.bbox.top + u.bbox.height);
        ctx.stroke();
        ctx.restore();
      }],
      ready: [(u) => onClick(u.over, () => {
        if (u.cursor.left >= 0) view.seek(u.posToVal(u.cursor.left, 'x'));
      })],
    },
  };
}

function makePlot(el, title, series, axes, view, sync) {
  const box = document.createElement('div');
  box.className = 'plot';
  el.appendChild(box);
  const opts = {
    title,
    width: 400,
    height: 170,
    cursor: { sync: { key: sync.key }, drag: { x: true, y: false } },
    scales: { x: { time: false } },
    legend: { live: true },
    series: [{ label: 't (s)' }, ...series],
    axes: [{ label: 't (s)', size: 34 }, ...axes],
    plugins: [timeMarker(view)],
  };
  const data = [[], ...series.map(() => [])];
  const u = new uPlot(opts, data, box);
  return { u, box };
}

// ys of a run sampled at the times ts of another (linear between rows; NaN
// past the run's end): a second run's series drawn over the first's
function resample(d, ys, ts) {
  const out = new Float64Array(ts.length);
  for (let r = 0; r < ts.length; r++) {
    const br = ts[r] <= d.duration + 1e-12 ? d.bracket(ts[r]) : null;
    out[r] = br && ys ? ys[br.i] + br.f * (ys[br.j] - ys[br.i]) : NaN;
  }
  return out;
}

// the series of a second run: the same colours, dashed, labelled B
const dashed = (series) => series.map((s) => ({ ...s, label: `${s.label} (B)`, dash: [5, 4], width: 1.2 }));

export class Plots {
  // el: container; data: RunData; view: {time, seek(t)}; other: {data, labels}
  // of a second run whose servo, orientation and chain series are drawn over
  // the first's (`chainsim view A B`)
  constructor(el, data, view, other = null) {
    this.el = el;
    this.data = data;
    this.view = view;
    this.other = other;
    this.sync = uPlot.sync('chainsim');
    this.module = 0;
    this.joint = 0;
    this.plots = {};
    this.builtFor = null;
    new ResizeObserver(() => this.resize()).observe(el);
  }

  // the selects for module and joint, built once the scene is known
  controls(bar) {
    this.bar = bar;
    bar.innerHTML = '';
    const mk = (label, cls) => {
      const l = document.createElement('label');
      l.textContent = label + ' ';
      const s = document.createElement('select');
      s.className = cls;
      l.appendChild(s);
      bar.appendChild(l);
      return s;
    };
    this.modSel = mk('module', 'sel-module');
    this.jointSel = mk('joint', 'sel-joint');
    const mods = this.data.scene?.modules ?? [];
    for (const m of mods) this.modSel.add(new Option(`${m.index} ${m.type}`, m.index));
    this.modSel.onchange = () => { this.module = Number(this.modSel.value); this.fillJoints(); this.rebuild(); };
    this.jointSel.onchange = () => { this.joint = Number(this.jointSel.value); this.rebuild(); };
    this.fillJoints();
  }

  fillJoints() {
    const m = this.data.scene?.modules?.[this.module];
    this.jointSel.innerHTML = '';
    (m?.servos ?? []).forEach((s, j) => this.jointSel.add(new Option(`s${j} ${s}`, j)));
    this.joint = Math.min(this.joint, Math.max(0, (m?.servos?.length ?? 1) - 1));
    this.jointSel.value = this.joint;
  }

  // build the plots for the current selection (series depend on it)
  rebuild() {
    for (const p of Object.values(this.plots)) { p.u.destroy(); p.box.remove(); }
    this.plots = {};
    const sc = this.data.scene;
    if (!sc) return;
    const m = sc.modules?.[this.module];
    const servos = m?.servos ?? [];
    const deg = { label: 'deg', size: 46 };
    const amp = { label: 'A', size: 46 };
    const sync = this.sync;
    const s = this.joint;
    const ob = this.other ? dashed : () => [];
    const servoSeries = [{ label: 'set-point', stroke: '#29335c', width: 1.5, dash: [6, 3] },
      { label: 'angle', stroke: '#e4572e', width: 1.5 }];
    this.plots.servo = makePlot(this.el, `module ${this.module}: ${servos[s] ?? 'no servo'}: set-point vs angle`,
      [...servoSeries, ...ob(servoSeries)], [deg], this.view, sync);
    this.plots.current = makePlot(this.el, `module ${this.module}: motor currents`,
      [...servos.map((n, j) => ({ label: `s${j} ${n}`, stroke: PALETTE[j + 1], width: 1 })),
        { label: 'supply', stroke: '#444', width: 1.5 }], [amp], this.view, sync);
    const channels = this.data.sensorColumns(this.module);
    this.channels = channels;
    if (channels.length)
      this.plots.sensors = makePlot(this.el, `module ${this.module}: sensor channels (trace.csv)`,
        channels.map((c, k) => ({ label: c.slice(c.indexOf('.') + 1), stroke: PALETTE[k % PALETTE.length], width: 1 })),
        [{ label: 'value', size: 50 }], this.view, sync);
    const orientationSeries = [{ label: 'heading', stroke: '#29335c', width: 1.5 },
      { label: 'pitch', stroke: '#2a9d8f', width: 1.5 }, { label: 'roll', stroke: '#e4572e', width: 1.5 }];
    this.plots.orientation = makePlot(this.el, 'chain: heading, pitch and roll',
      [...orientationSeries, ...ob(orientationSeries)], [deg], this.view, sync);
    const chainSeries = [{ label: 'distance (m)', stroke: '#29335c', width: 1.5, scale: 'm' },
      { label: 'speed (m/s)', stroke: '#2a9d8f', width: 1.5, scale: 'mps' }];
    this.plots.chain = makePlot(this.el, 'chain (centre of mass)', [...chainSeries, ...ob(chainSeries)],
      [{ label: 'm', scale: 'm', size: 50 }, { label: 'm/s', scale: 'mps', side: 1, size: 50, grid: { show: false } }],
      this.view, sync);
    const unit = this.data.energySeries().unit;
    this.plots.energy = makePlot(this.el, `energy per module (${unit})`,
      (sc.modules ?? []).map((mm, k) => ({ label: `m${mm.index}`, stroke: PALETTE[k % PALETTE.length], width: 1 })),
      [{ label: unit, size: 50 }], this.view, sync);
    this.energyUnit = unit;
    this.builtFor = sc;
    this.resize();
    this.update(true);
  }

  resize() {
    const w = Math.max(200, this.el.clientWidth - 12);
    for (const p of Object.values(this.plots)) p.u.setSize({ width: w, height: 170 });
  }

  // new data: set every plot's series
  update() {
    const d = this.data;
    if (!d.scene) return;
    if (this.builtFor !== d.scene) { if (this.bar) this.controls(this.bar); this.rebuild(); return; }
    const t = d.t;
    const col = (name) => d.column(name) ?? new Float64Array(t.length);
    const mi = this.module, sj = this.joint;
    const m = d.scene.modules?.[mi];
    const p = this.plots;
    const b = this.other?.data;
    const colB = (name) => resample(b, b.column(name), t);
    p.servo.u.setData([t, col(`m${mi}.s${sj}.setpoint_deg`), col(`m${mi}.s${sj}.angle_deg`),
      ...(b ? [colB(`m${mi}.s${sj}.setpoint_deg`), colB(`m${mi}.s${sj}.angle_deg`)] : [])]);
    p.current.u.setData([t, ...(m?.servos ?? []).map((_, j) => col(`m${mi}.s${j}.current_a`)), col(`m${mi}.supply_a`)]);
    if (p.sensors) p.sensors.u.setData([t, ...this.channels.map((c) => col(c))]);
    const o = d.orientationSeries();
    const ob = b ? b.orientationSeries() : null;
    p.orientation.u.setData([t, o.heading, o.pitch, o.roll,
      ...(ob ? [resample(b, ob.heading, t), resample(b, ob.pitch, t), resample(b, ob.roll, t)] : [])]);
    const { dist, speed } = d.chainSeries();
    const cb = b ? b.chainSeries() : null;
    p.chain.u.setData([t, dist, speed, ...(cb ? [resample(b, cb.dist, t), resample(b, cb.speed, t)] : [])]);
    const e = d.energySeries();
    if (e.unit !== this.energyUnit) { this.rebuild(); return; }
    p.energy.u.setData([t, ...e.series]);
  }

  // the replay time moved: redraw the time markers only
  redrawMarkers() {
    for (const p of Object.values(this.plots)) p.u.redraw(false, false);
  }
}
