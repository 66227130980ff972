// lensray's render worker: runs the library compiled to WebAssembly
// (lensray.wasm, web/wasm/) off the main thread, a few grid rows at a time,
// and posts the picture after each slice so the page shows it sharpening.
//
// Messages in:  {type:'render', id, text, width, height, number, heat}
//               {type:'pick', id, col, row}   (click-to-focus query)
//               {type:'objects', id}          (object under every pixel)
// Messages out: {type:'error', id, line, message}
//               {type:'scene', id, camera}
//               {type:'frame', id, rgba, pass, passes, rays, ms, done}
//               {type:'heat', id, rgba, psnr, maxDiff}
//               {type:'pick', id, depth, object}, {type:'objects', id, map, depth}
'use strict';

const FIXED = 0, FLOAT = 1;
// Work between two looks at the message queue and two posted frames.
const SLICE_MS = 40;
const FIRST_STEP = 8, PREVIEW_SAMPLES = 1;

let wasm = null;
let current = 0; // id of the render in progress; a newer request cancels it
let size = { width: 0, height: 0 };
const queue = [];

const ready = fetch('lensray.wasm')
  .then((r) => r.arrayBuffer())
  .then((b) => WebAssembly.instantiate(b, {}))
  .then((m) => { wasm = m.instance.exports; });

// Yields to the event loop without setTimeout's clamp, so new messages
// (a newer render, a click) are seen between slices.
const channel = new MessageChannel();
const waiting = [];
channel.port1.onmessage = () => waiting.shift()();
const yieldNow = () => new Promise((r) => { waiting.push(r); channel.port2.postMessage(0); });

function bytes(ptr, len) {
  return new Uint8Array(wasm.memory.buffer, ptr, len);
}

function parse(text) {
  const utf8 = new TextEncoder().encode(text);
  bytes(wasm.lr_text_buffer(utf8.length), utf8.length).set(utf8);
  const line = wasm.lr_parse();
  const message = new TextDecoder().decode(bytes(wasm.lr_message(), wasm.lr_message_len()));
  return { line, message };
}

function image(number) {
  const len = size.width * size.height * 4;
  return new Uint8ClampedArray(bytes(wasm.lr_image(number), len)); // a copy
}

// Renders every pass in `number`; posts frames when `show`. Returns false
// when a newer request cancelled it.
async function renderAll(id, number, show) {
  // The frame's time includes its set-up (lr_setup runs the adaptive
  // pre-pass of both number types), its rays this type's pre-pass's.
  const t0 = performance.now();
  const passes = wasm.lr_setup(size.width, size.height, FIRST_STEP, PREVIEW_SAMPLES);
  let rays = wasm.lr_survey_rays(number);
  for (let p = 0; p < passes; p++) {
    const rows = wasm.lr_pass_rows(p);
    let g = 0;
    while (g < rows) {
      const start = performance.now();
      // Grows the slice row by row until it has taken SLICE_MS.
      while (g < rows && performance.now() - start < SLICE_MS) {
        rays += wasm.lr_render(number, p, g, g + 1);
        g++;
      }
      const passDone = g >= rows;
      if (show) {
        const rgba = image(number);
        const done = passDone && p === passes - 1;
        postMessage({ type: 'frame', id, rgba, width: size.width, height: size.height, pass: p, passes,
                      passDone, samples: wasm.lr_pass_samples(p), rays, ms: performance.now() - t0, done },
                    [rgba.buffer]);
      }
      await yieldNow();
      if (current !== id) return false;
    }
  }
  return true;
}

// Error heat map between the two number types, and its PSNR (8-bit RGB).
function heat() {
  const a = image(FIXED), b = image(FLOAT);
  const out = new Uint8ClampedArray(a.length);
  let se = 0, maxDiff = 0;
  for (let i = 0; i < a.length; i += 4) {
    let m = 0;
    for (let c = 0; c < 3; c++) {
      const d = a[i + c] - b[i + c];
      se += d * d;
      m = Math.max(m, Math.abs(d));
    }
    maxDiff = Math.max(maxDiff, m);
    // 0 black; 1-3 levels dark to bright red; 4-15 red to yellow; 16+ white.
    const v = m === 0 ? [0, 0, 0] : m < 4 ? [80 + 58 * m, 0, 0] : m < 16 ? [255, (m - 3) * 21, 0] : [255, 255, 255];
    out.set([v[0], v[1], v[2], 255], i);
  }
  const mse = se / ((a.length / 4) * 3);
  const psnr = mse === 0 ? Infinity : 10 * Math.log10((255 * 255) / mse);
  return { rgba: out, psnr, maxDiff };
}

async function render(msg) {
  const { id } = msg;
  const { line, message } = parse(msg.text);
  if (line !== 0) {
    postMessage({ type: 'error', id, line, message });
    return;
  }
  size = { width: msg.width, height: msg.height };
  const camera = {};
  ['focus', 'fNumber', 'radius', 'blades', 'rotation', 'samples', 'aspect', 'objects']
    .forEach((k, i) => { camera[k] = wasm.lr_camera(i); });
  postMessage({ type: 'scene', id, camera });
  if (!(await renderAll(id, msg.number, true))) return;
  if (msg.heat) {
    const other = msg.number === FIXED ? FLOAT : FIXED;
    // The shown image stays in its buffer; the other type renders into its own.
    if (!(await renderOther(id, other))) return;
    const h = heat();
    postMessage({ type: 'heat', id, rgba: h.rgba, psnr: h.psnr, maxDiff: h.maxDiff }, [h.rgba.buffer]);
  }
}

// The other number type's full picture, without resetting the shown one
// (lr_setup clears both images, so the shown one is restored afterwards).
async function renderOther(id, number) {
  const shown = number === FIXED ? FLOAT : FIXED;
  const keep = image(shown);
  const ok = await renderAll(id, number, false);
  if (ok) bytes(wasm.lr_image(shown), keep.length).set(keep);
  return ok;
}

function pick(msg) {
  const depth = wasm.lr_depth_at(msg.number, msg.col, msg.row);
  const object = wasm.lr_object_at(msg.number, msg.col, msg.row);
  postMessage({ type: 'pick', id: msg.id, depth: Number.isNaN(depth) ? null : depth, object });
}

function objects(msg) {
  const map = new Uint8Array(size.width * size.height);
  const depth = new Float64Array(size.width * size.height);
  for (let r = 0; r < size.height; r++) {
    for (let c = 0; c < size.width; c++) {
      map[r * size.width + c] = wasm.lr_object_at(msg.number, c, r);
      depth[r * size.width + c] = wasm.lr_depth_at(msg.number, c, r);
    }
  }
  postMessage({ type: 'objects', id: msg.id, map, depth, width: size.width, height: size.height },
              [map.buffer, depth.buffer]);
}

onmessage = async (e) => {
  await ready;
  const msg = e.data;
  if (msg.type === 'render') {
    current = msg.id;
    // Only the newest render runs; an older one stops at its next slice.
    queue.length = 0;
    queue.push(msg);
    await yieldNow();
    const next = queue.shift();
    if (next && next.id === current) await render(next);
  } else if (msg.type === 'pick') {
    pick(msg);
  } else if (msg.type === 'objects') {
    objects(msg);
  }
};
