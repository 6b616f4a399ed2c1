// dynref view: browse runs written by `dynref view RUN... --out DIR` (ref/view/README.md).
// Data arrive as <script> files calling VIEW.runs / summaryZ / chunkZ / linksZ, so the page
// works from file:// without a server. Records are the canonical flat view of ref/trace: the
// history of an entity lists the same records as `dynref trace feature`.
'use strict';

const S = { runs: [], run: 0, summary: {}, summaries: {}, packed: {}, links: {}, graphs: {}, frameIndex: 0, entity: '', scripts: {},
  cache: new Map(), showToken: 0, shapes: { features: [], lines: [] } };
const TABLE_ROWS = 3000;  // history rows shown in the table (renderHistory)
const CACHE_CHUNKS = 2;  // decoded data files (chunks of frames) kept: the page stays small on long runs
const CARRIER = (stage) => stage === 'structure' || stage.startsWith('match.');
const STAGE_COLOURS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f',
  '#bcbd22', '#17becf', '#393b79', '#637939', '#8c6d31', '#843c39', '#7b4173'];
const $ = (id) => document.getElementById(id);

const VIEW = {
  runs(list) { S.runs = list; start(); },
  summaryZ(k, packed) { S.packed[`summary/${k}`] = packed; },
  chunkZ(k, n, heads, packed) { S.packed[`${k}/c${n}`] = { heads, packed }; },
  linksZ(k, packed) { S.links[k] = packed; },
};

// Adds <script src> once (`keep`) or each time (frame files: their data are dropped once decoded).
// The data files are read as windows-1252: one character per byte of their packed strings.
function loadScript(src, keep = true) {
  if (keep && S.scripts[src]) return S.scripts[src];
  const p = new Promise((resolve, reject) => {
    const el = document.createElement('script');
    el.charset = 'windows-1252';
    el.src = src;
    el.onload = () => { if (!keep) el.remove(); resolve(); };
    el.onerror = () => reject(new Error('cannot load ' + src));
    document.body.appendChild(el);
  });
  if (keep) S.scripts[src] = p;
  return p;
}
function summaryOf(k) {
  if (!S.summaries[k]) {
    S.summaries[k] = (async () => {
      await loadScript(`data/r${k}/summary.js`);
      S.summary[k] = unlzma(S.packed[`summary/${k}`]);
      S.summary[k].indexOfFrame = new Map(S.summary[k].frames.map((f, i) => [f, i]));
      delete S.packed[`summary/${k}`];
      return S.summary[k];
    })();
  }
  return S.summaries[k];
}

