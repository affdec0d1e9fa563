// Two runs of a scene compared (`chainsim view A B`): the table of their
// summaries' differences, the modules' log lines that differ, and where the
// two first differ: the channel-by-channel comparison chainsim made
// (boot.report, run_compare.h) and the first trace row that is not the same.

const num = (v, digits = 4) =>
  typeof v !== 'number' || !Number.isFinite(v) ? '\u2013' : Number.isInteger(v) ? String(v) : v.toFixed(digits);

function energy(summary) {
  const m = summary?.modules ?? [];
  return m.length ? m.reduce((s, x) => s + (x.energy_j ?? 0), 0) : undefined;
}

function faults(summary) {
  const f = (summary?.modules ?? []).filter((m) => m.fault).map((m) => `m${m.index}: ${m.fault}`);
  if (summary?.stopped_by) f.push(`stopped by ${summary.stopped_by}`);
  return f.length ? f.join('; ') : 'none';
}

// log lines (text only, times aside) of one run, per endpoint: "E text"
function logTexts(boot) {
  const out = [];
  for (const l of boot.logs ?? [])
    for (const line of (l.text ?? '').split('\n')) {
      const m = /^\d+\.\d+ (.*)$/.exec(line);
      if (m) out.push(`[${l.endpoint}] ${m[1]}`);
    }
  return out;
}

// the lines of a that b lacks (as multisets), in a's order
function missing(a, b) {
  const count = new Map();
  for (const x of b) count.set(x, (count.get(x) ?? 0) + 1);
  const out = [];
  for (const x of a) {
    const n = count.get(x) ?? 0;
    if (n > 0) count.set(x, n - 1);
    else out.push(x);
  }
  return out;
}

// the first row at which a column both traces have differs: {t, column, a, b};
// {none: why} when there is nothing to compare; null when they agree over
// the rows both have
export function firstTraceDifference(da, db) {
  const n = Math.min(da.rows, db.rows);
  const common = da.header.filter((h) => db.index.has(h) && h !== 't_s');
  if (!n) return { none: 'a trace has no rows' };
  if (!common.length) return { none: 'the traces have no column in common (other chains)' };
  const ca = common.map((h) => da.col[da.index.get(h)].a), cb = common.map((h) => db.col[db.index.get(h)].a);
  for (let r = 0; r < n; r++)
    for (let k = 0; k < common.length; k++)
      if (ca[k][r] !== cb[k][r] && !(Number.isNaN(ca[k][r]) && Number.isNaN(cb[k][r])))
        return { t: da.col[0].a[r], row: r, column: common[k], a: ca[k][r], b: cb[k][r] };
  return null;
}

// the comparison as plain data (for the table and the tests)
export function compareRuns(boot, da, db) {
  const [la, lb] = boot.labels;
  const sa = boot.a.summary, sb = boot.b.summary;
  const rows = [
    ['simulated (s)', sa?.sim_time_s, sb?.sim_time_s],
    ['exit code', sa?.exit_code, sb?.exit_code],
    ['distance (m)', sa?.chain?.distance_m, sb?.chain?.distance_m],
    ['speed (m/s)', sa?.chain?.speed_m_s, sb?.chain?.speed_m_s],
    ['energy (J)', energy(sa), energy(sb)],
    ['faults', faults(sa), faults(sb)],
  ];
  const la_ = logTexts(boot.a), lb_ = logTexts(boot.b);
  const onlyA = missing(la_, lb_), onlyB = missing(lb_, la_);
  rows.push(['log lines', la_.length, lb_.length]);
  return {
    labels: [la, lb],
    rows,
    logOnlyA: onlyA,
    logOnlyB: onlyB,
    trace: firstTraceDifference(da, db),
    first: boot.report?.first ?? null,
    drift: boot.report?.drift ?? null,
  };
}

export function buildCompareTable(el, c) {
  const box = document.createElement('div');
  box.className = 'cs-compare';
  const table = document.createElement('table');
  const tr = (cells, head = false) => {
    const r = document.createElement('tr');
    for (const c of cells) {
      const d = document.createElement(head ? 'th' : 'td');
      d.textContent = c;
      r.append(d);
    }
    table.append(r);
  };
  tr(['', `A: ${c.labels[0]}`, `B: ${c.labels[1]}`, 'B \u2212 A'], true);
  for (const [name, a, b] of c.rows) {
    const both = typeof a === 'number' && typeof b === 'number';
    tr([name, typeof a === 'number' ? num(a) : String(a ?? '\u2013'), typeof b === 'number' ? num(b) : String(b ?? '\u2013'),
      both ? num(b - a) : a === b ? 'same' : 'differ']);
  }
  box.append(table);
  const line = (cls, text) => {
    const p = document.createElement('div');
    p.className = cls;
    p.textContent = text;
    box.append(p);
  };
  line('cs-cmp-logs', `log lines only in A: ${c.logOnlyA.length}, only in B: ${c.logOnlyB.length}` +
    (c.logOnlyA.length ? ` | first only in A: ${c.logOnlyA[0]}` : '') +
    (c.logOnlyB.length ? ` | first only in B: ${c.logOnlyB[0]}` : ''));
  line('cs-cmp-trace', c.trace?.none ? `traces: not compared: ${c.trace.none}` : c.trace
    ? `traces first differ at t=${c.trace.t.toFixed(3)} s (${c.trace.column}: ${c.trace.a} vs ${c.trace.b})`
    : 'traces: the same over the rows both have');
  if (c.first)
    line('cs-cmp-first', `first divergence: t=${num(c.first.t_a_s, 3)} / ${num(c.first.t_b_s, 3)} s, ${c.first.who}, ` +
      `${c.first.channel}: ${c.first.a} vs ${c.first.b}`);
  else if (c.drift)
    line('cs-cmp-first', 'no divergence on any channel (logs, I2C, Sout, set-points, faults, addresses)');
  if (c.drift)
    line('cs-cmp-drift', `heads apart: ${num(c.drift.head_apart_max_m)} m at most (t=${num(c.drift.head_apart_max_at_s, 2)} s), ` +
      `servo angles ${num(c.drift.angle_rms_deg, 2)} deg rms`);
  el.prepend(box);
  return box;
}
