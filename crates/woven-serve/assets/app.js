// The woven explorer's page: a material editor and live views, talking to `woven serve`'s API
// (docs/serve.md). Vanilla JavaScript and canvas; nothing is loaded from elsewhere.
'use strict';

// ---- Parameters: the material file's keys (crates/woven/src/material.rs). Slider ranges are
// the useful part of each valid range; typed-in values go to the server as they are, and the
// library's validation answers for them.
const FIBER_ROUGH = [
  { key: 'fiber.eta', label: 'η, refractive index', min: 1, max: 2.5, step: 0.01 },
  { key: 'fiber.roughness', label: 'σh/τ, roughness', min: 0.005, max: 1, step: 0.005 },
  { key: 'fiber.diffuse', label: 'ρ0, diffuse albedo', min: 0, max: 0.99, step: 0.01 },
];
const FIBER_HTSG = [
  { key: 'fiber.eta', label: 'η, refractive index', min: 1, max: 2.5, step: 0.01 },
  { key: 'fiber.sigma_h_um', label: 'σh, µm', min: 0.01, max: 2, step: 0.01 },
  { key: 'fiber.tau_um', label: 'τ, µm', min: 0.1, max: 20, step: 0.1 },
  { key: 'fiber.diffuse', label: 'ρ0, diffuse albedo', min: 0, max: 0.99, step: 0.01 },
];
const YARN = [
  { key: 'yarn.lateral_length', label: 'L, lateral length (arc radii)', min: 0, max: 40, step: 0.1 },
  { key: 'yarn.slope_mean', label: 'μ, mean lateral slope (rad)', min: 0, max: 1.5707963, step: 0.01 },
  { key: 'yarn.slope_std', label: 'σ, slope spread (rad)', min: 0, max: 3.14159265, step: 0.01 },
  { key: 'yarn.interreflection', label: 'ħ, interreflection', min: 0, max: 1, step: 0.01 },
  { key: 'yarn.interreflection_albedo', label: 'ρ, interreflection albedo', min: 0, max: 1, step: 0.01 },
  { key: 'yarn.twist_std', label: 'σt, twist spread (rad)', min: 0, max: 1.5, step: 0.01 },
];
const WEAVE_FRACTION = [
  { key: 'weave.weft_fraction', label: 'γ, weft fraction', min: 0, max: 1, step: 0.01 },
];
const YARN_DEFAULTS = { lateral_length: 4, slope_mean: 0.4, slope_std: 0.5, interreflection: 0.2,
  interreflection_albedo: 0.5, twist_std: 0, isotropic: false };

const $ = (id) => document.getElementById(id);
const state = {
  material: null, presets: [], thetaDeg: 45, phiDeg: 0,
  hemi: null, plane: null, gonio: null, data: null, patternView: null,
  views: null, preview: null, check: null, compare: null, fit: null,
};
const tab = Math.random().toString(36).slice(2, 10);

// ---- Paths into the material object.
function getKey(path) {
  return path.split('.').reduce((o, k) => (o == null ? undefined : o[k]), state.material);
}
function setKey(path, value) {
  const parts = path.split('.');
  let o = state.material;
  for (const k of parts.slice(0, -1)) { if (o[k] == null) o[k] = {}; o = o[k]; }
  o[parts[parts.length - 1]] = value;
}
function deleteKey(path) {
  const parts = path.split('.');
  const parent = parts.length > 1 ? getKey(parts.slice(0, -1).join('.')) : state.material;
  if (parent) delete parent[parts[parts.length - 1]];
}

// ---- The editor.
function sliderRow(p) {
  const id = p.key.replace(/\./g, '-');
  const div = document.createElement('div');
  div.className = 'param';
  div.innerHTML = `<div class="head"><span>${p.label}</span><code>${p.key.split('.')[1]}</code></div>
    <div class="controls"><input type="range" id="${id}-range" min="${p.min}" max="${p.max}" step="${p.step}" aria-label="${p.key}">
    <input type="number" id="${id}" data-key="${p.key}" step="any" aria-label="${p.key} value"></div>
    <div class="field-error" data-error-for="${p.key}"></div>`;
  const range = div.querySelector('input[type=range]');
  const num = div.querySelector('input[type=number]');
  range.addEventListener('input', () => {
    num.value = range.value;
    setKey(p.key, Number(range.value));
    changed();
  });
  num.addEventListener('change', () => {
    const v = Number(num.value);
    // An empty or non-numeric entry goes to the server as text, so its error names the key.
    setKey(p.key, num.value.trim() === '' || !Number.isFinite(v) ? num.value : v);
    if (Number.isFinite(v)) range.value = v;
    changed();
  });
  return div;
}