// A packed data string (ref/view/packed.h LzmaLatin1: an LZMA stream, one windows-1252 character
// per byte) as JSON. BYTE_OF maps each character back to its byte, from the same decoder the
// browser read the file with.
const BYTE_OF = new Int16Array(65536).fill(-1);
{
  const cp1252 = new TextDecoder('windows-1252');
  for (let b = 0; b < 256; ++b) BYTE_OF[cp1252.decode(new Uint8Array([b])).charCodeAt(0)] = b;
}
function latin1Bytes(text) {
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; ++i) {
    const b = BYTE_OF[text.charCodeAt(i)];
    if (b < 0) throw new Error('invalid data character');
    bytes[i] = b;
  }
  return bytes;
}
// The decoder is lzma.js (the browser's DecompressionStream has no LZMA).
function unlzma(packed) {
  return JSON.parse(new TextDecoder().decode(lzmaDecode(latin1Bytes(packed))));
}
// Data files are decoded off the page's thread: LZMA in JavaScript runs at ~15 MB of JSON per
// second, so a long history (a map point seen in hundreds of frames: one data file per 30 frames,
// ~1 s each) would freeze the page for as long. DECODERS workers, made from a Blob of lzma.js's
// own function text (a worker script file cannot be loaded from file://), decode the files a
// history needs two at a time; the page only parses the JSON. Where a worker cannot be made, the
// page decodes itself (S.decoder says which; the selftest reports it).
const DECODERS = Math.max(1, Math.min(2, navigator.hardwareConcurrency || 1));
const decoders = { pool: null, next: 0, jobs: new Map(), id: 0 };
function decoderPool() {
  if (decoders.pool !== null) return decoders.pool;
  decoders.pool = [];
  try {
    const source = `'use strict';\nconst lzmaDecode = (${lzmaDecode.toString()});\n` +
      'onmessage = (e) => { try { const out = lzmaDecode(e.data.bytes);' +
      ' postMessage({ id: e.data.id, out }, [out.buffer]); }' +
      ' catch (err) { postMessage({ id: e.data.id, error: String(err) }); } };';
    const url = URL.createObjectURL(new Blob([source], { type: 'text/javascript' }));
    for (let i = 0; i < DECODERS; ++i) {
      const w = new Worker(url);
      // A worker that cannot run (a browser refusing Blob workers here): every file it holds and
      // every later one is decoded by the page.
      w.onerror = () => {
        decoders.pool = [];
        S.decoder = 'page';
        for (const job of decoders.jobs.values()) {
          try { job.resolve(lzmaDecode(latin1Bytes(job.packed))); } catch (err) { job.reject(err); }
        }
        decoders.jobs.clear();
      };
      w.onmessage = (e) => {
        const job = decoders.jobs.get(e.data.id);
        decoders.jobs.delete(e.data.id);
        if (e.data.error) job.reject(new Error(e.data.error));
        else job.resolve(e.data.out);
      };
      decoders.pool.push(w);
    }
    S.decoder = 'worker';
  } catch (err) {
    decoders.pool = [];
    S.decoder = 'page';
  }
  return decoders.pool;
}
// unlzma, decoded by the next worker of the pool (by the page when there is none).
async function unlzmaOffThread(packed) {
  const pool = decoderPool();
  if (!pool.length) return unlzma(packed);
  const bytes = latin1Bytes(packed);
  const id = ++decoders.id;
  const job = new Promise((resolve, reject) => {
    decoders.jobs.set(id, { resolve, reject, packed });
    pool[decoders.next++ % pool.length].postMessage({ id, bytes }, [bytes.buffer]);
  });
  const out = await (SELFTEST ? busyUntil(job) : job);
  return JSON.parse(new TextDecoder().decode(out));
}
// The selftest runs in headless Chromium under --virtual-time-budget, whose clock moves on while
// the page is idle, and waiting for a worker is idle: the page would be dumped before the worker
// answers. So there the page keeps itself busy (a message to itself, never a timer) until it does.
const SELFTEST = new URLSearchParams(location.search).get('selftest') === '1';
async function busyUntil(promise) {
  let settled = false;
  promise.then(() => { settled = true; }, () => { settled = true; });
  const channel = new MessageChannel();
  while (!settled) await new Promise((resolve) => { channel.port1.onmessage = resolve; channel.port2.postMessage(0); });
  return promise;
}
// One frame's packed columns (packed.h PackColumns), expanded lazily: a column is restored (a
// template {c, t, n} expanded, a reference {"=": [schema, index]} resolved) only when asked for,
// so that a history reads the entity columns of a frame, not all of its numbers.
class FrameColumns {
  constructor(p) { this.order = p.order; this.cols = p.cols; this.plain = {}; }
  column(sid, i) {
    const key = `${sid}/${i}`;
    if (this.plain[key]) return this.plain[key];
    let c = this.cols[sid][i];
    if (!Array.isArray(c) && c.t) {
      const cur = c.n.map(() => 0), out = new Array(c.c);
      for (let r = 0; r < c.c; ++r) {
        let s = c.t[0];
        for (let k = 0; k < c.n.length; ++k) s += (cur[k] += c.n[k][r]) + c.t[k + 1];
        out[r] = s;
      }
      c = out;
    } else if (!Array.isArray(c)) {
      c = this.column(c['='][0], c['='][1]);
    }
    return (this.plain[key] = c);
  }
  row(sid, j) {  // [schema, entity, occurrence, values...]
    const n = this.cols[sid].length, row = [Number(sid)];
    for (let i = 0; i < n; ++i) row.push(this.column(sid, i)[j]);
    return row;
  }
  // Rows whose entity passes `keep`, in file order; every row when keep is null.
  rows(keep) {
    const picked = {};
    for (const sid of Object.keys(this.cols)) {
      const ents = this.column(sid, 0), set = new Set();
      for (let j = 0; j < ents.length; ++j) if (!keep || keep(ents[j])) set.add(j);
      if (set.size) picked[sid] = set;
    }
    const next = {}, out = [];
    for (const sid of this.order) {
      const j = (next[sid] = next[sid] === undefined ? 0 : next[sid] + 1);
      if (picked[sid] && picked[sid].has(j)) out.push(this.row(sid, j));
    }
    return out;
  }
}
// The frames of data file c<n>.js of run k (ref/view/site_data.cpp ChunkWriter): [{head, columns}].
// The last CACHE_CHUNKS files stay decoded.
function chunkOf(k, n) {
  const key = `${k}/c${n}`;
  let p = S.cache.get(key);
  if (p) {
    S.cache.delete(key);
  } else {
    p = (async () => {
      await loadScript(`data/r${k}/c${n}.js`, false);
      const z = S.packed[key];
      delete S.packed[key];
      if (!z) return undefined;
      const frames = await unlzmaOffThread(z.packed);
      return frames.map((cols, i) => ({ ...z.heads[i], columns: new FrameColumns(cols) }));
    })();
    p.catch(() => S.cache.delete(key));
  }
  S.cache.set(key, p);
  while (S.cache.size > CACHE_CHUNKS) S.cache.delete(S.cache.keys().next().value);
  return p;
}
// The frames of a history in order, each with its data (frameOf), the next data file decoded by a
// worker while the page reads the rows of this one, and the progress in #history-title.
async function* historyFrames(k, summary, frames, id) {
  const K = summary.chunk_frames;
  const chunkOfFrame = (f) => (summary.indexOfFrame.has(f) ? Math.floor(summary.indexOfFrame.get(f) / K) : -1);
  const chunks = [...new Set(frames.map(chunkOfFrame).filter((c) => c >= 0))];
  let current = -1;
  for (const f of frames) {
    const c = chunkOfFrame(f);
    if (c !== current && c >= 0) {
      current = c;
      const i = chunks.indexOf(c);
      if (chunks.length > 1) $('history-title').textContent = `${id}: reading data file ${i + 1} of ${chunks.length} (frame ${f})`;
      if (i + 1 < chunks.length) chunkOf(k, chunks[i + 1]).catch(() => {});  // decoded ahead
    }
    yield [f, await frameOf(k, f)];
  }
}
// A frame's data {frame, stamp, image, columns} (undefined when the run has no such frame).
async function frameOf(k, f) {
  const summary = await summaryOf(k);
  const index = summary.indexOfFrame.get(f);
  if (index === undefined) return undefined;
  const K = summary.chunk_frames;
  const chunk = await chunkOf(k, Math.floor(index / K));
  return chunk ? chunk[index % K] : undefined;
}
// Every record of a frame as stored rows, decoded once per frame (showFrame).
function allRows(data) {
  if (!data.all) data.all = data.columns.rows(null);
  return data.all;
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
const baseId = (entity) => { const at = entity.indexOf('@'); return at < 0 ? entity : entity.slice(0, at); };
const perFrame = (id) => /^(f|i|l|pl|r)\d+\.\d+$/.test(id);
const frameOfId = (id) => Number(id.replace(/^[a-z]+/, '').split('.')[0]);

// Frames whose groups hold records of `id` (its own frame, and the summary's links).
function framesOf(summary, id) {
  const set = new Set(summary.links[id] || []);
  if (perFrame(id)) set.add(frameOfId(id));
  return [...set].sort((a, b) => a - b);
}

// Entities of a frame tied to landmark `m` (/^(mp|ml|mpl)(\d+)$/ match): the OBS naming map point
// m (associated, else final), or the records with input map_line / map_plane m. Reads only the
// columns it needs (FrameColumns).
function relatedEntities(summary, cols, m) {
  const related = new Set();
  for (const sid of Object.keys(cols.cols)) {
    const [type, , , names] = summary.schemas[sid];
    let values = null;
    if (m[1] === 'mp' && type === 'obs') {
      const a = names.indexOf('associated_map_point_id'), f = a >= 0 ? a : names.indexOf('map_point_id');
      if (f >= 0) values = cols.column(sid, 2 + f);
    } else if (m[1] !== 'mp') {
      const f = names.indexOf(m[1] === 'ml' ? 'in.map_line' : 'in.map_plane');
      if (f >= 0) values = cols.column(sid, 2 + f).map((v) => (v === Number(m[2]) ? m[2] : ''));
    }
    if (!values) continue;
    const ents = cols.column(sid, 0);
    for (let j = 0; j < ents.length; ++j) if (String(values[j]) === m[2]) related.add(ents[j]);
  }
  return related;
}

// The records `dynref trace feature RUN ID` lists (README "Feature history"). Only the rows of
// the entity (and of its related entities) are decoded.
async function plainHistory(k, id) {
  const summary = await summaryOf(k);
  const frames = framesOf(summary, id);
  const m = /^(mp|ml|mpl)(\d+)$/.exec(id);
  const rows = [];
  for await (const [f, data] of historyFrames(k, summary, frames, id)) {
    if (!data) continue;
    const wanted = m ? relatedEntities(summary, data.columns, m) : new Set();
    wanted.add(id);
    for (const row of data.columns.rows((e) => wanted.has(baseId(e)))) rows.push({ frame: f, ...decode(summary, row) });
  }
  return { id, rows };
}

// "f20.2" -> {prefix f, frame 20, index 2, perFrame}; "mp34" -> {prefix mp, frame -1, index 34}
// (as ref/trace/trace_follow.cpp ParseId).
function parseId(id) {
  let k = 0;
  while (k < id.length && id[k] >= 'a' && id[k] <= 'z') ++k;
  const p = { prefix: id.slice(0, k), frame: -1, index: -1, perFrame: false };
  const dot = id.indexOf('.', k);
  if (dot < 0) {
    const v = parseInt(id.slice(k), 10);
    if (!Number.isNaN(v)) p.index = v;
    return p;
  }
  p.perFrame = true;
  const f = parseInt(id.slice(k, dot), 10);
  if (Number.isNaN(f)) return p;
  p.frame = f;
  const i = parseInt(id.slice(dot + 1), 10);
  if (!Number.isNaN(i)) p.index = i;
  return p;
}
const byText = (a, b) => (a < b ? -1 : a > b ? 1 : 0);

// A residual link (trace_follow.cpp IsResidualLink): a one-hop reference, never followed further.
const isResidual = (via) => via.startsWith('residual (');

// The run's link graph (data/r<k>/links.js: the links `trace feature --follow` searches).
async function graphOf(k) {
  if (S.graphs[k]) return S.graphs[k];
  await loadScript(`data/r${k}/links.js`);
  const data = unlzma(S.links[k]);
  const adj = new Map(), instances = new Map();
  const add = (a, b, via) => {  // the first link names a pair, an identity link replaces a residual one
    if (!adj.has(a)) adj.set(a, new Map());
    const old = adj.get(a).get(b);
    if (old === undefined || (isResidual(old) && !isResidual(via))) adj.get(a).set(b, via);
  };
  for (let i = 0; i < data.links.length; i += 3) {
    const via = data.via[data.links[i + 2]];
    add(data.links[i], data.links[i + 1], via);
    add(data.links[i + 1], data.links[i], via);
  }
  for (const m of data.masks) {
    const inst = parseId(m).index;
    if (!instances.has(inst)) instances.set(inst, []);
    instances.get(inst).push(m);
  }
  for (const list of instances.values()) list.sort(byText);
  const sorted = new Map();
  const neighbours = (e) => {  // [entity, via] by entity (std::map order)
    if (!sorted.has(e)) sorted.set(e, adj.has(e) ? [...adj.get(e)].sort((a, b) => byText(a[0], b[0])) : null);
    return sorted.get(e);
  };
  S.graphs[k] = { neighbours, instances };
  delete S.links[k];
  return S.graphs[k];
}

// The chain of `start` (README "Following a feature"; the breadth-first search of
// trace_follow.cpp LinkGraph::Closure, step for step; residual links are one-hop references): [{entity, frame, via, from}] with
// per-frame entities by (frame, prefix, index), then landmarks.
function closure(graph, start) {
  const BACK = 1, FORWARD = 2, BOTH = 3;
  const seen = new Map(), expanded = new Map(), landmarksDone = new Set(), queue = [];
  // core: on the start's own track (trace_follow.cpp Closure): only its landmarks bring in theirs.
  const visit = (e, dir, via, from, core) => {
    if (!seen.has(e)) {
      const p = parseId(e);
      seen.set(e, { entity: e, frame: p.perFrame ? p.frame : -1, via, from });
    }
    const done = expanded.get(e) || 0;
    expanded.set(e, done);
    const mask = core ? dir | (dir << 2) : dir;
    if ((done | mask) === done) return;
    expanded.set(e, done | mask);
    queue.push([e, dir, core]);
  };
  const towards = (from, to, dir) => (to < from ? BACK : to > from ? FORWARD : dir);
  visit(start, BOTH, 'start', '', true);
  for (let qi = 0; qi < queue.length; ++qi) {
    const [e, dir, core] = queue[qi];
    const p = parseId(e);
    const next = graph.neighbours(e);
    if (!p.perFrame) {
      landmarksDone.add(e);
      if (next) for (const [n, via] of next) visit(n, isResidual(via) ? 0 : BOTH, via, e, true);
      continue;
    }
    if (next) {
      for (const [n, via] of next) {
        const q = parseId(n);
        if (q.perFrame) {
          const d = towards(p.frame, q.frame, dir);
          if (d & dir) visit(n, d, via, e, core);
          continue;
        }
        visit(n, 0, via, e, false);
        if (!core || isResidual(via) || landmarksDone.has(n)) continue;
        landmarksDone.add(n);
        const lm = graph.neighbours(n);
        if (lm) {
          for (const [other, via2] of lm) {
            const r = parseId(other);
            if (r.perFrame) visit(other, isResidual(via2) ? 0 : towards(p.frame, r.frame, dir), via2, n, false);
          }
        }
      }
    }
    if (p.prefix === 'i' && graph.instances.has(p.index))
      for (const n of graph.instances.get(p.index)) visit(n, BOTH, 'instance id', e, core);
  }
  const key = (c) => { const p = parseId(c.entity); return [p.perFrame ? 0 : 1, p.frame, p.prefix, p.index, c.entity]; };
  const cmp = (a, b) => {
    const x = key(a), y = key(b);
    for (let i = 0; i < x.length; ++i) if (x[i] !== y[i]) return x[i] < y[i] ? -1 : 1;
    return 0;
  };
  return [...seen.values()].sort(cmp);
}

// `dynref trace feature RUN ID --follow`: every record (counts aside) of every chain entity and
// its residuals, frames ascending, file order within a frame.
async function followHistory(k, id) {
  const summary = await summaryOf(k);
  const chain = closure(await graphOf(k), baseId(id));
  const members = new Set(chain.map((c) => c.entity));
  const frames = new Set();
  for (const c of chain) for (const f of framesOf(summary, c.entity)) frames.add(f);
  const rows = [];
  for await (const [f, data] of historyFrames(k, summary, [...frames].sort((a, b) => a - b), id)) {
    if (!data) continue;
    for (const row of data.columns.rows((e) => members.has(baseId(e)))) {
      const r = decode(summary, row);
      if (r.type !== 'count') rows.push({ frame: f, ...r });
    }
  }
  return { id, rows, chain };
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
  // A loop, not Math.min(...frames): a followed map point of a 300-frame run reaches 2.26 M records,
  // beyond the call stack a spread may use ("Maximum call stack size exceeded").
  let f0 = Infinity, f1 = -Infinity;
  for (const r of history.rows) f0 = Math.min(f0, r.frame), f1 = Math.max(f1, r.frame + 1);
  if (f0 > f1) return;
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
  $('history-title').textContent = `${history.id}${history.chain ? ` followed (${history.chain.length} entities)` : ''}: ` +
    `${history.rows.length} records over ${frames.size} frames, ${rejected} rejections` +
    (S.summary[S.run].digits < 17 ? ` (numbers to ${S.summary[S.run].digits} significant digits)` : '');
  drawPlot(history);
  renderChain(history.chain);
  const div = divergenceOf(S.run);
  const table = document.createElement('table');
  table.innerHTML = '<tr><th>frame</th><th>type</th><th>stage</th><th>entity</th><th>before &rarr; after</th><th>fields</th></tr>';
  // At most TABLE_ROWS rows in the table (a followed history reaches tens of thousands of records,
  // and building their DOM took longer than decoding them); the selftest output keeps every row.
  for (const r of history.rows.slice(0, TABLE_ROWS)) {
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
  if (history.rows.length > TABLE_ROWS)
    $('history').insertAdjacentHTML('beforeend', `<p class="muted">first ${TABLE_ROWS} of ${history.rows.length} records shown ` +
      '(all of them: <code>dynref trace feature</code>)</p>');
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

// The chain of a followed entity: one link per entity (frame, entity, link, reached from).
function renderChain(chain) {
  const box = $('chain');
  box.innerHTML = '';
  box.hidden = !chain;
  if (!chain) return;
  const summary = document.createElement('summary');
  summary.textContent = `chain: ${chain.length} entities (frame -> entity, link, from)`;
  box.appendChild(summary);
  for (const c of chain) {
    const line = document.createElement('div');
    const a = document.createElement('a');
    a.href = '#';
    a.textContent = c.entity;
    a.onclick = (e) => { e.preventDefault(); showEntity(c.entity); };
    line.append(`${c.frame >= 0 ? c.frame : '-'} -> `, a, ` (${c.via}${c.from ? ', from ' + c.from : ''})`);
    box.appendChild(line);
  }
}

async function showEntity(id) {
  $('entity').value = id;
  S.entity = id;
  const follow = $('follow').checked;
  const history = follow ? await followHistory(S.run, id) : await plainHistory(S.run, id);
  if (S.entity !== id) return history;  // another entity was asked for meanwhile
  renderHistory(history);
  if (SELFTEST) {
    const out = history.rows.map((r) => [r.frame, r.type, r.stage, r.kind, r.entity, r.occurrence,
      Object.fromEntries(r.fields)]);
    const chain = history.chain ? history.chain.map((c) => [c.frame, c.entity, c.via, c.from]) : null;
    $('selftest').textContent = JSON.stringify({ entity: id, follow, chain, rows: out, decoder: S.decoder || 'none' });
    document.title = 'selftest-done';
  }
  return history;
}

// The frame's features (OBS u, v) and line segments, for clicks on the image.
function frameShapes(summary, data) {
  const features = [], lines = [];
  for (const row of allRows(data)) {
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
  for (const row of allRows(data)) {
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
  const token = ++S.showToken;
  const data = await frameOf(S.run, frame);
  if (token !== S.showToken || !data) return;  // the slider moved on meanwhile
  const counts = {};
  for (const row of allRows(data)) {
    const r = decode(summary, row);
    counts[r.type] = (counts[r.type] || 0) + 1;
  }
  $('frame-info').textContent = `stamp ${data.stamp} | ` + Object.entries(counts).map(([t, n]) => `${t} ${n}`).join(', ');
  const img = $('overlay');
  const shapes = frameShapes(summary, data);
  const scale = summary.image_scale || 1;  // the JPEG's size relative to the frame
  img.onload = () => {
    img.style.width = `${Math.round(img.naturalWidth / scale)}px`;
    const c = $('hits');
    c.width = img.clientWidth;
    c.height = img.clientHeight;
    c.onclick = (e) => {
      const sx = img.naturalWidth / scale / img.clientWidth, sy = img.naturalHeight / scale / img.clientHeight;
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
  if (params.has('follow')) $('follow').checked = params.get('follow') === '1';
  $('follow').onchange = () => { if (S.entity) showEntity(S.entity); };
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
