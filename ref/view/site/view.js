// dynref view: browse runs written by `dynref view RUN... --out DIR` (ref/view/README.md).
// Data arrive as <script> files calling VIEW.runs / VIEW.summary / VIEW.frame, so the page
// works from file:// without a server. Records are the canonical flat view of ref/trace: the
// history of an entity lists the same records as `dynref trace feature`.
'use strict';

const S = { runs: [], run: 0, summary: {}, frames: {}, frameIndex: 0, entity: '', scripts: {}, shapes: { features: [], lines: [] } };
const CARRIER = (stage) => stage === 'structure' || stage.startsWith('match.');
const STAGE_COLOURS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f',
  '#bcbd22', '#17becf', '#393b79', '#637939', '#8c6d31', '#843c39', '#7b4173'];
const $ = (id) => document.getElementById(id);

const VIEW = {
  runs(list) { S.runs = list; start(); },
  summary(k, s) { S.summary[k] = s; },
  frame(k, f, d) { (S.frames[k] = S.frames[k] || {})[f] = d; },
};

function loadScript(src) {
  if (!S.scripts[src]) {
    S.scripts[src] = new Promise((resolve, reject) => {
      const el = document.createElement('script');
      el.src = src;
      el.onload = () => resolve();
      el.onerror = () => reject(new Error('cannot load ' + src));
      document.body.appendChild(el);
    });
  }
  return S.scripts[src];
}
async function summaryOf(k) { await loadScript(`data/r${k}/summary.js`); return S.summary[k]; }
async function frameOf(k, f) {
  await loadScript(`data/r${k}/f${f}.js`);
  return S.frames[k][f];
}

// A stored row [schema, entity, occurrence, values...] as a record.
function decode(summary, row) {
  const [type, stage, kind, names] = summary.schemas[row[0]];
  const fields = names.map((n, i) => [n, row[3 + i]]);
  return { type, stage, kind, entity: row[1], occurrence: row[2], fields };
}
function field(rec, name) {
  const f = rec.fields.find((x) => x[0] === name);
  return f === undefined ? undefined : f[1];
}
const matches = (entity, wanted) => entity === wanted || entity.startsWith(wanted + '@');
const baseId = (entity) => entity.split('@')[0];
const perFrame = (id) => /^(f|i|l|pl|r)\d+\.\d+$/.test(id);
const frameOfId = (id) => Number(id.replace(/^[a-z]+/, '').split('.')[0]);

// The records `dynref trace feature RUN ID` lists (README "Feature history").
async function plainHistory(k, id) {
  const summary = await summaryOf(k);
  const frames = perFrame(id) ? [frameOfId(id)] : (summary.links[id] || []);
  const m = /^(mp|ml|mpl)(\d+)$/.exec(id);
  const rows = [];
  for (const f of frames) {
    const data = await frameOf(k, f);
    if (!data) continue;
    const recs = data.records.map((r) => decode(summary, r));
    const related = new Set();
    if (m && m[1] === 'mp') {
      for (const r of recs) {
        if (r.type !== 'obs') continue;
        const assoc = field(r, 'associated_map_point_id');
        if (String(assoc !== undefined ? assoc : field(r, 'map_point_id')) === m[2]) related.add(r.entity);
      }
    } else if (m) {
      const input = m[1] === 'ml' ? 'in.map_line' : 'in.map_plane';
      for (const r of recs) if (field(r, input) === Number(m[2])) related.add(r.entity);
    }
    for (const r of recs) {
      let take = matches(r.entity, id);
      for (const x of related) take = take || matches(r.entity, x);
      if (take) rows.push({ frame: f, ...r });
    }
  }
  return { id, rows };
}

function formatValue(v) { return typeof v === 'number' ? String(v) : v; }
function fieldText(rec) { return rec.fields.map(([n, v]) => `${n}=${formatValue(v)}`).join(' '); }

function stageColour(stage, stages) {
  if (!stages.has(stage)) stages.set(stage, STAGE_COLOURS[stages.size % STAGE_COLOURS.length]);
  return stages.get(stage);
}

function svg(tag, attrs, parent) {
  const el = document.createElementNS('http://www.w3.org/2000/svg', tag);
  for (const [a, v] of Object.entries(attrs)) el.setAttribute(a, v);
  if (parent) parent.appendChild(el);
  return el;
}