function buildSliders() {
  const fiber = $('fiber-sliders');
  fiber.replaceChildren(...(getKey('fiber.model') === 'htsg' ? FIBER_HTSG : FIBER_ROUGH).map(sliderRow));
  $('yarn-sliders').replaceChildren(...YARN.map(sliderRow));
  $('weave-fraction').replaceChildren(...WEAVE_FRACTION.map(sliderRow));
}

function fillEditor() {
  buildSliders();
  for (const p of [...FIBER_ROUGH, ...FIBER_HTSG, ...YARN, ...WEAVE_FRACTION]) {
    const id = p.key.replace(/\./g, '-');
    const num = $(id);
    if (!num) continue;
    const v = getKey(p.key);
    num.value = v ?? '';
    if (typeof v === 'number') $(id + '-range').value = v;
  }
  $('fiber-model').value = getKey('fiber.model') || 'rough';
  $('fiber-normalization').value = getKey('fiber.normalization') || 'paper';
  const yarn = state.material.yarn != null;
  $('has-yarn').checked = yarn;
  $('yarn-isotropic').checked = !!getKey('yarn.isotropic');
  for (const el of document.querySelectorAll('#yarn-params input:not(#has-yarn), #weave-params select, #weave-params input')) {
    el.disabled = !yarn;
  }
  const weave = state.material.weave;
  const mode = weave == null ? 'none' : weave.pattern !== undefined ? 'pattern' : 'fraction';
  $('weave-mode').value = mode;
  $('weave-fraction').hidden = mode !== 'fraction';
  $('weave-pattern').hidden = mode !== 'pattern';
  if (mode === 'pattern') {
    const p = weave.pattern;
    const names = [...$('pattern-name').options].map((o) => o.value);
    if (typeof p === 'string' && !names.includes(p)) $('pattern-name').add(new Option(p, p));
    $('pattern-name').value = typeof p === 'string' ? p : 'matrix';
  }
}

function wireEditor() {
  $('fiber-model').addEventListener('change', (e) => {
    const m = e.target.value;
    setKey('fiber.model', m);
    if (m === 'htsg') {
      deleteKey('fiber.roughness');
      setKey('fiber.sigma_h_um', 0.2); setKey('fiber.tau_um', 2.0);
    } else {
      deleteKey('fiber.sigma_h_um'); deleteKey('fiber.tau_um');
      setKey('fiber.roughness', 0.1);
    }
    fillEditor(); changed();
  });
  $('fiber-normalization').addEventListener('change', (e) => { setKey('fiber.normalization', e.target.value); changed(); });
  $('has-yarn').addEventListener('change', (e) => {
    if (e.target.checked) state.material.yarn = { ...YARN_DEFAULTS };
    else { delete state.material.yarn; delete state.material.weave; }
    fillEditor(); changed();
  });
  $('yarn-isotropic').addEventListener('change', (e) => { setKey('yarn.isotropic', e.target.checked); changed(); });
  $('weave-mode').addEventListener('change', (e) => {
    const m = e.target.value;
    if (m === 'none') delete state.material.weave;
    else if (m === 'fraction') state.material.weave = { weft_fraction: 0.5 };
    else state.material.weave = { pattern: 'plain' };
    fillEditor(); changed();
  });
  $('pattern-name').addEventListener('change', (e) => {
    if (e.target.value !== 'matrix') { state.material.weave = { pattern: e.target.value }; changed(); }
  });
  $('wif-file').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    clearErrors();
    try {
      const r = await fetch('api/wif', { method: 'POST', body: await file.text() });
      const j = await r.json();
      if (!r.ok) { showError(j, 'weave.pattern'); return; }
      state.material.weave = { pattern: j.matrix };
      const names = [...$('pattern-name').options].map((o) => o.value);
      if (!names.includes('matrix')) $('pattern-name').add(new Option('(matrix: ' + file.name + ')', 'matrix'));
      $('pattern-name').value = 'matrix';
      changed();
    } catch (err) { showError({ error: String(err) }); }
  });
  $('preset').addEventListener('change', (e) => loadPreset(e.target.value));
}

function loadPreset(name) {
  const p = state.presets.find((x) => x.name === name);
  if (!p) return;
  state.material = structuredClone(p.material);
  fillEditor();
  changed();
}

