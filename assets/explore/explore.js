// shadelab explore: the browser page. It uses only the API of docs/explore.md (version 1).
// No library, no build step: plain ES2020 for Chromium and Firefox.
'use strict';

const $ = (id) => document.getElementById(id);
const API = '/api/v1/';
const PRECISIONS = ['f32', 'f16'];
const PRECISION_LABEL = { f32: 'float32', f16: 'float16' };
const SIZES = [64, 128, 256, 512, 1024];
const DEBOUNCE_MS = 250;
// [statistics key, label, is a pixel count]
const STATS = [
  ['max_abs_error', 'max |dI|', false],
  ['p99_abs_error', 'p99 |dI|', false],
  ['mean_abs_error', 'mean |dI|', false],
  ['flip_mean', 'FLIP mean', false],
  ['non_finite_pixels', 'non-finite pixels', true],
  ['covered_pixels', 'covered pixels', true],
];

const st = {
  session: null,
  methods: new Map(),   // name -> session method entry (source with \n line ends)
  picked: null,         // the entry picked in #method (A)
  check: { ok: false, key: null, name: null },  // the last check answered for A
  checkNo: 0, checkCtrl: null,
  seq: 0,
  run: null,            // the current set of result requests (see startRun)
  disasmCtrl: null, disasmKey: null, // the [method, precision] of the disassembly shown
  errorLines: new Map(), // line -> messages, for the gutter
  gutterLines: 0,
  tabEscape: false,     // Esc pressed in the editor: the next Tab leaves it
  hashNo: 0, lastHash: '',
  timers: {},
  scale: 1.5,           // right end of the cost bars' axis (a ratio)
};
const TAB = randomId();

// ---------------------------------------------------------------- small helpers

function randomId() {
  const b = new Uint8Array(8);
  crypto.getRandomValues(b);
  return Array.from(b, (x) => x.toString(16).padStart(2, '0')).join('');
}

function debounce(key, fn, ms = DEBOUNCE_MS) {
  clearTimeout(st.timers[key]);
  st.timers[key] = setTimeout(fn, ms);
}

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c);
  return e;
}

function escapeHtml(s) {
  return s.replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}

// Numbers with 3 significant digits: fixed between 1e-3 and 1e4, else exponent.
function fmt(x, isCount = false) {
  if (x === null || x === undefined || (typeof x === 'number' && !Number.isFinite(x))) return 'n/a';
  if (isCount) return String(Math.round(x));
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e-3 && a < 1e4 ? String(Number(x.toPrecision(3))) : x.toExponential(2);
}

function fmtDiff(a, b, isCount) {
  if (typeof a !== 'number' || typeof b !== 'number') return 'n/a';
  const d = a - b;
  return (d > 0 ? '+' : '') + fmt(d, isCount);
}

function banner(msg) {
  const b = $('banner');
  b.textContent = msg;
  b.hidden = !msg;
}

function setState(s) { document.body.dataset.state = s; }

// ---------------------------------------------------------------- HTTP

class HttpError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}

// A superseded request: aborted by a newer set, or answered 409 by the server.
const superseded = (e) => e.name === 'AbortError' || (e instanceof HttpError && e.status === 409);

async function errorOf(r) {
  let msg = `${r.status} ${r.statusText}`.trim();
  try {
    const j = await r.json();
    if (j && j.error) msg = j.error;
  } catch (_) { /* not JSON: keep the status */ }
  return new HttpError(r.status, msg);
}

