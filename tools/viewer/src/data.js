// The data of a run, as the viewer holds it: scene.json, the trace as columns
// (growing while a live run streams in), the bus log as events, summary.json,
// and the series derived from them (chain centre of mass, distance, speed,
// energy per module).

// a growable column of doubles
class Column {
  constructor(cap = 1024) {
    this.a = new Float64Array(cap);
    this.n = 0;
  }
  push(v) {
    if (this.n === this.a.length) {
      const b = new Float64Array(this.a.length * 2);
      b.set(this.a);
      this.a = b;
    }
    this.a[this.n++] = v;
  }
  view() {
    return this.a.subarray(0, this.n);
  }
}

const BUS_KINDS = ['i2c', 'sync', 'addr', 'touch', 'fault', 'log'];

// one bus.log line "<t_us> <kind> ..." as an event; a module's log line
// comes as "<t_us> log endpoint=E <text>" (the live view sends them so; a
// replay makes them from modules/NN-TYPE.log, logLines)
export function parseBusLine(line) {
  const m = /^(\d+)\s+(\S+)\s*(.*)$/.exec(line.trim());
  if (!m) return null;
  const log = m[2] === 'log' && /^endpoint=(\d+) ?(.*)$/.exec(m[3]);
  if (log) {
    const t = Number(m[1]) / 1e6;
    return { t, kind: 'log', text: log[2], line: `${t.toFixed(6)} [${log[1]}] ${log[2]}`, module: Number(log[1]), fields: {} };
  }
  const ev = { t: Number(m[1]) / 1e6, kind: m[2], text: m[3], line: line.trim(), module: -1 };
  const fields = {};
  for (const kv of ev.text.matchAll(/(\w+)=(\S+)/g)) fields[kv[1]] = kv[2];
  ev.fields = fields;
  if (ev.kind === 'fault') {
    const mm = /\bmodule (\d+)/.exec(ev.text);
    ev.module = mm ? Number(mm[1]) : -1;  // -1: the central control or unknown
  } else if ('endpoint' in fields) {
    ev.module = Number(fields.endpoint);
  } else if ('from' in fields) {
    ev.module = Number(fields.from);
  }
  if (ev.kind === 'touch') ev.level = Number(fields.level ?? 1);
  if (!BUS_KINDS.includes(ev.kind)) ev.kind = 'other';
  return ev;
}

// a module's log file ("<t_s> <text>" lines) as "<t_us> log endpoint=E <text>" lines
export function logLines(endpoint, text) {
  let out = '';
  for (const line of text.split('\n')) {
    const m = /^(\d+)\.(\d{6}) (.*)$/.exec(line);
    if (m) out += `${Number(m[1]) * 1e6 + Number(m[2])} log endpoint=${endpoint} ${m[3]}\n`;
  }
  return out;
}

export class RunData {
  constructor() {
    this.scene = null;
    this.summary = null;
    this.header = [];
    this.col = [];          // Column per trace column
    this.index = new Map(); // column name -> index
    this.events = [];       // bus events in time order
    this.marks = [];        // the fault and touch events among them
    this.partial = '';      // an incomplete trailing CSV line (live)
    this.version = 0;       // bumps on every change
    this.massIdx = [];      // [{mass, x, y, z}] column indices for the centre of mass
    this.com = [new Column(), new Column(), new Column()];
  }

  setScene(scene, headerLine) {
    this.scene = scene;
    this.header = headerLine.trim().split(',');
    this.col = this.header.map(() => new Column());
    this.header.forEach((h, i) => this.index.set(h, i));
    this.massIdx = [];
    for (const m of scene.modules ?? [])
      for (const b of m.bodies) {
        const p = `m${m.index}.${b.name}.`;
        if (this.index.has(p + 'x'))
          this.massIdx.push({ mass: b.mass_kg, x: this.index.get(p + 'x'), y: this.index.get(p + 'y'), z: this.index.get(p + 'z') });
      }
    this.version++;
  }

  // CSV text of whole lines (a trailing partial line is kept for the next call)
  addRows(text) {
    text = this.partial + text;
    const end = text.lastIndexOf('\n');
    this.partial = end < 0 ? text : text.slice(end + 1);
    if (end < 0) return;
    const nc = this.header.length;
    for (const line of text.slice(0, end).split('\n')) {
      if (!line || line.startsWith('t_s')) continue;
      const f = line.split(',');
      if (f.length < nc) continue;
      for (let i = 0; i < nc; i++) this.col[i].push(parseFloat(f[i]));
      this.pushCom(this.col[0].n - 1);
    }
    this.version++;
  }