// ---- Errors: next to the field the server names, else in the banner.
function clearErrors() {
  for (const el of document.querySelectorAll('.field-error')) el.textContent = '';
  for (const el of document.querySelectorAll('.invalid')) el.classList.remove('invalid');
  $('error').hidden = true;
}
function showError(body, fallbackField) {
  const field = body.field || fallbackField;
  let slot = null;
  if (field) {
    // `weave.pattern[2][3]` belongs to `weave.pattern`.
    for (let f = field; f && !slot; f = f.replace(/(\[[^\]]*\]|\.[^.[]*)$/, '')) {
      slot = document.querySelector(`[data-error-for="${CSS.escape(f)}"]`);
      if (f.indexOf('.') < 0 && f.indexOf('[') < 0) break;
    }
  }
  if (slot) {
    slot.textContent = body.value !== undefined ? `${body.value}: expected ${body.expected}` : body.error;
    const input = document.querySelector(`[data-key="${CSS.escape(field)}"]`);
    if (input) input.classList.add('invalid');
  } else {
    $('error').textContent = body.error;
    $('error').hidden = false;
  }
}

// ---- Requests: each view aborts its own superseded request; the channel tells the server too.
async function stream(url, body, controller, onMessage) {
  const r = await fetch(url, {
    method: 'POST', headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body), signal: controller.signal,
  });
  if (!r.ok) {
    let e;
    try { e = await r.json(); } catch { e = { error: `${r.status} ${r.statusText}` }; }
    const err = new Error(e.error); err.api = e; throw err;
  }
  const reader = r.body.getReader();
  const decoder = new TextDecoder();
  let buffer = '';
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += decoder.decode(value, { stream: true });
    let i;
    while ((i = buffer.indexOf('\n')) >= 0) {
      const line = buffer.slice(0, i);
      buffer = buffer.slice(i + 1);
      if (line.trim()) onMessage(JSON.parse(line));
    }
  }
}
function restart(slot) {
  if (state[slot]) state[slot].abort();
  state[slot] = new AbortController();
  return state[slot];
}
const isAbort = (e) => e.name === 'AbortError';

// ---- What a change triggers: the views at once (every animation frame at most), the material's
// TOML and pattern, and, after a pause, the rendered preview and the data comparison.
let frame = 0, slowTimer = 0;
function changed() {
  state.gonioFresh = false;
  if (!frame) frame = requestAnimationFrame(() => { frame = 0; refreshViews(); checkMaterial(); });
  clearTimeout(slowTimer);
  slowTimer = setTimeout(() => { refreshPreview(); if (state.data) refreshCompare(); }, 350);
}

async function checkMaterial() {
  const c = restart('check');
  try {
    const r = await fetch('api/material', {
      method: 'POST', headers: { 'content-type': 'application/json' },
      body: JSON.stringify({ material: state.material }), signal: c.signal,
    });
    const j = await r.json();
    if (!r.ok) return;
    $('toml-view').textContent = j.toml;
    $('summary').textContent = j.summary;
    state.patternView = j.pattern;
    drawPattern();
    $('pattern-info').textContent = j.pattern ? `γ = ${j.weft_fraction.toFixed(3)}${j.pattern.name ? ' · ' + j.pattern.name : ''} · ${j.pattern.matrix.length}×${j.pattern.matrix[0].length}` : '';
  } catch (e) { if (!isAbort(e)) throw e; }
}

async function refreshViews(which) {
  const c = restart('views');
  const started = performance.now();
  const views = $('views');
  const sent = JSON.stringify(state.material);
  views.dataset.busy = '1';
  $('views-status').textContent = 'computing…';
  try {
    await stream('api/views', {
      material: JSON.parse(sent), theta_i_deg: state.thetaDeg, phi_i_deg: state.phiDeg,
      views: which, channel: 'views-' + tab,
    }, c, (m) => {
      if (m.kind === 'progress') {
        $('views-progress').value = m.done / m.total;
        $('views-status').textContent = `computing… ${m.done} / ${m.total} evaluations`;
      } else if (m.kind === 'plane') {
        clearErrors();
        state.plane = { points: m.points, theta: state.thetaDeg, phi: state.phiDeg };
        drawPlane(); fillPlaneTable();
      } else if (m.kind === 'hemisphere') {
        clearErrors();
        state.hemi = { ...m, theta: state.thetaDeg, phi: state.phiDeg };
        drawHemisphere();
      } else if (m.kind === 'gonio') {
        state.gonio = m; state.gonioFresh = true; drawGonio();
      } else if (m.kind === 'done') {
        $('views-progress').value = 1;
        const ms = performance.now() - started;
        $('views-status').textContent = `updated in ${ms.toFixed(0)} ms (server ${m.ms.toFixed(0)} ms)`;
        views.dataset.lastMs = ms.toFixed(1);
        views.dataset.material = sent;
        views.dataset.generation = String(Number(views.dataset.generation) + 1);
        views.dataset.busy = '0';
      }
    });
  } catch (e) {
    if (isAbort(e)) return;
    views.dataset.busy = '0';
    $('views-status').textContent = 'not updated: see the error';
    clearErrors();
    showError(e.api || { error: String(e) });
    views.dataset.error = (e.api && e.api.field) || 'error';
  }
}