async function post(path, body, signal) {
  const r = await fetch(API + path, {
    method: 'POST', credentials: 'same-origin', signal,
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  if (!r.ok) throw await errorOf(r);
  return r;
}

// Reads an NDJSON body line by line as it arrives.
async function readNdjson(response, onLine) {
  const reader = response.body.getReader();
  const decoder = new TextDecoder();
  let buf = '';
  for (;;) {
    const { value, done } = await reader.read();
    buf += done ? decoder.decode() : decoder.decode(value, { stream: true });
    let nl;
    while ((nl = buf.indexOf('\n')) >= 0) {
      const line = buf.slice(0, nl).trim();
      buf = buf.slice(nl + 1);
      if (line) onLine(JSON.parse(line));
    }
    if (done) break;
  }
  if (buf.trim()) onLine(JSON.parse(buf));
}

// ---------------------------------------------------------------- method and scene references

function normalise(text) { return text.replace(/\r\n?/g, '\n'); }

function isEdited() { return !!st.picked && $('source').value !== st.picked.source; }

function methodRef() {
  return isEdited() ? { source: $('source').value } : { name: st.picked.name };
}

// The name the saved file and the command lines use.
function saveName() { return isEdited() ? 'my_method' : st.picked.name; }

// Scene options are valued "scene:ID", "model:ID" or "upload:ID".
function sceneRef(value = $('scene').value) {
  const i = value.indexOf(':');
  return { [value.slice(0, i)]: value.slice(i + 1) };
}

function sceneValue(ref) {
  const kind = ['scene', 'model', 'upload'].find((k) => ref && typeof ref[k] === 'string');
  return kind ? `${kind}:${ref[kind]}` : '';
}

function hasOption(select, value) {
  return Array.from(select.options).some((o) => o.value === value);
}

// ---------------------------------------------------------------- filling the controls

function fillMethodSelect(select) {
  select.textContent = '';
  const groups = { table: el('optgroup', { label: 'table' }), user: el('optgroup', { label: 'your methods (--method-file)' }) };
  for (const m of st.methods.values()) {
    const o = el('option', { value: m.name, text: m.name });
    if (m.description) o.title = m.description;
    groups[m.user ? 'user' : 'table'].append(o);
  }
  for (const g of Object.values(groups)) if (g.children.length) select.append(g);
}

function fillScenes() {
  const select = $('scene');
  const groups = {
    scene: el('optgroup', { label: 'scenes', id: 'scene-group-scene' }),
    model: el('optgroup', { label: 'models', id: 'scene-group-model' }),
  };
  for (const s of st.session.scenes) {
    const g = groups[s.kind] || groups.scene;
    g.append(el('option', { value: `${s.kind === 'model' ? 'model' : 'scene'}:${s.id}`, text: s.name || s.id }));
  }
  for (const g of Object.values(groups)) if (g.children.length) select.append(g);
}

function fillSizes() {
  const { size_min: lo = 64, size_max: hi = 1024 } = st.session.limits || {};
  const sizes = SIZES.filter((s) => s >= lo && s <= hi);
  const def = st.session.defaults.size;
  if (def && !sizes.includes(def)) sizes.push(def);
  sizes.sort((a, b) => a - b);
  for (const s of sizes) $('size').append(el('option', { value: String(s), text: `${s} × ${s}` }));
}

function applyDefaults() {
  const d = st.session.defaults;
  $('method').value = st.methods.has(d.method) ? d.method : $('method').options[0].value;
  $('method-b').value = $('method').value;
  const sv = sceneValue(d.scene);
  if (hasOption($('scene'), sv)) $('scene').value = sv;
  if (d.size) $('size').value = String(d.size);
  $('precision').value = d.precision === 'f16' ? 'f16' : 'f32';
  $('budget').value = d.budget || '';
}

// Picks method A and shows its source.
function pickMethod(name) {
  st.picked = st.methods.get(name);
  $('method').value = name;
  $('source').value = st.picked.source;
  $('method-description').textContent = st.picked.description || '';
  clearDisasm();
  onSourceShown();
}

function showClaims() {
  const m = st.picked, box = $('claims');
  box.textContent = '';
  const items = [];
  for (const c of m.claims || []) {
    items.push(`${c.verdict} (${c.basis}): ${c.claim}` + (c.measured ? ` — ${c.measured}` : ''));
  }
  if (m.stress_valid_angle_deg !== null && m.stress_valid_angle_deg !== undefined) {
    items.push(`stress valid angle: ${fmt(m.stress_valid_angle_deg)}°`);
  }
  if (!items.length) return;
  box.append(el('span', { class: 'claims-title', text: `claims for ${m.name}` + (isEdited() ? ' (unedited)' : '') }));
  for (const t of items) box.append(el('div', { text: t }));
}

// ---------------------------------------------------------------- editor: gutter, tab, errors

function lineCount(text) {
  let n = 1;
  for (let i = text.indexOf('\n'); i >= 0; i = text.indexOf('\n', i + 1)) n++;
  return n;
}

function updateGutter() {
  const gutter = $('gutter'), n = lineCount($('source').value);
  if (n !== st.gutterLines) {
    const frag = document.createDocumentFragment();
    for (let i = 1; i <= n; i++) frag.append(el('div', { text: String(i) }));
    gutter.textContent = '';
    gutter.append(frag);
    st.gutterLines = n;
  }
  Array.from(gutter.children).forEach((d, i) => {
    const msgs = st.errorLines.get(i + 1);
    d.classList.toggle('err', !!msgs);
    if (msgs) d.title = msgs.join('\n'); else d.removeAttribute('title');
  });
  gutter.scrollTop = $('source').scrollTop;
}

function showErrors(errors) {
  const list = $('errors');
  list.textContent = '';
  st.errorLines = new Map();
  for (const e of errors) {
    const line = Number.isInteger(e.line) ? e.line : null;
    const li = el('li', { text: line !== null ? `line ${line}: ${e.message}` : e.message });
    if (line !== null) {
      li.dataset.line = String(line);
      li.tabIndex = 0;
      li.title = 'go to the line';
      st.errorLines.set(line, [...(st.errorLines.get(line) || []), e.message]);
    }
    list.append(li);
  }
  updateGutter();
}

// Puts the caret at the start of a line and selects it.
function goToLine(line) {
  const ta = $('source'), lines = ta.value.split('\n');
  const start = lines.slice(0, line - 1).reduce((n, l) => n + l.length + 1, 0);
  ta.focus();
  ta.setSelectionRange(start, start + (lines[line - 1] || '').length);
  const lh = parseFloat(getComputedStyle(ta).lineHeight) || 18;
  ta.scrollTop = Math.max(0, (line - 4) * lh);
}

function onEditorKey(e) {
  if (e.key === 'Escape') { st.tabEscape = true; return; }
  const plainTab = e.key === 'Tab' && !e.shiftKey && !e.ctrlKey && !e.altKey && !e.metaKey;
  if (plainTab && !st.tabEscape) {
    e.preventDefault();
    // execCommand keeps the undo history; setRangeText where it is refused.
    if (!document.execCommand('insertText', false, '    ')) {
      const ta = $('source');
      ta.setRangeText('    ', ta.selectionStart, ta.selectionEnd, 'end');
      ta.dispatchEvent(new Event('input'));
    }
  }
  if (e.key !== 'Tab') st.tabEscape = false;
}

// Called whenever the editor's text changed (typed, picked, restored).
function onSourceShown() {
  updateGutter();
  $('edit-state').textContent = isEdited() ? 'edited: sent as source' : '';
  $('source').classList.toggle('edited', isEdited());
  showClaims();
}

// ---------------------------------------------------------------- check

async function runCheck() {
  clearTimeout(st.timers.check); // this check supersedes one still waiting for a pause in typing
  const no = ++st.checkNo;
  if (st.checkCtrl) st.checkCtrl.abort();
  const ctrl = st.checkCtrl = new AbortController();
  const ref = methodRef();
  const key = JSON.stringify(ref);
  document.body.dataset.check = 'pending';
  let res;
  const limit = (st.session.limits || {}).source_bytes;
  if (ref.source !== undefined && limit && new TextEncoder().encode(ref.source).length > limit) {
    res = { ok: false, errors: [{ line: null, message: `the source is over the limit of ${limit} bytes` }] };
  } else {
    try {
      const r = await fetch(API + 'check', {
        method: 'POST', credentials: 'same-origin', signal: ctrl.signal,
        headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ method: ref }),
      });
      // The verdict may come with 200 or with an error status (422): read it from the body.
      let j = null;
      try { j = await r.json(); } catch (_) { /* no JSON body */ }
      if (j && typeof j.ok === 'boolean') res = j;
      else throw new HttpError(r.status, (j && j.error) || `${r.status} ${r.statusText}`);
    } catch (e) {
      if (e.name === 'AbortError' || no !== st.checkNo) return;
      res = { ok: false, errors: [{ line: null, message: `check failed: ${e.message}` }] };
    }
  }
  if (no !== st.checkNo) return;
  st.check = { ok: res.ok, key, name: res.name || null };
  showErrors(res.ok ? [] : (res.errors || []));
  document.body.dataset.check = res.ok ? 'ok' : 'errors';
  if (res.ok) startRun();
  else setState('invalid');
}

