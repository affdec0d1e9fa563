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