// ---- Drawing: a colour map of our own (dark blue → magenta → orange → pale yellow).
const STOPS = [[0, [13, 8, 60]], [0.3, [110, 30, 130]], [0.6, [220, 80, 70]], [0.85, [250, 170, 60]], [1, [252, 245, 190]]];
function colour(t) {
  t = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0));
  for (let i = 1; i < STOPS.length; i++) {
    if (t <= STOPS[i][0]) {
      const [t0, a] = STOPS[i - 1], [t1, b] = STOPS[i];
      const u = (t - t0) / (t1 - t0);
      return a.map((x, k) => Math.round(x + (b[k] - x) * u));
    }
  }
  return STOPS[STOPS.length - 1][1];
}

// Bilinear read of the hemisphere grid (as woven::figures::hemisphere::Grid::sample).
function sampleGrid(g, x, y) {
  const n = g.n;
  const fx = Math.min(n - 1, Math.max(0, (x + 1) * 0.5 * n - 0.5));
  const fy = Math.min(n - 1, Math.max(0, (1 - y) * 0.5 * n - 0.5));
  const c0 = Math.floor(fx), r0 = Math.floor(fy);
  const c1 = Math.min(c0 + 1, n - 1), r1 = Math.min(r0 + 1, n - 1);
  const tx = fx - c0, ty = fy - r0;
  const at = (r, c) => { const v = g.values[r * n + c]; return v == null ? 0 : v; };
  const top = at(r0, c0) * (1 - tx) + at(r0, c1) * tx;
  const bottom = at(r1, c0) * (1 - tx) + at(r1, c1) * tx;
  return top * (1 - ty) + bottom * ty;
}

const HEMI = { cx: 140, cy: 150, r: 130 };
function drawHemisphere() {
  const cv = $('hemi-canvas'), ctx = cv.getContext('2d');
  ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, cv.width, cv.height);
  const g = state.hemi;
  if (!g) return;
  const log = $('hemi-log').checked;
  const max = g.max > 0 ? g.max : 1, floor = max * 1e-3;
  const pos = (f) => (log ? Math.log10(Math.max(f, floor) / floor) / 3 : f / max);
  const size = 2 * HEMI.r, img = ctx.createImageData(size, size);
  for (let j = 0; j < size; j++) {
    for (let i = 0; i < size; i++) {
      const x = (i + 0.5) / HEMI.r - 1, y = 1 - (j + 0.5) / HEMI.r;
      if (x * x + y * y > 1) continue;
      const [r, gg, b] = colour(pos(sampleGrid(g, x, y)));
      const k = 4 * (j * size + i);
      img.data[k] = r; img.data[k + 1] = gg; img.data[k + 2] = b; img.data[k + 3] = 255;
    }
  }
  ctx.putImageData(img, HEMI.cx - HEMI.r, HEMI.cy - HEMI.r);
  // Rings at θr = 30°, 60°; the axes; the light (dot) and the mirror direction (ring).
  ctx.strokeStyle = 'rgba(255,255,255,0.5)'; ctx.lineWidth = 1;
  for (const t of [30, 60, 90]) {
    ctx.beginPath(); ctx.arc(HEMI.cx, HEMI.cy, HEMI.r * Math.sin(t * Math.PI / 180), 0, 2 * Math.PI); ctx.stroke();
  }
  ctx.fillStyle = '#333'; ctx.font = '11px sans-serif';
  ctx.fillText('weft x →', HEMI.cx + HEMI.r - 40, HEMI.cy + HEMI.r + 14);
  ctx.fillText('warp y ↑', HEMI.cx - HEMI.r, HEMI.cy - HEMI.r - 4);
  const st = Math.sin(g.theta * Math.PI / 180), ph = g.phi * Math.PI / 180;
  const lx = HEMI.cx + HEMI.r * st * Math.cos(ph), ly = HEMI.cy - HEMI.r * st * Math.sin(ph);
  ctx.fillStyle = '#fff'; ctx.strokeStyle = '#000';
  ctx.beginPath(); ctx.arc(lx, ly, 5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
  ctx.strokeStyle = '#fff'; ctx.lineWidth = 2;
  ctx.beginPath(); ctx.arc(2 * HEMI.cx - lx, 2 * HEMI.cy - ly, 6, 0, 2 * Math.PI); ctx.stroke();
  // Colour bar.
  const bx = 310, by = 20, bh = 260;
  for (let k = 0; k < bh; k++) {
    const [r, gg, b] = colour(1 - k / bh);
    ctx.fillStyle = `rgb(${r},${gg},${b})`; ctx.fillRect(bx, by + k, 14, 1);
  }
  ctx.fillStyle = '#333';
  const ticks = log ? [0, 1, 2, 3] : [0, 0.25, 0.5, 0.75, 1];
  for (const t of ticks) {
    const frac = log ? t / 3 : t;
    const v = log ? floor * 10 ** t : max * t;
    ctx.fillText(fmt(v), bx + 18, by + bh - frac * bh + 4);
  }
  $('incidence').textContent = `light at θi = ${g.theta.toFixed(1)}°, φi = ${g.phi.toFixed(1)}° (grid ${g.n}²; max ${fmt(g.max)} sr⁻¹)`;
}