// A setting changed: new results if the method is known to compile.
function onSettingChange() {
  updatePermalink();
  if (document.body.dataset.check === 'pending') return; // the check will start the run
  if (st.check.ok && st.check.key === JSON.stringify(methodRef())) startRun();
}

function onSourceInput() {
  onSourceShown();
  // The results on screen are of the text before this edit: a run still going must not mark
  // the page done when it ends.
  if (st.run) { st.run.ctrl.abort(); st.run = null; }
  markStale();
  setState('busy');
  document.body.dataset.check = 'pending';
  debounce('check', () => { runCheck(); updatePermalink(); });
}

// ---------------------------------------------------------------- a set of result requests

function markStale() {
  for (const id of ['cell-a', 'cell-b', 'cell-diff', 'stats']) $(id).classList.add('stale');
}

// Renders and costs of A (and B) in parallel, each shown as it arrives.
function startRun() {
  if (st.run) st.run.ctrl.abort();
  const set = {
    seq: ++st.seq, ctrl: new AbortController(), ab: $('ab').checked,
    precision: $('precision').value, methodA: methodRef(), edited: isEdited(),
    renders: {}, failed: false, isa: {}, costMs: {},
  };
  st.run = set;
  setState('busy');
  // A disassembly shown for another method or precision is no longer the one of these costs.
  if (st.disasmKey && st.disasmKey !== JSON.stringify([set.methodA, set.precision])) clearDisasm();
  const common = {
    scene: sceneRef(), size: Number($('size').value), precision: set.precision,
    budget: $('budget').value.trim(), tab: TAB, seq: set.seq,
  };
  resetResults(set);
  const sides = [['a', set.methodA]];
  if (set.ab) sides.push(['b', { name: $('method-b').value }]);
  const renders = [], costs = [];
  for (const [side, method] of sides) {
    renders.push(renderJob(set, side, method, common));
    for (const p of PRECISIONS) costs.push(costJob(set, side, method, p));
  }
  Promise.all(costs).then(() => {
    if (set === st.run) $('costs').dataset.done = 'true';
  });
  Promise.all([...renders, ...costs]).then(() => {
    if (set !== st.run) return;
    for (const id of ['cell-a', 'cell-b', 'cell-diff', 'stats']) $(id).classList.remove('stale');
    setState(set.failed ? 'error' : 'done');
  });
}

function resetResults(set) {
  $('costs').dataset.done = 'false';
  $('cell-b').hidden = !set.ab;
  $('cell-diff').hidden = !set.ab;
  $('stats').classList.toggle('ab', set.ab);
  document.body.classList.toggle('ab-on', set.ab);
  $('name-a').textContent = set.edited ? 'edit of ' + st.picked.name : st.picked.name;
  $('name-b').textContent = set.ab ? $('method-b').value : '';
  $('render-ms').textContent = $('render-ms-b').textContent = $('cost-ms').textContent = '';
  buildCostRows(set);
  updateCommands();
}

async function renderJob(set, side, method, common) {
  const sfx = side === 'a' ? '' : '-b';
  try {
    const r = await post('render', { method, ...common }, set.ctrl.signal);
    const j = await r.json();
    if (set !== st.run) return;
    set.renders[side] = j;
    showRender(sfx, j);
  } catch (e) {
    if (superseded(e) || set !== st.run) return;
    set.failed = true;
    set.renders[side] = null;
    showRenderError(sfx, e.message);
  }
  $('cell-' + side).classList.remove('stale');
  showStats(set);
  updateWins(set);
  updateCommands();
  if (set.ab && set.renders.a && set.renders.b) drawAbDiff(set);
}

function showRender(sfx, j) {
  $('render-error' + sfx).textContent = '';
  $('render' + sfx).src = 'data:image/png;base64,' + j.render_png;
  $('heatmap' + sfx).src = 'data:image/png;base64,' + j.heatmap_png;
  $('render-ms' + sfx).textContent = typeof j.elapsed_ms === 'number' ? `render ${Math.round(j.elapsed_ms)} ms` : '';
  const v = $('verdict' + sfx), b = j.budget;
  v.textContent = '';
  v.className = 'verdict';
  if (!b) return;
  v.classList.add(b.within ? 'within' : 'outside');
  v.append(el('strong', { text: b.within ? 'within the budget' : 'outside the budget' }));
  if (typeof b.limit === 'number') v.append(` (limit ${fmt(b.limit)})`);
  if (b.why) v.append(': ' + b.why);
}

function showRenderError(sfx, message) {
  $('render-error' + sfx).textContent = message;
  $('render' + sfx).removeAttribute('src');
  $('heatmap' + sfx).removeAttribute('src');
  $('verdict' + sfx).textContent = '';
  $('verdict' + sfx).className = 'verdict';
}