// P(dynamic) after every update vs frame, jumps coloured by stage, decisions under the axis.
function drawPlot(history) {
  const plot = $('plot');
  plot.innerHTML = '';
  const W = 640, H = 220, L = 40, R = 150, T = 10, B = 40;
  const probs = history.rows.filter((r) => r.type === 'prob' && !CARRIER(r.stage));
  const decisions = history.rows.filter((r) => r.type === 'decision');
  const all = history.rows.map((r) => r.frame);
  if (all.length === 0) return;
  const f0 = Math.min(...all), f1 = Math.max(...all) + 1;
  const x = (f) => L + ((f - f0) / Math.max(1, f1 - f0)) * (W - L - R);
  const y = (p) => T + (1 - p) * (H - T - B);
  svg('line', { x1: L, y1: y(0), x2: W - R, y2: y(0), stroke: '#999' }, plot);
  svg('line', { x1: L, y1: y(0), x2: L, y2: y(1), stroke: '#999' }, plot);
  for (const p of [0, 0.5, 1]) svg('text', { x: 4, y: y(p) + 4, 'font-size': 10 }, plot).textContent = p;
  svg('text', { x: L, y: H - 4, 'font-size': 10 }, plot).textContent = `frame ${f0}`;
  svg('text', { x: W - R - 40, y: H - 4, 'font-size': 10 }, plot).textContent = `frame ${f1 - 1}`;
  const stages = new Map();
  const perFrameCount = {};
  for (const r of probs) perFrameCount[r.frame] = (perFrameCount[r.frame] || 0) + 1;
  const seen = {};
  for (const r of probs) {
    const i = (seen[r.frame] = (seen[r.frame] || 0) + 1) - 1;
    const xf = x(r.frame + (0.8 * i) / perFrameCount[r.frame]);
    const before = field(r, 'before'), after = field(r, 'after');
    const colour = stageColour(r.stage, stages);
    if (typeof before === 'number' && typeof after === 'number') {
      svg('line', { x1: xf, y1: y(before), x2: xf, y2: y(after), stroke: colour, 'stroke-width': 2 }, plot);
      svg('circle', { cx: xf, cy: y(after), r: 2.5, fill: colour }, plot).appendChild(
        svg('title', {})).textContent = `${r.entity} frame ${r.frame} ${r.stage}: ${before} -> ${after}`;
    }
  }
  for (const d of decisions) {
    const kept = field(d, 'kept') === '1';
    const xd = x(d.frame + 0.4), yd = H - B + 12;
    const mark = kept ? svg('path', { d: `M${xd - 4},${yd + 4}L${xd + 4},${yd + 4}L${xd},${yd - 4}Z`, fill: '#2a2' }, plot)
      : svg('path', { d: `M${xd - 4},${yd - 4}L${xd + 4},${yd + 4}M${xd - 4},${yd + 4}L${xd + 4},${yd - 4}`, stroke: '#d22', 'stroke-width': 2 }, plot);
    svg('title', {}, mark).textContent = `${d.entity} frame ${d.frame} ${d.stage}: ${kept ? 'kept' : 'rejected'} (${field(d, 'reason')})`;
  }
  let ly = T + 8;
  for (const [stage, colour] of stages) {
    svg('rect', { x: W - R + 8, y: ly - 8, width: 10, height: 10, fill: colour }, plot);
    svg('text', { x: W - R + 22, y: ly + 1, 'font-size': 10 }, plot).textContent = stage;
    ly += 13;
  }
}

function divergenceOf(k) {
  const s = S.summary[k];
  return s && s.divergence && s.divergence.frame !== undefined ? s.divergence : null;
}