function fmt(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  return a >= 1000 || a < 0.01 ? v.toExponential(1) : v.toPrecision(3).replace(/\.?0+$/, '');
}
function niceStep(x) {
  const d = 10 ** Math.floor(Math.log10(x));
  for (const m of [1, 2, 2.5, 5, 10]) if (m * d >= x) return m * d;
  return 10 * d;
}

// A line plot: series of {label, colour, points: [[x, y]], dash, dots}.
function linePlot(cv, { series, xlabel, ylabel, xmin, xmax, xstep }) {
  const ctx = cv.getContext('2d');
  const W = cv.width, H = cv.height, L = 56, R = 10, T = 10, B = 36;
  ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, W, H);
  let ymax = 0;
  for (const s of series) for (const [, y] of s.points) if (Number.isFinite(y)) ymax = Math.max(ymax, y);
  if (!(ymax > 0)) ymax = 1;
  const ystep = niceStep(ymax / 5);
  ymax = Math.ceil(ymax / ystep - 1e-9) * ystep;
  const X = (x) => L + (x - xmin) / (xmax - xmin) * (W - L - R);
  const Y = (y) => H - B - y / ymax * (H - T - B);
  ctx.strokeStyle = '#ddd'; ctx.fillStyle = '#333'; ctx.font = '11px sans-serif'; ctx.lineWidth = 1;
  ctx.textAlign = 'right';
  for (let y = 0; y <= ymax + 1e-12; y += ystep) {
    ctx.beginPath(); ctx.moveTo(L, Y(y)); ctx.lineTo(W - R, Y(y)); ctx.stroke();
    ctx.fillText(fmt(y), L - 4, Y(y) + 4);
  }
  ctx.textAlign = 'center';
  for (let x = Math.ceil(xmin / xstep) * xstep; x <= xmax + 1e-9; x += xstep) {
    ctx.beginPath(); ctx.moveTo(X(x), T); ctx.lineTo(X(x), H - B); ctx.stroke();
    ctx.fillText(fmt(x), X(x), H - B + 14);
  }
  ctx.fillText(xlabel, (L + W - R) / 2, H - 6);
  ctx.save(); ctx.translate(12, (T + H - B) / 2); ctx.rotate(-Math.PI / 2); ctx.fillText(ylabel, 0, 0); ctx.restore();
  ctx.strokeStyle = '#333'; ctx.strokeRect(L, T, W - L - R, H - T - B);
  let ly = T + 14;
  for (const s of series) {
    ctx.strokeStyle = s.colour; ctx.fillStyle = s.colour; ctx.lineWidth = 1.6;
    ctx.setLineDash(s.dash || []);
    if (s.dots) {
      for (const [x, y] of s.points) { ctx.beginPath(); ctx.arc(X(x), Y(y), 2.5, 0, 2 * Math.PI); ctx.fill(); }
    } else {
      ctx.beginPath();
      s.points.forEach(([x, y], i) => (i ? ctx.lineTo(X(x), Y(y)) : ctx.moveTo(X(x), Y(y))));
      ctx.stroke();
    }
    ctx.setLineDash([]);
    ctx.textAlign = 'right';
    ctx.fillText(s.label, W - R - 8, ly); ly += 14;
  }
  ctx.textAlign = 'start';
}

