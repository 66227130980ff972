// lensray's page: the editor, the controls and the link on the main thread;
// all rendering in worker.js (the library in WebAssembly).
'use strict';

const DEFAULTS = { number: 'fixed', width: 320, height: 240 };
const DEFAULT_PRESET = 'paper-program1';
const FOCUS_GROUP = ['focal_length', 'focus_distance', 'focus_on'];
const APERTURE_GROUP = ['radius', 'f_number'];

const $ = (id) => document.getElementById(id);
const text = $('text'), gutter = $('gutter'), marker = $('marker'), status = $('status');
const canvas = $('picture'), heatCanvas = $('heat');
const worker = new Worker('worker.js');

const state = { ...DEFAULTS, heat: false };
// What the tests and the closing note read: the browser's own timings.
const lensray = (window.lensray = {
  renderId: 0, doneId: 0, errorId: 0, heatId: 0, sceneId: 0,
  timings: null, lastError: null, psnr: null, image: null, camera: null,
  objects: () => ask({ type: 'objects', number: numberIndex() }),
});
let errorLine = 0;

const numberIndex = () => (state.number === 'f32' ? 1 : 0);

// Numbers as the scene format writes them: plain decimals, at most 4 places.
function fmt(x) {
  return String(parseFloat(Number(x).toFixed(4)));
}

// ---- the editor ----

function updateGutter() {
  const n = text.value.split('\n').length;
  let html = '';
  for (let i = 1; i <= n; i++) {
    html += i === errorLine ? `<span class="error" data-line="${i}">${i}</span>\n` : `<span data-line="${i}">${i}</span>\n`;
  }
  gutter.innerHTML = html;
  syncScroll();
}

function syncScroll() {
  gutter.scrollTop = text.scrollTop;
  if (errorLine > 0) {
    marker.hidden = false;
    marker.style.top = `${4 + (errorLine - 1) * 18 - text.scrollTop}px`;
  } else {
    marker.hidden = true;
  }
}

function showError(line, message) {
  errorLine = line;
  status.className = line ? 'error' : 'ok';
  status.textContent = line ? message : 'scene ok';
  // Bring the marked line into view where it is not.
  const top = (line - 1) * 18;
  if (line && (top < text.scrollTop || top > text.scrollTop + text.clientHeight - 36)) text.scrollTop = Math.max(0, top - 90);
  updateGutter();
}

// Writes `keyword value` into the scene text: over the last statement of its
// group (the one in force: the last one stands), else before the first object.
function setKeyword(keyword, value, group = [keyword]) {
  const lines = text.value.split('\n');
  const re = new RegExp(`^\\s*(${group.join('|')})(\\s|#|$)`);
  let last = -1;
  lines.forEach((l, i) => { if (re.test(l)) last = i; });
  const stmt = `${keyword} ${value}`;
  if (last >= 0) {
    const old = lines[last];
    const hash = old.indexOf('#');
    // A comment stays only where it still describes the same keyword.
    const keep = hash >= 0 && old.trim().startsWith(keyword + ' ') ? '  ' + old.slice(hash) : '';
    lines[last] = stmt + keep;
  } else {
    let at = lines.findIndex((l) => /^\s*object(\s|$)/.test(l));
    if (at < 0) at = lines.length;
    lines.splice(at, 0, stmt);
  }
  text.value = lines.join('\n');
  updateGutter();
}

// ---- the link ----

function toBase64Url(s) {
  const bytes = new TextEncoder().encode(s);
  let bin = '';
  for (let i = 0; i < bytes.length; i += 0x8000) bin += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(bin).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(s) {
  const b64 = s.replace(/-/g, '+').replace(/_/g, '/');
  const bin = atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4));
  return new TextDecoder().decode(Uint8Array.from(bin, (c) => c.charCodeAt(0)));
}

function linkHash() {
  const p = [`scene=${toBase64Url(text.value)}`];
  if (state.number !== DEFAULTS.number) p.push(`number=${state.number}`);
  if (state.width !== DEFAULTS.width) p.push(`width=${state.width}`);
  if (state.height !== DEFAULTS.height) p.push(`height=${state.height}`);
  return '#' + p.join('&');
}

// Settings from a link; false where it carries no scene.
function readHash() {
  const p = new URLSearchParams(location.hash.slice(1));
  if (!p.get('scene')) return false;
  try {
    text.value = fromBase64Url(p.get('scene'));
  } catch (e) {
    return false;
  }
  state.number = p.get('number') === 'f32' ? 'f32' : 'fixed';
  const side = (v, d) => { const n = parseInt(v, 10); return n >= 1 && n <= 2048 ? n : d; };
  state.width = side(p.get('width'), DEFAULTS.width);
  state.height = side(p.get('height'), DEFAULTS.height);
  return true;
}