function renderHistory(history) {
  const rejected = history.rows.filter((r) => r.type === 'decision' && field(r, 'kept') === '0').length;
  const frames = new Set(history.rows.map((r) => r.frame));
  $('history-title').textContent = `${history.id}: ` +
    `${history.rows.length} records over ${frames.size} frames, ${rejected} rejections`;
  drawPlot(history);
  const div = divergenceOf(S.run);
  const table = document.createElement('table');
  table.innerHTML = '<tr><th>frame</th><th>type</th><th>stage</th><th>entity</th><th>before &rarr; after</th><th>fields</th></tr>';
  for (const r of history.rows) {
    const tr = document.createElement('tr');
    if (r.type === 'decision') tr.className = field(r, 'kept') === '1' ? 'decision-kept' : 'decision-rejected';
    if (div && div.frame === r.frame && div.entity === r.entity && div.stage === r.stage) tr.classList.add('diverges');
    const ba = r.type === 'prob' ? `${formatValue(field(r, 'before'))} &rarr; ${formatValue(field(r, 'after'))}`
      : r.type === 'residual' ? `w ${formatValue(field(r, 'weight'))}, chi2 ${formatValue(field(r, 'chi2'))}` : '';
    tr.innerHTML = `<td>${r.frame}</td><td>${r.type}</td><td>${r.stage}</td><td>${r.entity}</td><td>${ba}</td>` +
      `<td class="fields"></td>`;
    tr.lastChild.textContent = fieldText(r);
    tr.onclick = () => showFrame(S.summary[S.run].frames.indexOf(r.frame));
    table.appendChild(tr);
  }
  $('history').innerHTML = '';
  $('history').appendChild(table);
  const other = $('other-run');
  other.innerHTML = '';
  S.runs.forEach((run, k) => {
    if (k === S.run) return;
    const b = document.createElement('button');
    b.textContent = `same entity in ${run.label}`;
    b.onclick = () => selectRun(k).then(() => showEntity(history.id));
    other.appendChild(b);
  });
}

async function showEntity(id) {
  $('entity').value = id;
  S.entity = id;
  const history = await plainHistory(S.run, id);
  renderHistory(history);
  const params = new URLSearchParams(location.search);
  if (params.get('selftest') === '1') {
    const out = history.rows.map((r) => [r.frame, r.type, r.stage, r.kind, r.entity, r.occurrence,
      Object.fromEntries(r.fields)]);
    $('selftest').textContent = JSON.stringify({ entity: id, rows: out });
    document.title = 'selftest-done';
  }
  return history;
}

// The frame's features (OBS u, v) and line segments, for clicks on the image.
function frameShapes(summary, data) {
  const features = [], lines = [];
  for (const row of data.records) {
    const r = decode(summary, row);
    if (r.type === 'obs') features.push({ entity: r.entity, u: field(r, 'u'), v: field(r, 'v') });
    if (r.type === 'prob' && r.kind === 'line_sample' && field(r, 'in.x0') !== undefined)
      lines.push({ entity: r.entity, x0: field(r, 'in.x0'), y0: field(r, 'in.y0'), x1: field(r, 'in.x1'), y1: field(r, 'in.y1') });
  }
  return { features, lines };
}

function segmentDistance(px, py, l) {
  const dx = l.x1 - l.x0, dy = l.y1 - l.y0, n = dx * dx + dy * dy;
  const t = n > 0 ? Math.max(0, Math.min(1, ((px - l.x0) * dx + (py - l.y0) * dy) / n)) : 0;
  return Math.hypot(px - (l.x0 + t * dx), py - (l.y0 + t * dy));
}

// The feature (or line) nearest to image pixel (px, py) within `radius` px of the current frame.
function pickAt(px, py, radius) {
  let best = null, bestD = radius;
  for (const f of S.shapes.features) {
    const d = Math.hypot(f.u - px, f.v - py);
    if (d < bestD) bestD = d, best = f.entity;
  }
  for (const l of S.shapes.lines) {
    const d = segmentDistance(px, py, l);
    if (d < bestD) bestD = d, best = l.entity;
  }
  return best;
}

function listFrameEntities(summary, data) {
  const box = $('frame-entities');
  box.innerHTML = '';
  const groups = { 'instance masks': new Set(), 'rejected features': new Set(), lines: new Set(), planes: new Set() };
  for (const row of data.records) {
    const r = decode(summary, row);
    if (/^i\d+\.\d+$/.test(r.entity)) groups['instance masks'].add(r.entity);
    if (r.type === 'decision' && /^f\d+\.\d+$/.test(r.entity) && field(r, 'kept') === '0') groups['rejected features'].add(r.entity);
    if (/^l\d+\.\d+$/.test(r.entity)) groups.lines.add(r.entity);
    if (/^pl\d+\.\d+$/.test(r.entity)) groups.planes.add(r.entity);
  }
  for (const [name, set] of Object.entries(groups)) {
    if (set.size === 0) continue;
    const p = document.createElement('div');
    p.innerHTML = `<b>${name} (${set.size})</b>: `;
    [...set].slice(0, 300).forEach((id) => {
      const a = document.createElement('a');
      a.href = '#';
      a.textContent = id;
      a.onclick = (e) => { e.preventDefault(); showEntity(id); };
      p.appendChild(a);
    });
    box.appendChild(p);
  }
}