function drawPlane() {
  const p = state.plane;
  if (!p) return;
  linePlot($('plane-canvas'), {
    series: [{ label: `θi = ${p.theta.toFixed(1)}°, φi = ${p.phi.toFixed(1)}°`, colour: '#1f6fb2', points: p.points.map((q) => [q.x_deg, q.f]) }],
    xlabel: 'view angle (°): + on the mirror side', ylabel: 'f (sr⁻¹)', xmin: -90, xmax: 90, xstep: 30,
  });
}

// The plotted numbers, for tests and for anyone who inspects the page.
function fillPlaneTable() {
  const p = state.plane, t = $('plane-table');
  const ti = p.theta * Math.PI / 180, pi = p.phi * Math.PI / 180;
  const rows = ['<tr><th>theta_i</th><th>phi_i</th><th>theta_r</th><th>phi_r</th><th>f</th></tr>'];
  for (const q of p.points) {
    rows.push(`<tr data-theta-i="${ti}" data-phi-i="${pi}" data-theta-r="${q.theta_r}" data-phi-r="${q.phi_r}" data-f="${q.f}"><td>${ti}</td><td>${pi}</td><td>${q.theta_r}</td><td>${q.phi_r}</td><td>${q.f}</td></tr>`);
  }
  t.innerHTML = rows.join('');
}

const GONIO_COLOURS = ['#1f6fb2', '#2e8b57', '#c0392b'];
function drawGonio() {
  const g = state.gonio;
  linePlot($('gonio-canvas'), {
    series: g.azimuths.map(([, name], k) => ({ label: name, colour: GONIO_COLOURS[k], points: g.tilts_deg.map((t, i) => [t, g.radiance[k][i]]) })),
    xlabel: 'sample tilt t (°); θi = 45° + t, θr = 45° − t', ylabel: 'f cos θi (sr⁻¹)', xmin: -45, xmax: 45, xstep: 15,
  });
}

function drawPattern() {
  const cv = $('pattern-canvas'), ctx = cv.getContext('2d');
  ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, cv.width, cv.height);
  const p = state.patternView;
  if (!p) return;
  const m = p.matrix, rows = m.length, cols = m[0].length;
  // At least two repeats, at most 48 cells across.
  const reps = Math.max(1, Math.min(4, Math.floor(48 / Math.max(rows, cols))));
  const nr = Math.min(48, rows * reps), nc = Math.min(48, cols * reps);
  const cell = Math.floor(cv.width / Math.max(nr, nc)) || 1;
  for (let r = 0; r < nr; r++) {
    for (let c = 0; c < nc; c++) {
      // Row 0 (the first pick) at the bottom: the warp runs up the drawing.
      ctx.fillStyle = m[r % rows][c % cols] ? '#e8c170' : '#3b5b8c';
      ctx.fillRect(c * cell, cv.height - (r + 1) * cell, cell - (cell > 3 ? 1 : 0), cell - (cell > 3 ? 1 : 0));
    }
  }
}

// ---- The rendered preview.
async function refreshPreview() {
  const c = restart('preview');
  const cv = $('preview-canvas'), ctx = cv.getContext('2d');
  const status = $('preview-status');
  status.textContent = 'tabulating…';
  cv.dataset.pass = '0';
  try {
    await stream('api/preview', {
      material: state.material, shape: $('preview-shape').value, size: 100, passes: 64, channel: 'preview-' + tab,
    }, c, (m) => {
      if (m.kind === 'table') status.textContent = `tabulating the yarn: ${Math.round(100 * m.done / Math.max(1, m.total))} %`;
      else if (m.kind === 'image') {
        const bytes = Uint8Array.from(atob(m.rgb), (ch) => ch.charCodeAt(0));
        const img = ctx.createImageData(m.width, m.height);
        for (let i = 0; i < m.width * m.height; i++) {
          img.data[4 * i] = bytes[3 * i]; img.data[4 * i + 1] = bytes[3 * i + 1];
          img.data[4 * i + 2] = bytes[3 * i + 2]; img.data[4 * i + 3] = 255;
        }
        createImageBitmap(img).then((bmp) => {
          ctx.imageSmoothingEnabled = true;
          ctx.drawImage(bmp, 0, 0, cv.width, cv.height);
        });
        status.textContent = `${m.pass} samples per pixel (${(m.ms / 1000).toFixed(1)} s)`;
        cv.dataset.pass = m.pass;
      } else if (m.error) status.textContent = m.error;
    });
  } catch (e) {
    if (!isAbort(e)) status.textContent = 'not rendered: ' + (e.api ? e.api.error : e);
  }
}