  pushCom(r) {
    let mx = 0, my = 0, mz = 0, ms = 0;
    for (const b of this.massIdx) {
      mx += b.mass * this.col[b.x].a[r];
      my += b.mass * this.col[b.y].a[r];
      mz += b.mass * this.col[b.z].a[r];
      ms += b.mass;
    }
    if (ms === 0) ms = 1;
    this.com[0].push(mx / ms);
    this.com[1].push(my / ms);
    this.com[2].push(mz / ms);
  }

  addBus(text) {
    for (const line of text.split('\n')) {
      const ev = line.trim() && parseBusLine(line);
      if (ev) this.events.push(ev);
    }
    this.events.sort((a, b) => a.t - b.t);
    this.marks = this.events.filter((e) => e.kind === 'fault' || e.kind === 'touch');
    this.version++;
  }

  setSummary(s) {
    this.summary = s;
    this.version++;
  }

  get rows() {
    return this.col.length ? this.col[0].n : 0;
  }
  get t() {
    return this.col.length ? this.col[0].view() : new Float64Array(0);
  }
  get duration() {
    const n = this.rows;
    return n ? this.col[0].a[n - 1] : 0;
  }
  column(name) {
    const i = this.index.get(name);
    return i === undefined ? null : this.col[i].view();
  }

  // index of the last row at or before time t (0 when before the first)
  rowAt(t) {
    const a = this.col[0].a;
    let lo = 0, hi = this.rows - 1;
    if (hi < 0) return -1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (a[mid] <= t) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }

  // {i, j, f}: rows around t and the fraction between them
  bracket(t) {
    const i = this.rowAt(t);
    if (i < 0) return null;
    const j = Math.min(i + 1, this.rows - 1);
    const a = this.col[0].a;
    const f = j > i && a[j] > a[i] ? Math.min(1, Math.max(0, (t - a[i]) / (a[j] - a[i]))) : 0;
    return { i, j, f };
  }

  comAt(r) {
    return [this.com[0].a[r], this.com[1].a[r], this.com[2].a[r]];
  }

  // distance of the centre of mass from its start (m) and its horizontal speed
  // (m/s, central difference over +-window/2)
  chainSeries(window = 0.5) {
    const n = this.rows, t = this.t;
    const [x, y, z] = this.com.map((c) => c.view());
    const dist = new Float64Array(n), speed = new Float64Array(n);
    let lo = 0, hi = 0;
    for (let r = 0; r < n; r++) {
      dist[r] = Math.hypot(x[r] - x[0], y[r] - y[0], z[r] - z[0]);
      while (t[lo] < t[r] - window / 2) lo++;
      while (hi < n - 1 && t[hi + 1] <= t[r] + window / 2) hi++;
      const dt = t[hi] - t[lo];
      speed[r] = dt > 0 ? Math.hypot(x[hi] - x[lo], y[hi] - y[lo]) / dt : 0;
    }
    return { dist, speed };
  }