async function showFrame(index) {
  const summary = await summaryOf(S.run);
  if (index < 0 || index >= summary.frames.length) return;
  S.frameIndex = index;
  const frame = summary.frames[index];
  $('slider').value = index;
  $('frame-number').value = frame;
  const data = await frameOf(S.run, frame);
  const counts = {};
  for (const row of data.records) {
    const r = decode(summary, row);
    counts[r.type] = (counts[r.type] || 0) + 1;
  }
  $('frame-info').textContent = `stamp ${data.stamp} | ` + Object.entries(counts).map(([t, n]) => `${t} ${n}`).join(', ');
  const img = $('overlay');
  const shapes = frameShapes(summary, data);
  img.onload = () => {
    const c = $('hits');
    c.width = img.clientWidth;
    c.height = img.clientHeight;
    c.onclick = (e) => {
      const sx = img.naturalWidth / img.clientWidth, sy = img.naturalHeight / img.clientHeight;
      const best = pickAt(e.offsetX * sx, e.offsetY * sy, 10 * sx);
      if (best) showEntity(best);
    };
  };
  S.shapes = shapes;
  img.src = data.image || '';
  listFrameEntities(summary, data);
}

function polyline(points, colour, parent) {
  svg('polyline', { points: points.map((p) => p.join(',')).join(' '), fill: 'none', stroke: colour, 'stroke-width': 1.5 }, parent);
}

// Top view of ground truth and estimate (the two axes of largest ground-truth extent) and ATE over time.
function drawTrajectory(t, parent) {
  if (!t || !t.gt) {
    parent.insertAdjacentHTML('beforeend', `<p class="muted">no trajectory against ground truth${t && t.error ? ': ' + t.error : ''}</p>`);
    return;
  }
  const ext = [0, 1, 2].map((a) => Math.max(...t.gt.map((p) => p[a])) - Math.min(...t.gt.map((p) => p[a])));
  const axes = [0, 1, 2].sort((a, b) => ext[b] - ext[a]).slice(0, 2).sort();
  const pts = t.gt.concat(t.est);
  const lo = axes.map((a) => Math.min(...pts.map((p) => p[a]))), hi = axes.map((a) => Math.max(...pts.map((p) => p[a])));
  const span = Math.max(hi[0] - lo[0], hi[1] - lo[1], 1e-6);
  const top = svg('svg', { width: 300, height: 300 }, parent);
  const map = (p) => [10 + ((p[axes[0]] - lo[0]) / span) * 280, 290 - ((p[axes[1]] - lo[1]) / span) * 280];
  polyline(t.gt.map(map), '#2a2', top);
  polyline(t.est.map(map), '#d22', top);
  svg('text', { x: 8, y: 14, 'font-size': 11 }, top).textContent = `top view (axes ${'xyz'[axes[0]]}${'xyz'[axes[1]]}): GT green, estimate red`;
  const ate = svg('svg', { width: 420, height: 300 }, parent);
  const e = t.ate;
  const emax = Math.max(...e.map((p) => p[1]), 1e-9), t0 = e[0][0], t1 = e[e.length - 1][0];
  polyline(e.map((p) => [40 + ((p[0] - t0) / Math.max(t1 - t0, 1e-9)) * 370, 280 - (p[1] / emax) * 260]), '#36c', ate);
  svg('text', { x: 8, y: 14, 'font-size': 11 }, ate).textContent = `ATE over time: RMSE ${(1000 * t.rmse_m).toFixed(1)} mm, max ${(1000 * emax).toFixed(1)} mm`;
}