// ---- rendering ----

let pending = 0;
const replies = new Map();
function ask(msg) {
  const id = ++pending;
  return new Promise((resolve) => { replies.set(id, resolve); worker.postMessage({ ...msg, id: -id }); });
}

function render() {
  const id = ++lensray.renderId;
  $('save').disabled = true;
  const hash = linkHash();
  history.replaceState(null, '', hash);
  $('link').href = hash;
  lensray.timings = { id, width: state.width, height: state.height, number: state.number,
    start: performance.now(), firstFrame: null, previewDone: null, done: null, maxMainGap: 0, maxMainGapAfterFirstFrame: 0, ticks: 0,
    longTasks: 0, longestTask: 0, longestTaskAfterFirstFrame: 0, longTaskList: [] };
  worker.postMessage({ type: 'render', id, text: text.value, width: state.width, height: state.height,
    number: numberIndex(), heat: state.heat });
}

// The main thread's longest stall while a render runs: how responsive the page stays.
let lastTick = performance.now();
setInterval(() => {
  const now = performance.now();
  const t = lensray.timings;
  if (t && t.done === null) {
    t.maxMainGap = Math.max(t.maxMainGap, now - lastTick);
    // From the first frame on the worker renders and the page only draws.
    if (t.firstFrame !== null) { t.maxMainGapAfterFirstFrame = Math.max(t.maxMainGapAfterFirstFrame, now - lastTick); t.ticks++; }
  }
  lastTick = now;
}, 10);

// The browser's own long-task entries (main-thread tasks over 50 ms) while a render runs.
if (typeof PerformanceObserver !== 'undefined' && PerformanceObserver.supportedEntryTypes?.includes('longtask')) {
  new PerformanceObserver((list) => {
    const t = lensray.timings;
    if (!t) return;
    for (const e of list.getEntries()) {
      if (e.startTime + e.duration < t.start || (t.done !== null && e.startTime > t.start + t.done)) continue;
      t.longTasks++;
      t.longestTask = Math.max(t.longestTask, e.duration);
      // After the first frame the worker renders and the page only draws.
      if (t.firstFrame !== null && e.startTime >= t.start + t.firstFrame) t.longestTaskAfterFirstFrame = Math.max(t.longestTaskAfterFirstFrame, e.duration);
      t.longTaskList.push([Math.round(e.startTime - t.start), Math.round(e.duration)]);
    }
  }).observe({ type: 'longtask', buffered: false });
}

function draw(target, rgba, w, h) {
  if (target.width !== w || target.height !== h) { target.width = w; target.height = h; }
  target.getContext('2d').putImageData(new ImageData(rgba, w, h), 0, 0);
}

worker.onmessage = (e) => {
  const m = e.data;
  if (m.id < 0) { // a reply to ask()
    const resolve = replies.get(-m.id);
    replies.delete(-m.id);
    if (resolve) resolve(m);
    return;
  }
  if (m.id !== lensray.renderId) return; // an older render's last words
  const t = lensray.timings;
  if (m.type === 'error') {
    showError(m.line, m.message);
    lensray.lastError = { line: m.line, message: m.message };
    lensray.errorId = m.id;
  } else if (m.type === 'scene') {
    showError(0, '');
    lensray.lastError = null;
    lensray.camera = m.camera;
    lensray.sceneId = m.id;
    showCamera(m.camera);
  } else if (m.type === 'frame') {
    draw(canvas, m.rgba, m.width, m.height);
    const now = performance.now() - t.start;
    if (t.firstFrame === null) t.firstFrame = now;
    if (t.previewDone === null && m.passDone) { t.previewDone = now; $('preview-ms').textContent = `${now.toFixed(0)} ms`; }
    $('pass').textContent = `${m.pass + 1}/${m.passes} (${m.samples} samples)`;
    $('rays').textContent = m.rays.toLocaleString('en');
    $('frame-ms').textContent = `${m.ms.toFixed(0)} ms`;
    $('rays-per-s').textContent = m.ms > 0 ? Math.round((m.rays / m.ms) * 1000).toLocaleString('en') : '–';
    if (m.done) {
      t.done = now;
      t.workerMs = m.ms;
      t.rays = m.rays;
      lensray.image = { rgba: m.rgba, width: m.width, height: m.height };
      lensray.doneId = m.id;
      $('save').disabled = false;
    }
  } else if (m.type === 'heat') {
    draw(heatCanvas, m.rgba, canvas.width, canvas.height);
    lensray.psnr = m.psnr;
    lensray.heatId = m.id;
    $('psnr').textContent = Number.isFinite(m.psnr) ? `${m.psnr.toFixed(2)} dB (max ${m.maxDiff} levels)` : '∞ (identical)';
  }
};