// ---- Measured data.
const dataSource = () => state.data.dataset ? { dataset: state.data.dataset } : { csv: state.data.text, name: state.data.name };

// The cloth model fitted to the data from the current material (woven fit --model cloth); the
// fitted material replaces the editor's.
async function runFit() {
  if (!state.data) return;
  const c = restart('fit');
  const status = $('fit-status');
  delete status.dataset.logRms;
  status.textContent = 'fitting…';
  $('data-fit').disabled = true;
  try {
    await stream('api/fit', { material: state.material, ...dataSource(), channel: 'fit-' + tab }, c, (m) => {
      if (m.kind === 'progress') status.textContent = `fitting… step ${m.done} of ${m.total}`;
      else if (m.kind === 'failed') status.textContent = 'not fitted: ' + m.error;
      else if (m.kind === 'fit') {
        state.material = m.material;
        fillEditor();
        changed();
        const warn = m.warnings.length ? `; ${m.warnings.length} warning(s): ${m.warnings.join(' ')}` : '';
        status.textContent = `fitted: RMS log error ${m.rms_log.toFixed(3)}, relative RMS ${(100 * m.relative_rms).toFixed(1)} %${warn}`;
        status.dataset.logRms = m.rms_log;
      }
    });
  } catch (e) {
    if (!isAbort(e)) status.textContent = 'not fitted: ' + (e.api ? e.api.error : e);
  } finally {
    $('data-fit').disabled = false;
  }
}

async function refreshCompare() {
  const c = restart('compare');
  const status = $('data-status');
  status.textContent = `comparing ${state.data.name}…`;
  try {
    await stream('api/compare', { material: state.material, ...dataSource(), channel: 'compare-' + tab }, c, (m) => {
      if (m.kind === 'progress') status.textContent = `comparing… ${m.done} / ${m.total} rows`;
      else if (m.kind === 'compare') {
        state.data.result = m;
        drawData();
        const e = m.error;
        const rel = state.data.relative ? ' (relatively calibrated: the error includes an unknown scale)' : '';
        status.textContent = `${state.data.name}${rel}: ${e.rows} rows; RMS error ${(100 * e.relative_rms).toFixed(1)} % of the mean value; RMS log ratio ${e.log_rms.toFixed(3)} (typical factor ${Math.exp(e.log_rms).toFixed(2)}×)`;
        status.dataset.relativeRms = e.relative_rms;
        status.dataset.logRms = e.log_rms;
        status.dataset.rows = e.rows;
      }
    });
  } catch (e) {
    if (isAbort(e)) return;
    status.textContent = 'not compared: ' + (e.api ? e.api.error : e);
    status.dataset.error = '1';
  }
}

function drawData() {
  const r = state.data.result;
  linePlot($('data-canvas'), {
    series: [
      { label: 'model', colour: '#1f6fb2', points: r.model.map((v, i) => [i, v]) },
      { label: 'measured', colour: '#c0392b', dots: true, points: r.samples.map((s, i) => [i, s.value]) },
    ],
    xlabel: 'row of the file', ylabel: 'f (sr⁻¹)', xmin: 0, xmax: Math.max(1, r.samples.length - 1), xstep: niceStep(Math.max(1, r.samples.length) / 8),
  });
}