  // the chain's heading, pitch and roll per row, degrees: heading (from +x,
  // counter-clockwise) and pitch (up positive) of the line from the last
  // module to the first; roll of the modules' mean up (their frames' z,
  // scene.json's `up` of each body) about that line: 0 upright, about +-90
  // on its side, 180 upside down
  orientationSeries() {
    const n = this.rows, mods = this.scene?.modules ?? [];
    const heading = new Float64Array(n), pitch = new Float64Array(n), roll = new Float64Array(n);
    const ups = [];
    const cols = mods.map((m) => {
      const p = `m${m.index}.${m.bodies?.[0]?.name}.`;
      const idx = ['x', 'y', 'z', 'qw', 'qx', 'qy', 'qz'].map((s) => this.index.get(p + s));
      if (!idx.every((v) => v !== undefined)) return null;
      ups.push(m.bodies[0].up ?? null);
      return idx.map((k) => this.col[k].a);
    }).filter((c) => c);
    if (!cols.length || !n) return { heading, pitch, roll };
    // v rotated by the quaternion (w, x, y, z)
    const rot = (w, x, y, z, v) => {
      const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
      return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
    };
    const unit = (v) => { const l = Math.hypot(...v) || 1; return v.map((c) => c / l); };
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const meanQ = (r) => {
      const q0 = cols[0];
      const s = [0, 0, 0, 0];
      for (const c of cols) {
        const sign = c[3][r] * q0[3][r] + c[4][r] * q0[4][r] + c[5][r] * q0[5][r] + c[6][r] * q0[6][r] < 0 ? -1 : 1;
        for (let k = 0; k < 4; k++) s[k] += sign * c[3 + k][r];
      }
      const l = Math.hypot(...s) || 1;
      return s.map((v) => v / l);
    };
    const axisAt = (r) => {
      const head = cols[0], tail = cols[cols.length - 1];
      const a = [head[0][r] - tail[0][r], head[1][r] - tail[1][r], head[2][r] - tail[2][r]];
      if (Math.hypot(...a) > 1e-9) return unit(a);
      const q = meanQ(r);  // one module: its body's x
      return unit(rot(q[0], q[1], q[2], q[3], [1, 0, 0]));
    };
    // without scene.json's up (an older run): the body axis that was up at the start
    const q0 = meanQ(0);
    const up0 = rot(q0[0], -q0[1], -q0[2], -q0[3], [0, 0, 1]);
    for (let r = 0; r < n; r++) {
      const a = axisAt(r);
      heading[r] = Math.atan2(a[1], a[0]) * 180 / Math.PI;
      pitch[r] = Math.asin(Math.max(-1, Math.min(1, a[2]))) * 180 / Math.PI;
      let u = [0, 0, 0];
      if (ups.every((v) => v)) {
        cols.forEach((c, k) => {
          const w = rot(c[3][r], c[4][r], c[5][r], c[6][r], ups[k]);
          for (let i = 0; i < 3; i++) u[i] += w[i];
        });
      } else {
        const q = meanQ(r);
        u = rot(q[0], q[1], q[2], q[3], up0);
      }
      const level = unit([-a[2] * a[0], -a[2] * a[1], 1 - a[2] * a[2]]);  // world up, square to the axis
      const now = unit(u.map((c, k) => c - dot(u, a) * a[k]));
      roll[r] = Math.atan2(dot(a, cross(level, now)), dot(level, now)) * 180 / Math.PI;
    }
    return { heading, pitch, roll };
  }

  // every sensor channel of module m in the trace: its columns other than the
  // bodies' poses, the servos' and the supply current (ADC counts of
  // pitch_current, accelerometer axes, wheel counters...)
  sensorColumns(m) {
    const prefix = `m${m}.`;
    return this.header.filter((h) => h.startsWith(prefix) &&
      !/\.(x|y|z|qw|qx|qy|qz)$/.test(h) && !/^m\d+\.s\d+\./.test(h) && h !== `${prefix}supply_a`);
  }

  // cumulative energy per module (J): the integral of its supply current times
  // the supply voltage. scene.json may give supply_v; otherwise the voltage is
  // the one that makes the integral end at summary.json's energy_j. Without
  // either (a live run still going) the charge in A*s is returned.
  energySeries() {
    const t = this.t, n = this.rows;
    const charge = (this.scene?.modules ?? []).map((m) => {
      const i = this.column(`m${m.index}.supply_a`);
      const q = new Float64Array(n);
      for (let r = 1; r < n && i; r++) q[r] = q[r - 1] + 0.5 * (i[r] + i[r - 1]) * (t[r] - t[r - 1]);
      return q;
    });
    let v = this.scene?.supply_v;
    // all modules share the supply: take the voltage from the module that used the most charge
    let best = -1;
    charge.forEach((q, k) => {
      if (n && q[n - 1] > 0 && (best < 0 || q[n - 1] > charge[best][n - 1])) best = k;
    });
    const e = best >= 0 ? this.summary?.modules?.[best]?.energy_j : undefined;
    if (!v && e !== undefined) v = e / charge[best][n - 1];
    if (v) for (const q of charge) for (let r = 0; r < n; r++) q[r] *= v;
    return { series: charge, unit: v ? 'J' : 'A*s' };
  }

  // index of the first event at or after time t (events.length when none)
  eventAt(t) {
    let lo = 0, hi = this.events.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.events[mid].t < t - 1e-9) lo = mid + 1;
      else hi = mid;
    }
    return lo;
  }
}