function buildStatsRows() {
  const body = $('stats').tBodies[0];
  for (const [key, label] of STATS) {
    body.append(el('tr', { 'data-stat': key },
      el('th', { scope: 'row', text: label }),
      el('td', { class: 'a' }), el('td', { class: 'b bcol' }), el('td', { class: 'd bcol' })));
  }
}

function showStats(set) {
  const sa = set.renders.a ? set.renders.a.statistics : undefined;
  const sb = set.ab && set.renders.b ? set.renders.b.statistics : undefined;
  const cell = (s, key, isCount) => (s === undefined ? '–' : fmt(s && s[key], isCount));
  for (const [key, , isCount] of STATS) {
    const tr = $('stats').querySelector(`tr[data-stat="${key}"]`);
    const [a, b, d] = tr.querySelectorAll('td');
    a.textContent = cell(sa, key, isCount);
    a.dataset.value = sa && typeof sa[key] === 'number' ? String(sa[key]) : '';
    b.textContent = cell(sb, key, isCount);
    d.textContent = sa && sb ? fmtDiff(sa[key], sb[key], isCount) : '–';
  }
}

// ---------------------------------------------------------------- A/B pixel difference

function loadImage(src) {
  const img = new Image();
  img.src = src;
  return img.decode().then(() => img);
}

function pixelsOf(img, w, h) {
  const c = document.createElement('canvas');
  c.width = w; c.height = h;
  const ctx = c.getContext('2d', { willReadFrequently: true });
  ctx.drawImage(img, 0, 0);
  return ctx.getImageData(0, 0, w, h).data;
}

// |A - B| per pixel (largest channel difference), times 10, as grey.
async function drawAbDiff(set) {
  let ia, ib;
  try {
    [ia, ib] = await Promise.all([$('render').src, $('render-b').src].map(loadImage));
  } catch (_) { return; }
  if (set !== st.run) return;
  const w = Math.min(ia.naturalWidth, ib.naturalWidth), h = Math.min(ia.naturalHeight, ib.naturalHeight);
  const a = pixelsOf(ia, w, h), b = pixelsOf(ib, w, h);
  const canvas = $('ab-diff');
  canvas.width = w; canvas.height = h;
  const ctx = canvas.getContext('2d');
  const out = ctx.createImageData(w, h);
  let max = 0;
  for (let i = 0; i < a.length; i += 4) {
    const d = Math.max(Math.abs(a[i] - b[i]), Math.abs(a[i + 1] - b[i + 1]), Math.abs(a[i + 2] - b[i + 2]));
    if (d > max) max = d;
    const g = Math.min(255, d * 10);
    out.data[i] = out.data[i + 1] = out.data[i + 2] = g;
    out.data[i + 3] = 255;
  }
  ctx.putImageData(out, 0, 0);
  canvas.dataset.maxDiff = String(max);
  $('cell-diff').classList.remove('stale');
}

// ---------------------------------------------------------------- cost rows

const seriesKeys = (set) => (set.ab ? ['a', 'b'] : ['a']).flatMap((s) => PRECISIONS.map((p) => [s, p]));
const ratioKey = (side, p) => (side === 'a' ? 'ratio' : 'ratioB') + p.toUpperCase(); // dataset key

function buildCostRows(set) {
  const costs = $('costs');
  costs.textContent = '';
  st.scale = 1.5;
  costs.style.setProperty('--scale', st.scale);
  // The axis is laid out as a row, so that its track lines up with the bars' tracks.
  const track = el('span', { class: 'track' }, el('span', { class: 'axis-zero', text: '0' }),
    el('span', { class: 'axis-one', text: '1.0' }), el('span', { class: 'axis-max', text: st.scale.toFixed(1) }));
  costs.append(el('div', { class: 'cost-axis', 'aria-hidden': 'true' }, el('span', { class: 'fam' }),
    el('div', { class: 'bars' }, el('div', { class: 'series' }, el('span'), track, el('span'), el('span'))),
    el('span', { class: 'unit' })));
  for (const f of st.session.families || []) costRow(set, f.id, f.vendor);
}

// The row of a family, made (under its vendor's group) the first time it is met.
function costRow(set, family, vendor) {
  const costs = $('costs');
  let row = Array.from(costs.querySelectorAll('.cost-row')).find((r) => r.dataset.family === family);
  if (row) return row;
  vendor = vendor || family.split(':')[0];
  let group = Array.from(costs.querySelectorAll('.vendor')).find((g) => g.dataset.vendor === vendor);
  if (!group) {
    group = el('section', { class: 'vendor', 'data-vendor': vendor }, el('h3', { text: vendor }));
    costs.append(group);
  }
  row = el('div', {
    class: 'cost-row', tabindex: '0', role: 'button', 'data-family': family,
    'data-ratio-f32': '', 'data-ratio-f16': '', title: `${family}: click for the disassembly`,
  });
  const bars = el('div', { class: 'bars' });
  for (const [side, p] of seriesKeys(set)) {
    bars.append(el('div', { class: `series s-${side}-${p} pending`, 'data-series': `${side}-${p}` },
      el('span', { class: 'lbl', text: (side === 'b' ? 'B ' : '') + PRECISION_LABEL[p] }),
      el('span', { class: 'track' }, el('span', { class: 'bar' }), el('span', { class: 'one' })),
      el('span', { class: 'status', text: 'waiting…' }),
      el('span', { class: 'num' }),
      el('span', { class: 'delta' })));
    if (side === 'b') row.dataset[ratioKey(side, p)] = '';
  }
  row.append(el('span', { class: 'fam', text: family }), bars, el('span', { class: 'unit' }));
  group.append(row);
  return row;
}