function renderSummary(summary) {
  const box = $('summary');
  box.innerHTML = '';
  const run = summary.run || {};
  const h = summary.header || {};
  box.insertAdjacentHTML('beforeend', `<h2>${summary.label}: method ${h.method || run.method || '?'}, end state ${summary.end_state}</h2>` +
    `<p class="muted">${summary.run_dir} | sequence ${h.sequence_path || ''} | detector ${h.detector_source || ''} | commit ${h.dynref_commit || ''}</p>`);
  drawTrajectory(summary.trajectory, box);
  const timing = run.timing || {};
  const rows = Object.entries(timing).filter(([, v]) => v && v.mean_ms_per_frame !== undefined)
    .map(([k, v]) => `<tr><td>${k}</td><td>${v.mean_ms_per_frame.toFixed(2)}</td></tr>`).join('');
  const stages = Object.entries(run.timing_stages || {}).map(([k, v]) => `<tr><td>stage ${k}</td><td>${Number(v).toFixed(2)}</td></tr>`).join('');
  box.insertAdjacentHTML('beforeend', `<h3>ms per frame</h3><table><tr><th>module</th><th>mean ms/frame</th></tr>${rows}${stages}</table>`);
  const counts = Object.entries(summary.counts).map(([name, series]) => {
    const v = series.map((p) => p[1]);
    const sum = v.reduce((a, b) => a + b, 0);
    return `<tr><td>${name}</td><td>${v.length}</td><td>${sum}</td><td>${(sum / v.length).toFixed(2)}</td><td>${Math.max(...v)}</td></tr>`;
  }).join('');
  box.insertAdjacentHTML('beforeend', `<h3>per-stage counts</h3><table><tr><th>stage.counter</th><th>frames</th><th>sum</th><th>mean</th><th>max</th></tr>${counts}</table>`);
  const facts = ['frames', 'tracked', 'lost', 'keyframes', 'map_points'].filter((k) => run[k] !== undefined)
    .map((k) => `${k} ${JSON.stringify(run[k])}`).join(', ');
  if (facts) box.insertAdjacentHTML('beforeend', `<p>run.json: ${facts}</p>`);
}

async function selectRun(k) {
  S.run = k;
  document.querySelectorAll('#runs button').forEach((b, i) => b.classList.toggle('active', i === k));
  const summary = await summaryOf(k);
  $('slider').max = Math.max(0, summary.frames.length - 1);
  renderSummary(summary);
  const div = divergenceOf(k);
  const banner = $('divergence');
  banner.hidden = !div;
  if (div) {
    banner.textContent = `first divergence from ${S.runs[0].label}: ${div.text} (click to open)`;
    banner.onclick = () => showFrame(summary.frames.indexOf(div.frame)).then(() => showEntity(baseId(div.entity)));
  }
  await showFrame(Math.min(S.frameIndex, summary.frames.length - 1));
}

async function start() {
  const bar = $('runs');
  S.runs.forEach((run, k) => {
    const b = document.createElement('button');
    b.textContent = run.label;
    b.onclick = () => selectRun(k);
    bar.appendChild(b);
  });
  $('slider').oninput = (e) => showFrame(Number(e.target.value));
  $('prev').onclick = () => showFrame(S.frameIndex - 1);
  $('next').onclick = () => showFrame(S.frameIndex + 1);
  $('frame-number').onchange = async (e) => showFrame((await summaryOf(S.run)).frames.indexOf(Number(e.target.value)));
  $('show').onclick = () => showEntity($('entity').value.trim());
  $('entity').onkeydown = (e) => { if (e.key === 'Enter') showEntity($('entity').value.trim()); };
  document.onkeydown = (e) => {
    if (e.target.tagName === 'INPUT') return;
    if (e.key === 'ArrowLeft') showFrame(S.frameIndex - 1);
    if (e.key === 'ArrowRight') showFrame(S.frameIndex + 1);
  };
  const params = new URLSearchParams(location.search);
  await selectRun(Number(params.get('run') || 0));
  if (params.has('frame')) {
    const summary = await summaryOf(S.run);
    await showFrame(summary.frames.indexOf(Number(params.get('frame'))));
  }
  if (params.has('entity')) await showEntity(params.get('entity'));
  if (params.has('click')) {  // click=u,v: what a click at that image pixel does (tests, links)
    const [u, v] = params.get('click').split(',').map(Number);
    const best = pickAt(u, v, 10);
    if (best) await showEntity(best);
  }
}