// The controls show the parsed scene's camera (except the one being edited).
function showCamera(c) {
  const set = (id, v) => { if (document.activeElement !== $(id)) $(id).value = v; };
  set('focus', fmt(c.focus));
  set('fnumber', c.radius > 0 ? fmt(c.fNumber) : '');
  const blades = String(c.blades);
  if (![...$('blades').options].some((o) => o.value === blades)) $('blades').add(new Option(blades, blades));
  set('blades', blades);
  set('rotation', fmt(c.rotation));
  set('samples', String(c.samples));
}

function showSettings() {
  $('number').value = state.number;
  $('width').value = state.width;
  $('height').value = state.height;
  $('heatmap').checked = state.heat;
  $('heat-figure').hidden = !state.heat;
  $('view').classList.toggle('heat', state.heat);
}

// ---- controls ----

let typing = null;
text.addEventListener('input', () => {
  updateGutter();
  clearTimeout(typing);
  typing = setTimeout(render, 120);
});
text.addEventListener('scroll', syncScroll);

function control(id, keyword, group, valid) {
  $(id).addEventListener('change', () => {
    const v = Number($(id).value);
    if ($(id).value === '' || !valid(v)) return;
    setKeyword(keyword, fmt(v), group);
    render();
  });
}
control('focus', 'focus_distance', FOCUS_GROUP, (v) => v > 0 && v < 32768);
control('fnumber', 'f_number', APERTURE_GROUP, (v) => v > 0 && v < 32768);
control('blades', 'aperture_blades', undefined, (v) => v === 0 || (v >= 3 && v <= 16));
control('rotation', 'aperture_rotation', undefined, (v) => Math.abs(v) < 32768);
control('samples', 'point', undefined, (v) => Number.isInteger(v) && v >= 1 && v <= 65535);

$('number').addEventListener('change', () => { state.number = $('number').value; render(); });
$('heatmap').addEventListener('change', () => { state.heat = $('heatmap').checked; showSettings(); render(); });
for (const id of ['width', 'height']) {
  $(id).addEventListener('change', () => {
    const n = parseInt($(id).value, 10);
    if (n >= 1 && n <= 2048) { state[id] = n; render(); }
  });
}

// Click to focus: the depth of what the pixel's chief ray meets first.
canvas.addEventListener('click', async (e) => {
  const r = canvas.getBoundingClientRect();
  const col = Math.floor(((e.clientX - r.left) * canvas.width) / r.width);
  const row = Math.floor(((e.clientY - r.top) * canvas.height) / r.height);
  const hit = await ask({ type: 'pick', number: numberIndex(), col, row });
  lensray.lastPick = { col, row, depth: hit.depth, object: hit.object };
  if (hit.depth === null || !(hit.depth > 0)) {
    status.className = 'ok';
    status.textContent = `nothing in front of the lens at pixel (${col}, ${row}): focus unchanged`;
    return;
  }
  setKeyword('focus_distance', fmt(hit.depth), FOCUS_GROUP);
  render();
});

$('save').addEventListener('click', () => {
  const img = lensray.image;
  if (!img) return;
  const blob = new Blob([encodePng(img.rgba, img.width, img.height)], { type: 'image/png' });
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = `lensray-${$('preset').value || 'scene'}-${state.number}-${img.width}x${img.height}.png`;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
});

async function loadPreset(name) {
  const r = await fetch(`scenes/${name}.scene`);
  text.value = await r.text();
  text.scrollTop = 0;
  updateGutter();
  render();
}
$('preset').addEventListener('change', () => loadPreset($('preset').value));

window.addEventListener('hashchange', () => {
  if (location.hash !== $('link').getAttribute('href') && readHash()) { showSettings(); updateGutter(); render(); }
});

(async () => {
  const names = (await (await fetch('scenes/index.txt')).text()).split('\n').filter(Boolean);
  for (const n of names) $('preset').add(new Option(n, n));
  if (readHash()) {
    $('preset').value = '';
    showSettings();
    updateGutter();
    render();
  } else {
    $('preset').value = DEFAULT_PRESET;
    showSettings();
    await loadPreset(DEFAULT_PRESET);
  }
  lensray.presets = names;
})();