async function costJob(set, side, method, precision) {
  try {
    const r = await post('cost', { method, precision, tab: TAB, seq: set.seq }, set.ctrl.signal);
    await readNdjson(r, (line) => {
      if (set !== st.run) return;
      // The last line is {"done": true, ...}; a superseded stream may end {"done": false, "superseded": true}.
      if (line.done) costDone(set, side, precision, line);
      else if (line.family) costLine(set, side, precision, line);
      else if (line.error) costError(set, side, precision, line.error);
    });
  } catch (e) {
    if (superseded(e) || set !== st.run) return;
    costError(set, side, precision, e.message);
  }
  if (set === st.run) finishSeries(set, side, precision);
}

function costLine(set, side, p, line) {
  const row = costRow(set, line.family, line.vendor);
  const s = row.querySelector(`[data-series="${side}-${p}"]`);
  if (!s) return;
  const ratio = typeof line.ratio === 'number' && Number.isFinite(line.ratio) ? line.ratio : null;
  row.dataset[ratioKey(side, p)] = ratio === null ? '' : String(ratio);
  s.classList.remove('pending');
  s.classList.toggle('nofig', ratio === null);
  if (ratio !== null) {
    s.style.setProperty('--r', ratio);
    s.querySelector('.num').textContent = ratio.toPrecision(3);
    s.querySelector('.status').textContent = '';
    s.title = [line.statistic, line.value !== undefined ? `${line.value} vs phong_exact ${line.phong_exact}` : '',
      line.unit || '', line.from_store ? '(from the compile store)' : ''].filter(Boolean).join(' ');
    growScale(ratio);
  } else {
    s.querySelector('.status').textContent = line.status || 'no figure';
    s.querySelector('.num').textContent = '';
  }
  if (line.bound_unit) {
    row.dataset['bound' + (side === 'a' ? '' : 'B') + p.toUpperCase()] = line.bound_unit;
  }
  refreshRow(set, row);
}

function costError(set, side, p, message) {
  let box = $('costs').querySelector('.cost-errors');
  if (!box) {
    box = el('ul', { class: 'cost-errors', role: 'status' });
    $('costs').prepend(box);
  }
  box.append(el('li', { text: `${side === 'b' ? 'B ' : ''}${PRECISION_LABEL[p]}: ${message}` }));
}

function costDone(set, side, p, line) {
  if (side === 'a') {
    set.isa[p] = line.isa || '';
    if (typeof line.elapsed_ms === 'number') set.costMs[p] = line.elapsed_ms;
    $('cost-ms').textContent = PRECISIONS.filter((q) => q in set.costMs)
      .map((q) => `${q} ${Math.round(set.costMs[q])} ms`).join(' · ');
    updateCommands();
  }
}

// A stream ended: families it did not name have no figure.
function finishSeries(set, side, p) {
  for (const s of $('costs').querySelectorAll(`.series.pending[data-series="${side}-${p}"]`)) {
    s.classList.remove('pending');
    s.classList.add('nofig');
    s.querySelector('.status').textContent = 'no figure';
    refreshRow(set, s.closest('.cost-row'));
  }
}

// Widens the bars' axis when a ratio passes its end (bars are sized by CSS from --r / --scale).
function growScale(ratio) {
  if (ratio <= st.scale) return;
  st.scale = Math.ceil(ratio * 1.05 * 2) / 2;
  const costs = $('costs');
  costs.style.setProperty('--scale', st.scale);
  const max = costs.querySelector('.axis-max');
  if (max) max.textContent = st.scale.toFixed(1);
}

// The row's derived parts: A − B per precision, its bound units, greyed when it has no figure.
function refreshRow(set, row) {
  const num = (k) => (row.dataset[k] ? Number(row.dataset[k]) : null);
  if (set.ab) {
    for (const p of PRECISIONS) {
      const a = num(ratioKey('a', p)), b = num(ratioKey('b', p));
      const d = a !== null && b !== null ? a - b : null;
      row.dataset['ratioDiff' + p.toUpperCase()] = d === null ? '' : String(d);
      row.querySelector(`[data-series="b-${p}"] .delta`).textContent =
        d === null ? '' : `A − B ${d > 0 ? '+' : ''}${d.toFixed(3)}`;
    }
  }
  const units = [...new Set(PRECISIONS.map((p) => row.dataset['bound' + p.toUpperCase()]).filter(Boolean))];
  row.querySelector('.unit').textContent = units.length ? `bound: ${units.join(' / ')}` : '';
  const series = row.querySelectorAll('.series');
  row.classList.toggle('nofig', Array.from(series).every((s) => s.classList.contains('nofig')));
  winsOf(set, row);
}

// "wins": cheaper than phong_exact (current precision) and within the budget.
function winsOf(set, row) {
  for (const side of set.ab ? ['a', 'b'] : ['a']) {
    const r = set.renders[side];
    const within = !!(r && r.budget && r.budget.within === true);
    const ratio = row.dataset[ratioKey(side, set.precision)];
    const wins = within && ratio !== '' && ratio !== undefined && Number(ratio) < 1;
    if (side === 'a') row.classList.toggle('wins', wins);
    const s = row.querySelector(`[data-series="${side}-${set.precision}"]`);
    if (s) s.classList.toggle('wins', wins);
  }
}

function updateWins(set) {
  for (const row of $('costs').querySelectorAll('.cost-row')) winsOf(set, row);
}

// ---------------------------------------------------------------- disassembly and its diff

function clearDisasm() {
  if (st.disasmCtrl) st.disasmCtrl.abort();
  st.disasmKey = null;
  const box = $('disasm');
  box.textContent = '';
  delete box.dataset.family;
  box.append(el('p', { class: 'note', text: 'Click a family row to compare the fragment program with phong_exact\'s.' }));
  for (const r of document.querySelectorAll('.cost-row.selected')) r.classList.remove('selected');
}