// ---- Downloads.
function download(name, blob) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob); a.download = name;
  document.body.append(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
function csvOf(kind) {
  const lines = [];
  if (kind === 'plane' && state.plane) {
    const ti = state.plane.theta * Math.PI / 180, pi = state.plane.phi * Math.PI / 180;
    lines.push('theta_i,phi_i,theta_r,phi_r,value');
    for (const q of state.plane.points) lines.push([ti, pi, q.theta_r, q.phi_r, q.f].join(','));
  } else if (kind === 'hemisphere' && state.hemi) {
    const g = state.hemi, ti = g.theta * Math.PI / 180, pi = g.phi * Math.PI / 180;
    lines.push('theta_i,phi_i,theta_r,phi_r,value');
    for (let row = 0; row < g.n; row++) {
      for (let col = 0; col < g.n; col++) {
        const x = -1 + (2 * col + 1) / g.n, y = 1 - (2 * row + 1) / g.n, r = Math.hypot(x, y);
        const v = g.values[row * g.n + col];
        if (r > 1 || v == null) continue;
        lines.push([ti, pi, Math.asin(r), ((Math.atan2(y, x) % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI), v].join(','));
      }
    }
  } else if (kind === 'gonio' && state.gonio) {
    const g = state.gonio;
    lines.push('azimuth_deg,tilt_deg,theta_i,phi_i,theta_r,phi_r,radiance');
    g.azimuths.forEach(([a], k) => g.tilts_deg.forEach((t, i) => {
      const p = a * Math.PI / 180;
      lines.push([a, t, (45 + t) * Math.PI / 180, p, (45 - t) * Math.PI / 180, p + Math.PI, g.radiance[k][i]].join(','));
    }));
  } else if (kind === 'data' && state.data && state.data.result) {
    const r = state.data.result;
    lines.push('theta_i,phi_i,theta_r,phi_r,measured,model');
    r.samples.forEach((s, i) => lines.push([s.theta_i, s.phi_i, s.theta_r, s.phi_r, s.value, r.model[i]].join(',')));
  } else return null;
  return lines.join('\n') + '\n';
}
function wireDownloads() {
  for (const b of document.querySelectorAll('[data-csv]')) {
    b.addEventListener('click', () => {
      const text = csvOf(b.dataset.csv);
      if (text) download(`woven-${b.dataset.csv}.csv`, new Blob([text], { type: 'text/csv' }));
    });
  }
  for (const b of document.querySelectorAll('[data-png]')) {
    b.addEventListener('click', () => $(b.dataset.png).toBlob((blob) => download(`woven-${b.dataset.png.replace('-canvas', '')}.png`, blob)));
  }
  $('download-toml').addEventListener('click', () => {
    const name = (state.material.name || 'material').replace(/[^A-Za-z0-9_-]+/g, '-');
    download(`${name}.toml`, new Blob([$('toml-view').textContent], { type: 'application/toml' }));
  });
}

// ---- Start.
async function start() {
  const r = await fetch('api/presets');
  const j = await r.json();
  state.presets = j.presets;
  for (const p of j.presets) $('preset').add(new Option(p.name, p.name));
  for (const n of j.patterns) $('pattern-name').add(new Option(n, n));
  wireEditor();
  wireDownloads();
  $('hemi-log').addEventListener('change', drawHemisphere);
  $('preview-shape').addEventListener('change', refreshPreview);
  $('hemi-canvas').addEventListener('click', (e) => {
    const cv = e.currentTarget, rect = cv.getBoundingClientRect();
    const px = (e.clientX - rect.left) * cv.width / rect.width, py = (e.clientY - rect.top) * cv.height / rect.height;
    const x = (px - HEMI.cx) / HEMI.r, y = (HEMI.cy - py) / HEMI.r, rr = Math.hypot(x, y);
    if (rr > 1) return;
    state.thetaDeg = Math.min(89, Math.asin(rr) * 180 / Math.PI);
    state.phiDeg = rr > 0 ? Math.atan2(y, x) * 180 / Math.PI : 0;
    refreshViews(state.gonioFresh ? ['hemisphere', 'plane'] : undefined);
  });
  $('data-file').addEventListener('change', async (e) => {
    const f = e.target.files[0];
    if (!f) return;
    delete $('data-status').dataset.error;
    delete $('data-status').dataset.rows;
    state.data = { name: f.name, text: await f.text() };
    $('data-bundled').value = '';
    $('data-fit').disabled = false;
    refreshCompare();
  });
  const ds = await (await fetch('api/datasets')).json();
  const relative = {};
  for (const d of ds.datasets) {
    relative[d.name] = d.relative;
    $('data-bundled').add(new Option(`${d.name} (${d.family}, ${d.samples} rows)`, d.name));
  }
  $('data-fit').addEventListener('click', runFit);
  $('data-bundled').addEventListener('change', (e) => {
    const name = e.target.value;
    if (!name) return;
    delete $('data-status').dataset.error;
    delete $('data-status').dataset.rows;
    state.data = { name, dataset: name, relative: relative[name] };
    $('data-fit').disabled = false;
    refreshCompare();
  });
  loadPreset(j.presets[0].name);
}
start();