async function showDisasm(row) {
  const family = row.dataset.family;
  const method = st.run ? st.run.methodA : methodRef();
  const precision = st.run ? st.run.precision : $('precision').value;
  for (const r of document.querySelectorAll('.cost-row.selected')) r.classList.remove('selected');
  row.classList.add('selected');
  if (st.disasmCtrl) st.disasmCtrl.abort();
  const ctrl = st.disasmCtrl = new AbortController();
  st.disasmKey = JSON.stringify([method, precision]);
  const box = $('disasm');
  box.dataset.family = family;
  box.dataset.state = 'busy';
  box.textContent = `loading the disassembly for ${family} (${PRECISION_LABEL[precision]})…`;
  try {
    const j = await (await post('disasm', { method, family, precision }, ctrl.signal)).json();
    if (ctrl !== st.disasmCtrl) return;
    renderDiff(box, j, precision);
    box.dataset.state = 'done';
  } catch (e) {
    if (e.name === 'AbortError' || ctrl !== st.disasmCtrl) return;
    box.textContent = '';
    box.append(el('div', { class: 'cell-error', text: `${family}: ${e.message}` }));
    box.dataset.state = 'error';
  }
}

// Myers' O(ND) line diff. Returns [op, i, j] with op '=' (a[i] == b[j]), '-' (a[i] only), '+' (b[j] only).
function diffLines(a, b) {
  // Common head and tail first: they are most of two programs' text.
  let head = 0;
  while (head < a.length && head < b.length && a[head] === b[head]) head++;
  let tail = 0;
  while (tail < a.length - head && tail < b.length - head &&
         a[a.length - 1 - tail] === b[b.length - 1 - tail]) tail++;
  const ma = a.slice(head, a.length - tail), mb = b.slice(head, b.length - tail);
  const ops = [];
  for (let i = 0; i < head; i++) ops.push(['=', i, i]);
  for (const [op, i, j] of myers(ma, mb)) ops.push([op, i + head, j + head]);
  for (let t = tail; t > 0; t--) ops.push(['=', a.length - t, b.length - t]);
  return ops;
}

function myers(a, b, maxD = 4000) {
  const n = a.length, m = b.length, max = n + m, off = max + 1;
  const v = new Int32Array(2 * max + 3);
  const trace = []; // trace[d][k + d]: furthest x on diagonal k after d edits
  let found = -1;
  for (let d = 0; d <= Math.min(max, maxD) && found < 0; d++) {
    for (let k = -d; k <= d; k += 2) {
      let x = (k === -d || (k !== d && v[off + k - 1] < v[off + k + 1])) ? v[off + k + 1] : v[off + k - 1] + 1;
      let y = x - k;
      while (x < n && y < m && a[x] === b[y]) { x++; y++; }
      v[off + k] = x;
      if (x >= n && y >= m) { found = d; break; }
    }
    trace.push(v.slice(off - d, off + d + 1));
  }
  if (found < 0) { // too different to be worth it: everything changed
    return [...a.map((_, i) => ['-', i, 0]), ...b.map((_, j) => ['+', n, j])];
  }
  const ops = [];
  let x = n, y = m;
  for (let d = found; d > 0; d--) {
    const prev = trace[d - 1], get = (k) => prev[k + d - 1];
    const k = x - y;
    const pk = (k === -d || (k !== d && get(k - 1) < get(k + 1))) ? k + 1 : k - 1;
    const px = get(pk), py = px - pk;
    while (x > px && y > py) { x--; y--; ops.push(['=', x, y]); }
    if (x === px) { y--; ops.push(['+', x, y]); } else { x--; ops.push(['-', x, y]); }
  }
  while (x > 0 && y > 0) { x--; y--; ops.push(['=', x, y]); }
  return ops.reverse();
}

// Side by side: phong_exact left, the method right; a run of removals faces the run of additions.
function renderDiff(box, j, precision) {
  const left = (j.reference && j.reference.text || '').split('\n');
  const right = (j.method && j.method.text || '').split('\n');
  const ops = diffLines(left, right);
  const rows = [];
  let dels = [], adds = [], onlyL = 0, onlyR = 0;
  const cell = (side, idx, lines, cls) => (idx === undefined
    ? '<td class="ln"></td><td class="empty"></td>'
    : `<td class="ln">${idx + 1}</td><td class="${side} ${cls}">${escapeHtml(lines[idx])}</td>`);
  const flush = () => {
    for (let i = 0; i < Math.max(dels.length, adds.length); i++) {
      rows.push(`<tr class="chg">${cell('l', dels[i], left, 'del')}${cell('r', adds[i], right, 'ins')}</tr>`);
    }
    onlyL += dels.length; onlyR += adds.length;
    dels = []; adds = [];
  };
  for (const [op, i, k] of ops) {
    if (op === '-') dels.push(i);
    else if (op === '+') adds.push(k);
    else { flush(); rows.push(`<tr>${cell('l', i, left, '')}${cell('r', k, right, '')}</tr>`); }
  }
  flush();
  box.textContent = '';
  box.dataset.leftOnly = String(onlyL);
  box.dataset.rightOnly = String(onlyR);
  const name = (j.method && j.method.name) || 'method';
  box.append(el('p', { class: 'note', text:
    `${j.family || box.dataset.family}, ${PRECISION_LABEL[precision]}: ${left.length} lines in phong_exact, ` +
    `${right.length} in ${name}; ${onlyL} only left, ${onlyR} only right` }));
  const table = el('table', { class: 'diff' });
  table.innerHTML = `<colgroup><col class="lnc"><col><col class="lnc"><col></colgroup><thead><tr><th colspan="2" scope="col">phong_exact</th><th colspan="2" scope="col">${escapeHtml(name)}</th></tr></thead>` +
    `<tbody>${rows.join('')}</tbody>`;
  box.append(el('div', { class: 'diff-scroll' }, table));
}

// ---------------------------------------------------------------- commands and the method file

// For an edit, the commands name the saved file: NAME.glsl and --methods NAME.
function commandFor(cmd, set) {
  if (!set.edited || !cmd) return cmd;
  const name = saveName();
  let c = cmd.replace(/\bedit_[0-9a-f]{12}\b/g, name);
  if (!/--method-file\b/.test(c)) c = c.replace(/^(\s*shadelab\s+\S+)/, `$1 --method-file ${name}.glsl`);
  return c;
}

function updateCommands() {
  const set = st.run, out = [];
  if (set) {
    if (set.edited) out.push(`# save the source as ${saveName()}.glsl, then:`);
    const ra = set.renders.a;
    if (ra && ra.compare) out.push(commandFor(ra.compare, set));
    if (set.isa[set.precision]) out.push(commandFor(set.isa[set.precision], set));
    const rb = set.ab && set.renders.b;
    if (rb && rb.compare) out.push('# B:', rb.compare);
  }
  $('commands').textContent = out.join('\n');
}

function saveMethodFile() {
  let text = $('source').value;
  const head = text.split('\n').slice(0, 20).join('\n');
  if (!/^\s*\/\/\s*shadelab-inputs:/m.test(head)) {
    text = `// shadelab-inputs: ${(st.picked.inputs || []).join(', ')}\n` + text;
  }
  if (!text.endsWith('\n')) text += '\n';
  const url = URL.createObjectURL(new Blob([text], { type: 'text/plain' }));
  const a = el('a', { href: url, download: saveName() + '.glsl' });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
  $('share-status').textContent = `saved ${saveName()}.glsl`;
}

// ---------------------------------------------------------------- permalink: JSON -> deflate-raw -> base64url

function toBase64url(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64url(text) {
  const s = atob(text.replace(/-/g, '+').replace(/_/g, '/'));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

async function pipeBytes(bytes, stream) {
  return new Uint8Array(await new Response(new Blob([bytes]).stream().pipeThrough(stream)).arrayBuffer());
}

async function encodeState(state) {
  const bytes = new TextEncoder().encode(JSON.stringify(state));
  if (typeof CompressionStream !== 'function') return toBase64url(bytes);
  let stream;
  try { stream = new CompressionStream('deflate-raw'); } catch (_) { stream = new CompressionStream('deflate'); }
  return toBase64url(await pipeBytes(bytes, stream));
}

// Tries deflate-raw, then deflate (zlib), then plain JSON.
async function decodeState(text) {
  const bytes = fromBase64url(text);
  for (const format of ['deflate-raw', 'deflate', null]) {
    try {
      const raw = format ? await pipeBytes(bytes, new DecompressionStream(format)) : bytes;
      const s = JSON.parse(new TextDecoder().decode(raw));
      if (s && typeof s === 'object') return s;
    } catch (_) { /* the next format */ }
  }
  throw new Error('unreadable state');
}

function currentState() {
  const s = {
    v: 1, method: st.picked.name, scene: $('scene').value, size: Number($('size').value),
    precision: $('precision').value, budget: $('budget').value, ab: $('ab').checked,
    method_b: $('method-b').value,
  };
  if (isEdited()) s.source = $('source').value;
  return s;
}

async function updatePermalink() {
  if (!st.picked) return;
  const no = ++st.hashNo;
  let enc;
  try { enc = await encodeState(currentState()); } catch (_) { return; }
  if (no !== st.hashNo) return; // a newer state was encoded meanwhile
  st.lastHash = '#s=' + enc;
  history.replaceState(history.state, '', st.lastHash);
}

async function stateFromHash() {
  const m = /^#s=([A-Za-z0-9_-]+)/.exec(location.hash);
  if (!m) return null;
  try {
    return await decodeState(m[1]);
  } catch (_) {
    banner('The link\'s state could not be read: showing the defaults.');
    return null;
  }
}

// Restores a decoded state onto the controls; what this server lacks falls back to the defaults.
function applyState(s) {
  const notes = [];
  const name = st.methods.has(s.method) ? s.method : st.session.defaults.method;
  if (s.method && !st.methods.has(s.method)) notes.push(`method ${s.method} is not offered here`);
  pickMethod(st.methods.has(name) ? name : $('method').options[0].value);
  if (typeof s.source === 'string') $('source').value = normalise(s.source);
  onSourceShown();
  const sceneMsg = restoreScene(s.scene);
  if (hasOption($('size'), String(s.size))) $('size').value = String(s.size);
  if (PRECISIONS.includes(s.precision)) $('precision').value = s.precision;
  if (typeof s.budget === 'string') $('budget').value = s.budget;
  $('ab').checked = !!s.ab;
  if (st.methods.has(s.method_b)) $('method-b').value = s.method_b;
  showAbControls();
  $('scene-error').textContent = sceneMsg;
  $('scene-error').className = 'scene-error' + (sceneMsg ? ' warn' : '');
  if (notes.length) banner(`From the link: ${notes.join('; ')}.`);
}

function restoreScene(value) {
  const def = sceneValue(st.session.defaults.scene);
  if (typeof value === 'string' && value.startsWith('upload:') && !hasOption($('scene'), value)) {
    if (hasOption($('scene'), def)) $('scene').value = def;
    return 'The link used an uploaded mesh, which a link cannot carry: showing the default scene. Drop the mesh file here to see it.';
  }
  if (typeof value === 'string' && hasOption($('scene'), value)) { $('scene').value = value; return ''; }
  if (value) {
    if (hasOption($('scene'), def)) $('scene').value = def;
    return `The link's scene ${value.replace(/^\w+:/, '')} is not offered here: showing the default scene.`;
  }
  return '';
}

async function copyLink() {
  await updatePermalink();
  // The token stays out of a shared link: the cookie (or the recipient's own URL) carries it.
  const u = new URL(location.href);
  u.searchParams.delete('token');
  const text = u.toString();
  try {
    await navigator.clipboard.writeText(text);
    $('share-status').textContent = 'link copied';
  } catch (_) {
    const input = el('input', { type: 'text', readonly: '', value: text, 'aria-label': 'link to copy', class: 'link-out' });
    $('share-status').textContent = 'copy this link: ';
    $('share-status').append(input);
    input.select();
  }
}

// ---------------------------------------------------------------- mesh upload

function headerSafe(name) { return name.replace(/[^\x20-\x7e]/g, '_'); }

async function uploadMesh(file) {
  const box = $('scene-error');
  const show = (text, cls) => { box.textContent = text; box.className = 'scene-error' + (cls ? ' ' + cls : ''); };
  const limit = (st.session.limits || {}).upload_bytes;
  if (limit && file.size > limit) return show(`${file.name}: ${file.size} bytes, over the limit of ${limit}`, 'error');
  show(`uploading ${file.name}…`, '');
  try {
    const r = await fetch(API + 'mesh', {
      method: 'POST', credentials: 'same-origin', body: file,
      headers: { 'X-Shadelab-Filename': headerSafe(file.name), 'Content-Type': 'application/octet-stream' },
    });
    if (!r.ok) throw await errorOf(r);
    const j = await r.json();
    addUploadOption(j);
    const warnings = j.warnings || [];
    show(warnings.length ? `${j.name}: ${warnings.join('; ')}` : '', warnings.length ? 'warn' : '');
    onSettingChange();
  } catch (e) {
    show(`${file.name}: ${e.message}`, 'error');
  }
}

function addUploadOption(j) {
  const select = $('scene');
  let group = $('scene-group-upload');
  if (!group) {
    group = el('optgroup', { label: 'uploads', id: 'scene-group-upload' });
    select.append(group);
  }
  const value = 'upload:' + j.upload;
  let opt = Array.from(select.options).find((o) => o.value === value);
  if (!opt) { opt = el('option', { value }); group.append(opt); }
  opt.textContent = `${j.name} (${j.triangles} triangles, uploaded)`;
  select.value = value;
}

function bindDrop() {
  const hasFiles = (e) => e.dataTransfer && Array.from(e.dataTransfer.types || []).includes('Files');
  let depth = 0;
  document.addEventListener('dragenter', (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth++;
    document.body.classList.add('dragging');
  });
  document.addEventListener('dragover', (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    e.dataTransfer.dropEffect = 'copy';
  });
  document.addEventListener('dragleave', (e) => {
    if (!hasFiles(e)) return;
    if (--depth <= 0) { depth = 0; document.body.classList.remove('dragging'); }
  });
  document.addEventListener('drop', (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth = 0;
    document.body.classList.remove('dragging');
    const file = e.dataTransfer.files[0];
    if (file && st.session) uploadMesh(file);
  });
}

// ---------------------------------------------------------------- wiring

function showAbControls() {
  $('method-b-field').hidden = !$('ab').checked;
}

function bindEvents() {
  const ta = $('source');
  ta.addEventListener('input', onSourceInput);
  ta.addEventListener('keydown', onEditorKey);
  ta.addEventListener('blur', () => { st.tabEscape = false; });
  ta.addEventListener('scroll', () => { $('gutter').scrollTop = ta.scrollTop; });
  $('errors').addEventListener('click', (e) => {
    const li = e.target.closest('li[data-line]');
    if (li) goToLine(Number(li.dataset.line));
  });
  $('errors').addEventListener('keydown', (e) => {
    const li = e.target.closest('li[data-line]');
    if (li && (e.key === 'Enter' || e.key === ' ')) { e.preventDefault(); goToLine(Number(li.dataset.line)); }
  });
  $('method').addEventListener('change', () => {
    pickMethod($('method').value);
    updatePermalink();
    runCheck();
  });
  for (const id of ['scene', 'size', 'method-b']) $(id).addEventListener('change', onSettingChange);
  $('precision').addEventListener('change', onSettingChange);
  $('ab').addEventListener('change', () => { showAbControls(); onSettingChange(); });
  $('budget').addEventListener('input', () => {
    const ok = /^\s*[0-9.eE+-]+\s*(\/\s*[0-9.eE+-]+\s*)?$/.test($('budget').value);
    $('budget').setAttribute('aria-invalid', String(!ok));
    if (ok) debounce('budget', onSettingChange);
  });
  $('mesh-file').addEventListener('change', () => {
    const f = $('mesh-file').files[0];
    if (f) uploadMesh(f);
    $('mesh-file').value = '';
  });
  $('copy-link').addEventListener('click', copyLink);
  $('save-method').addEventListener('click', saveMethodFile);
  const costs = $('costs');
  costs.addEventListener('click', (e) => {
    const row = e.target.closest('.cost-row');
    if (row) showDisasm(row);
  });
  costs.addEventListener('keydown', (e) => {
    const row = e.target.closest('.cost-row');
    if (row && (e.key === 'Enter' || e.key === ' ')) { e.preventDefault(); showDisasm(row); }
  });
  window.addEventListener('hashchange', async () => {
    if (location.hash === st.lastHash || !st.session) return;
    const s = await stateFromHash();
    if (s) { applyState(s); runCheck(); }
  });
  bindDrop();
}

async function init() {
  bindEvents();
  buildStatsRows();
  try {
    const r = await fetch(API + 'choices', { credentials: 'same-origin' });
    if (!r.ok) throw await errorOf(r);
    st.session = await r.json();
  } catch (e) {
    banner(`Could not load the session: ${e.message}. Open the URL that shadelab explore printed (with its token).`);
    setState('error');
    return;
  }
  for (const m of st.session.methods) st.methods.set(m.name, { ...m, source: normalise(m.source || '') });
  if (!st.methods.size) { banner('The server offers no method.'); setState('error'); return; }
  fillMethodSelect($('method'));
  fillMethodSelect($('method-b'));
  fillScenes();
  fillSizes();
  applyDefaults();
  const saved = await stateFromHash();
  if (saved) applyState(saved);
  else { pickMethod($('method').value); showAbControls(); }
  setState('busy');
  updatePermalink();
  runCheck();
}

init();
