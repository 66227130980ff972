// lensray's web page in a real browser: Playwright driving Debian's Chromium,
// headless. Run by scripts/test-all.sh (`npm test` in web/, after
// `bash web/build.sh`); needs /usr/bin/chromium and `npm ci` in web/.
//
// - Every preset, Q16.16 and f32: the page's "Save PNG" is bit for bit the
//   host's `lensray render` of the same scene and size.
// - Click-to-focus on each object of Program 1 (the floor too), of the
//   other presets with a lens and of random scenes, at points chosen by rule
//   from the page's object and depth pass: the clicked object is the
//   sharpest (the least blur radius, against the all-sharp pinhole picture).
// - The rays shown for a frame are the host's count (the adaptive
//   pre-pass's included) plus the preview's.
// - The camera controls write their keywords; the picture is then the
//   host's render of the text in the editor.
// - A typed error: its line is marked with the parser's message.
// - Timings from the page itself (performance.now): reported, not asserted.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { serve } from '../serve.mjs';

const web = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const root = path.dirname(web);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'lensray-web-'));
// The test profile's build (target/debug): the one the host tests already made.
const host = path.join(root, 'target', 'debug', 'lensray');
// Small pictures: every preset twice stays within seconds.
const W = 48, H = 36;

let server, browser, base;

before(async () => {
  execFileSync('cargo', ['build', '--profile', 'test', '-q', '-p', 'lensray-host', '--bin', 'lensray'], { cwd: root, stdio: 'inherit' });
  server = await serve(path.join(web, 'dist'), 0);
  base = `http://127.0.0.1:${server.address().port}/`;
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: ['--no-sandbox'] });
});

after(async () => {
  await browser?.close();
  server?.close();
  fs.rmSync(tmp, { recursive: true, force: true });
});

// ---- helpers ----

// PNG file bytes to {width, height, rgb}: 8-bit RGB or RGBA, any filters.
function decodePng(buf) {
  assert.deepEqual([...buf.subarray(0, 8)], [137, 80, 78, 71, 13, 10, 26, 10], 'PNG signature');
  let at = 8, width, height, colourType;
  const idat = [];
  while (at < buf.length) {
    const len = buf.readUInt32BE(at), type = buf.toString('latin1', at + 4, at + 8);
    const data = buf.subarray(at + 8, at + 8 + len);
    assert.equal(zlib.crc32(buf.subarray(at + 4, at + 8 + len)),
      buf.readUInt32BE(at + 8 + len), `${type} CRC`);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0); height = data.readUInt32BE(4); colourType = data[9];
      assert.equal(data[8], 8, 'bit depth'); assert.equal(data[12], 0, 'no interlace');
    } else if (type === 'IDAT') idat.push(data);
    at += 12 + len;
  }
  const bpp = { 2: 3, 6: 4 }[colourType];
  assert.ok(bpp, `colour type ${colourType}`);
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * bpp, out = Buffer.alloc(width * height * 3), prev = Buffer.alloc(stride), cur = Buffer.alloc(stride);
  for (let y = 0; y < height; y++) {
    const f = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let i = 0; i < stride; i++) {
      const a = i >= bpp ? cur[i - bpp] : 0, b = prev[i], c = i >= bpp ? prev[i - bpp] : 0;
      let p = 0;
      if (f === 1) p = a; else if (f === 2) p = b; else if (f === 3) p = (a + b) >> 1;
      else if (f === 4) { const q = a + b - c, pa = Math.abs(q - a), pb = Math.abs(q - b), pc = Math.abs(q - c); p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c; }
      cur[i] = (line[i] + p) & 255;
    }
    for (let x = 0; x < width; x++) for (let k = 0; k < 3; k++) out[(y * width + x) * 3 + k] = cur[x * bpp + k];
    cur.copy(prev);
  }
  return { width, height, rgb: out };
}

// The host's render, and its rays a pixel (the adaptive pre-pass's
// included), as it prints them: to 2 decimals.
function hostRender(scenePath, w, h, float) {
  const out = path.join(tmp, `host-${path.basename(scenePath)}-${float ? 'f32' : 'fixed'}-${w}x${h}.png`);
  const said = execFileSync(host, ['render', scenePath, '--width', String(w), '--height', String(h), ...(float ? ['--float'] : []), '-o', out],
    { stdio: ['ignore', 'pipe', 'pipe'], encoding: 'utf8' });
  const raysPerPixel = Number(said.match(/^rays per pixel: (\S+)$/m)?.[1]);
  return { ...decodePng(fs.readFileSync(out)), raysPerPixel };
}

const b64url = (s) => Buffer.from(s, 'utf8').toString('base64url');

// Waits until the render started by `action` (or the one running) has finished.
async function rendered(page, action) {
  const before = await page.evaluate(() => window.lensray?.renderId ?? 0);
  if (action) await action();
  await page.waitForFunction((b) => window.lensray && window.lensray.renderId > b &&
    window.lensray.doneId === window.lensray.renderId, before, { timeout: 120000 });
}

async function openLink(hash) {
  const page = await browser.newPage({ viewport: { width: 1300, height: 760 } });
  page.on('pageerror', (e) => { throw e; });
  await rendered(page, () => page.goto(base + hash));
  return page;
}

async function savePng(page) {
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save')]);
  return decodePng(fs.readFileSync(await download.path()));
}

async function pageImage(page) {
  return page.evaluate(() => {
    const { rgba, width, height } = window.lensray.image;
    return { width, height, rgba: Array.from(rgba) };
  });
}

// Sets an input as a user does: a slider's move commits at once; a typed
// number when the field loses focus (one change event, one render).
async function setInput(page, id, v) {
  await page.fill(id, String(v));
  if ((await page.getAttribute(id, 'type')) !== 'range') await page.locator(id).blur();
}

const presets = fs.readdirSync(path.join(root, 'scenes')).filter((f) => f.endsWith('.scene')).sort();

// ---- tests ----

test('every preset saves the host render bit for bit, Q16.16 and f32', async () => {
  assert.ok(presets.length >= 10, 'scenes/ has the presets');
  for (const file of presets) {
    const scenePath = path.join(root, 'scenes', file);
    const text = fs.readFileSync(scenePath, 'utf8');
    // The shareable link: the scene in base64url and the size.
    const page = await openLink(`#scene=${b64url(text)}&width=${W}&height=${H}`);
    assert.equal(await page.inputValue('#text'), text, `${file}: the link carries the scene`);
    const fixed = await savePng(page);
    await rendered(page, () => page.selectOption('#number', 'f32'));
    assert.match(page.url(), /[#&]number=f32(&|$)/, 'the link says f32');
    const float = await savePng(page);
    for (const [got, isFloat] of [[fixed, false], [float, true]]) {
      const want = hostRender(scenePath, W, H, isFloat);
      assert.equal(got.width, W); assert.equal(got.height, H);
      const diff = got.rgb.findIndex((v, i) => v !== want.rgb[i]);
      assert.equal(diff, -1, `${file} ${isFloat ? 'f32' : 'Q16.16'}: first differing byte ${diff}`);
    }
    await page.close();
  }
});

test('a link reopens the same picture, and the heat map gives the PSNR of the two number types', async () => {
  const scenePath = path.join(root, 'scenes', 'paper-program1.scene');
  const text = fs.readFileSync(scenePath, 'utf8');
  const page = await openLink(`#scene=${b64url(text)}&width=64&height=40`);
  await page.check('#heatmap');
  await page.waitForFunction(() => window.lensray.heatId === window.lensray.renderId, null, { timeout: 120000 });
  const psnr = await page.evaluate(() => window.lensray.psnr);
  const a = hostRender(scenePath, 64, 40, false), b = hostRender(scenePath, 64, 40, true);
  let se = 0;
  for (let i = 0; i < a.rgb.length; i++) se += (a.rgb[i] - b.rgb[i]) ** 2;
  const want = se === 0 ? Infinity : 10 * Math.log10((255 * 255) / (se / a.rgb.length));
  assert.ok(Math.abs(psnr - want) < 1e-9 || psnr === want, `page PSNR ${psnr} vs host images ${want}`);
  // The rays shown are the frame's: the preview's (8 x 5 blocks of 8 at one
  // ray), the pixels' and the adaptive pre-pass's (thousands of rays here,
  // well beyond the host's rounding to 1/100 a pixel).
  const shownRays = async () => {
    const t = await page.evaluate(() => window.lensray.timings);
    assert.equal(Number((await page.textContent('#rays')).replace(/,/g, '')), t.rays, 'the rays shown');
    return t.rays;
  };
  const raysMatch = (got, host, what) => assert.ok(Math.abs(got - 40 - host.raysPerPixel * 64 * 40) <= 0.005 * 64 * 40 + 1e-6,
    `${what}: page ${got} rays, host ${host.raysPerPixel} a pixel at 64x40 (and 40 preview rays)`);
  raysMatch(await shownRays(), a, 'Q16.16');
  // The page's own link, opened anew, gives the same pixels.
  const link = await page.getAttribute('#link', 'href');
  const first = await pageImage(page);
  const again = await openLink(link);
  assert.deepEqual(await pageImage(again), first);
  await again.close();
  // In f32 the link says so, and reopens in f32.
  await rendered(page, () => page.selectOption('#number', 'f32'));
  raysMatch(await shownRays(), b, 'f32');
  const floatLink = await page.getAttribute('#link', 'href');
  assert.match(floatLink, /^#scene=[A-Za-z0-9_-]+&number=f32&width=64&height=40$/);
  const floatPage = await openLink(floatLink);
  assert.equal(await floatPage.inputValue('#number'), 'f32');
  assert.deepEqual(await pageImage(floatPage), await pageImage(page));
  assert.notDeepEqual(await pageImage(floatPage), first, 'Q16.16 and f32 differ somewhere in Program 1');
  await floatPage.close();
  await page.close();
});

test('every camera control writes its keyword, and the picture is the host render of the text', async () => {
  const file = 'paper-program1.scene';
  const text = fs.readFileSync(path.join(root, 'scenes', file), 'utf8');
  const page = await openLink(`#scene=${b64url(text)}&width=${W}&height=${H}`);
  const set = async (id, v, select) => rendered(page, () => (select ? page.selectOption(id, String(v)) : setInput(page, id, v)));
  await set('#blades', 6, true);
  await set('#rotation', 30);
  await set('#samples', 16);
  await set('#fnumber', 2.5);
  await set('#focus', 9.5);
  const edited = await page.inputValue('#text');
  for (const re of [/^aperture_blades 6$/m, /^aperture_rotation 30$/m, /^point 16$/m, /^f_number 2.5$/m, /^focus_distance 9.5$/m]) {
    assert.match(edited, re);
  }
  // The group's old statement is replaced, not left to contradict it.
  assert.doesNotMatch(edited, /^(radius|point 70)\b/m);
  const scenePath = path.join(tmp, 'controls.scene');
  fs.writeFileSync(scenePath, edited);
  const got = await savePng(page), want = hostRender(scenePath, W, H, false);
  assert.equal(got.rgb.findIndex((v, i) => v !== want.rgb[i]), -1, 'the saved PNG is the host render of the edited text');
  // The controls show what the scene says.
  assert.equal(await page.inputValue('#blades'), '6');
  assert.equal(await page.inputValue('#samples'), '16');
  await page.close();
});

// ---- click-to-focus: how sharp each object is ----
//
// An object's sharpness is measured where it is looked at, by one rule for
// every object: its region is its own pixels near its click point (within
// an eighth of the width, at a depth within 10 % of the click's), less those
// within 8 pixels of a nearer object, whose blur may spread over them. Its
// blur there is the radius (in pixels) of the disc blur of the all-sharp
// pinhole picture that best matches the picture over that region: a size,
// like the circle of confusion, so a finely checkered floor and a smooth gold
// sphere compare fairly. (A share of squared error does not: a fine checker
// loses most of its contrast to a blur of one pixel, a smooth sphere little
// to one of eight.)

// Blur radii tried: 0 to 12 pixels in quarters.
const RADII = Array.from({ length: 49 }, (_, i) => i / 4);

// A disc of radius r as taps (dx, dy, weight): each pixel's share of it,
// from 4 x 4 points in the pixel; r = 0 is the pixel alone.
function disc(r) {
  const taps = [];
  const R = Math.ceil(r + 0.5);
  for (let dy = -R; dy <= R; dy++) {
    for (let dx = -R; dx <= R; dx++) {
      let n = 0;
      for (let i = 0; i < 16; i++) {
        const x = dx - 0.5 + ((i % 4) + 0.5) / 4, y = dy - 0.5 + (Math.floor(i / 4) + 0.5) / 4;
        if (x * x + y * y <= r * r) n++;
      }
      if (n > 0) taps.push([dx, dy, n]);
    }
  }
  return taps.length ? taps : [[0, 0, 1]];
}

// The pinhole picture blurred by each disc of RADII, at the listed pixels
// (RGB, 3 floats a pixel; taps outside the picture are left out).
function discBlurs(sharp, w, h, pixels) {
  return RADII.map((r) => {
    const taps = disc(r), out = new Float32Array(w * h * 3);
    for (const i of pixels) {
      const x = i % w, y = (i - x) / w, s = [0, 0, 0];
      let sw = 0;
      for (const [dx, dy, wt] of taps) {
        const u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= w || v >= h) continue;
        for (let c = 0; c < 3; c++) s[c] += wt * sharp[(v * w + u) * 4 + c];
        sw += wt;
      }
      for (let c = 0; c < 3; c++) out[i * 3 + c] = s[c] / sw;
    }
    return out;
  });
}

// The blur radius (pixels) that best explains a picture over a region.
function blurRadius(img, blurs, region) {
  let best = 0, bestErr = Infinity;
  blurs.forEach((b, k) => {
    let err = 0;
    for (const i of region) for (let c = 0; c < 3; c++) err += (img[i * 4 + c] - b[i * 3 + c]) ** 2;
    if (err < bestErr) { bestErr = err; best = RADII[k]; }
  });
  return best;
}

// Squared difference from the pinhole picture over a region.
function sharpError(img, sharp, region) {
  let err = 0;
  for (const i of region) for (let c = 0; c < 3; c++) err += (img[i * 4 + c] - sharp[i * 4 + c]) ** 2;
  return err;
}

// Opens a scene (a preset's file, or `text`) at f/`fNumber`, picks a click point on every object it shows
// by rule, clicks each, and returns for each click the blur radius of every
// object (and the objects left out, with why).
async function clickEachObject(file, { w = 160, h = 120, fNumber = 2, samples = null, text = null } = {}) {
  text ??= fs.readFileSync(path.join(root, 'scenes', file), 'utf8');
  // The all-sharp reference: the same scene through a pinhole (radius 0 stands last).
  const page = await openLink(`#scene=${b64url(text.replace(/\n?$/, '\n') + 'radius 0\n')}&width=${w}&height=${h}`);
  const sharp = (await pageImage(page)).rgba;
  const setControl = (id, v) => rendered(page, () => setInput(page, id, v));
  if (samples) await setControl('#samples', samples);
  // A wide lens (the f-number control), so focus shows at this size.
  await setControl('#fnumber', fNumber);
  assert.match(await page.inputValue('#text'), new RegExp(`^f_number ${fNumber}$`, 'm'), 'the f-number control writes f_number');
  await setControl('#focus', 1);
  assert.match(await page.inputValue('#text'), /^focus_distance 1$/m, 'the focus control writes focus_distance');
  const { map, depth } = await page.evaluate(async () => {
    const r = await window.lensray.objects();
    return { map: Array.from(r.map), depth: Array.from(r.depth) };
  });
  const at = (x, y) => (x >= 0 && y >= 0 && x < w && y < h ? map[y * w + x] : -1);
  const size = (id) => map.filter((v) => v === id).length;
  const skipped = [];
  // Objects in view over at least 1/500 of the picture.
  const ids = [...new Set(map)].filter((i) => i > 0).sort((p, q) => p - q)
    .filter((id) => size(id) * 500 >= w * h || !skipped.push({ id, why: `${size(id)} pixels in view` }));
  // The click point: the object's pixel nearest its centroid among those
  // inside it (every pixel within 2 is the object's), where its surface is
  // resolved (a 10 % step in depth takes 3 pixels or more: not a plane seen
  // edge-on near the horizon, where its checker is finer than a pixel), and
  // at a depth 1.25 times or more apart from the click depths of the objects
  // chosen before, smallest objects first: a plane runs through every depth,
  // and a click on it at another object's depth focuses both.
  const chosen = [];
  const R = Math.floor(w / 8);
  const apart = (a, b) => Math.max(a, b) >= 1.25 * Math.min(a, b);
  const resolved = (x, y) => {
    const d = depth[y * w + x];
    return [[1, 0], [-1, 0], [0, 1], [0, -1]].every(([dx, dy]) => Math.abs(depth[(y + dy) * w + x + dx] - d) * 30 <= d);
  };
  // Pixels within 8 of a nearer object: its blur may spread over them, so
  // they tell about its focus, not this object's.
  const shaded = new Uint8Array(w * h);
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const i = y * w + x;
      if (map[i] === 0) continue;
      for (let dy = -8; dy <= 8 && !shaded[i]; dy++) {
        for (let dx = -8; dx <= 8; dx++) {
          const o = at(x + dx, y + dy), j = (y + dy) * w + x + dx;
          if (o > 0 && o !== map[i] && depth[j] < depth[i]) { shaded[i] = 1; break; }
        }
      }
    }
  }
  for (const id of [...ids].sort((p, q) => size(p) - size(q) || p - q)) {
    let sx = 0, sy = 0, n = 0;
    map.forEach((v, i) => { if (v === id) { sx += i % w; sy += Math.floor(i / w); n++; } });
    let best = -1, bd = Infinity;
    map.forEach((v, i) => {
      if (v !== id || !chosen.every((c) => apart(depth[i], c.d))) return;
      const x = i % w, y = Math.floor(i / w);
      for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) if (at(x + dx, y + dy) !== id) return;
      if (!resolved(x, y) || shaded[i]) return;
      const d = (x - sx / n) ** 2 + (y - sy / n) ** 2;
      if (d < bd) { bd = d; best = i; }
    });
    if (best < 0) { skipped.push({ id, why: 'no resolved pixel inside it at a depth apart from the others' }); continue; }
    const cx = best % w, cy = Math.floor(best / w), d = depth[best];
    const region = [];
    for (let y = Math.max(0, cy - R); y <= Math.min(h - 1, cy + R); y++) {
      for (let x = Math.max(0, cx - R); x <= Math.min(w - 1, cx + R); x++) {
        const i = y * w + x;
        if (map[i] === id && Math.abs(depth[i] - d) <= 0.1 * d && !shaded[i]) region.push(i);
      }
    }
    chosen.push({ id, cx, cy, d, region });
  }
  const targets = chosen.sort((p, q) => p.id - q.id);
  // One object apart in depth has no other to be sharper than.
  if (targets.length < 2) { await page.close(); return { targets, clicks: [], skipped }; }
  const blurs = discBlurs(sharp, w, h, [...new Set(targets.flatMap((t) => t.region))]);
  const box = await page.locator('#picture').boundingBox();
  const clicks = [];
  for (const t of targets) {
    await rendered(page, () => page.mouse.click(box.x + ((t.cx + 0.5) * box.width) / w, box.y + ((t.cy + 0.5) * box.height) / h));
    const pick = await page.evaluate(() => window.lensray.lastPick);
    assert.equal(pick.object, t.id, `${file}: the click lands on object ${t.id}`);
    // The last statement of the focus group stands: the one the click wrote.
    const focus = Number([...(await page.inputValue('#text')).matchAll(/^(?:focus_distance|focus_on|focal_length) (\S+)/gm)].at(-1)?.[1]);
    assert.match([...(await page.inputValue('#text')).matchAll(/^(focus_distance|focus_on|focal_length) /gm)].at(-1)[1], /^focus_distance$/);
    assert.ok(Math.abs(focus - pick.depth) < 1e-4, `focus_distance ${focus} written for depth ${pick.depth}`);
    const img = (await pageImage(page)).rgba;
    clicks.push({ id: t.id, depth: pick.depth, radii: targets.map((o) => blurRadius(img, blurs, o.region)),
      errors: targets.map((o) => sharpError(img, sharp, o.region)) });
    console.log(`# ${file}: clicked object ${t.id} at (${t.cx}, ${t.cy}), depth ${pick.depth.toFixed(3)}: blur radius (px) of objects ` +
      targets.map((o, k) => `${o.id}: ${clicks.at(-1).radii[k]}`).join(', '));
  }
  await page.close();
  return { targets, clicks, skipped };
}

// Each click makes its object the sharpest of those measured (the least blur
// radius, strictly), and each object is closest to its pinhole picture when
// clicked (its own pixels, compared across the clicks).
function assertClickedIsSharpest(file, { targets, clicks }) {
  clicks.forEach((c, k) => {
    const others = c.radii.filter((_, j) => j !== k);
    assert.ok(c.radii[k] < Math.min(...others),
      `${file}: clicked object ${c.id}, blur radii of objects ${targets.map((t) => t.id)}: ${c.radii}`);
    const own = clicks.map((o) => o.errors[k]);
    assert.equal(Math.min(...own), c.errors[k], `${file}: object ${c.id} is nearest its pinhole picture when clicked: ${own}`);
  });
}

test('click-to-focus makes each object of Program 1 the sharpest', async () => {
  const file = 'paper-program1.scene';
  const r = await clickEachObject(file);
  assert.deepEqual(r.skipped, [], 'every object is clicked');
  assert.deepEqual(r.targets.map((t) => t.id), [1, 2, 3, 4], 'floor, cube, sphere, cone all in view and clicked');
  assertClickedIsSharpest(file, r);
});

test('click-to-focus makes the clicked object the sharpest in the other presets with a lens', async () => {
  let clicked = 0;
  // A scene that differs from one clicked before only in what the test sets
  // (lens, focus, samples) or in comments gives the same clicks: once is enough.
  const set = /^\s*(radius|f_number|focal_length|focus_distance|focus_on|point)(\s|$)/;
  const key = (text) => text.split('\n').map((l) => l.replace(/#.*/, '').trim()).filter((l) => l && !set.test(l)).join('\n');
  const seen = new Set([key(fs.readFileSync(path.join(root, 'scenes', 'paper-program1.scene'), 'utf8'))]);
  for (const file of presets) {
    const text = fs.readFileSync(path.join(root, 'scenes', file), 'utf8');
    // A lens (not a pinhole) and two objects or more; fewer samples than a
    // preset's finest, for time: the blur is the lens's, not the noise's.
    if (/^\s*radius\s+0(\.0*)?\s*(#.*)?$/m.test(text) || (text.match(/^\s*object\s/gm) || []).length < 2) continue;
    if (seen.has(key(text))) { console.log(`# ${file}: the clicks of a scene clicked before`); continue; }
    seen.add(key(text));
    const r = await clickEachObject(file, { samples: 32 });
    for (const s of r.skipped) console.log(`# ${file}: object ${s.id} not clicked: ${s.why}`);
    // A scene whose objects all stand at one depth has no sharpest object.
    if (r.targets.length < 2) { console.log(`# ${file}: fewer than two objects apart in depth: no sharpest one`); continue; }
    assertClickedIsSharpest(file, r);
    clicked += r.targets.length;
  }
  assert.ok(clicked >= 7, `${clicked} objects clicked`);
});

// A scene of Program 1's camera and lights: a checkered floor and `n`
// objects of random shapes, sizes and colours at random places, from a seed.
function randomScene(seed, n) {
  let x = seed >>> 0;
  const rnd = () => { x = (Math.imul(x, 1664525) + 1013904223) >>> 0; return x / 2 ** 32; };
  const num = (v) => String(Math.round(v * 1000) / 1000);
  const lines = ['width 10', 'aspect_ratio 1.33', 'image_distance 8', 'focal_length 4', 'look 0 0 -1', 'up 0 1 0',
    'point 32', 'radius 0.2', 'ambient_light 1 1 1', 'light_position 2 3 0', 'light_intensity 1 1 1',
    'light_position -3 2 -2', 'light_intensity 0.8 0.8 0.8', '',
    'object plane', 'Ka 0.1 0.1 0.1', `Kd ${num(rnd())} ${num(rnd())} ${num(rnd())}`, 'Ks 0.2 0.2 0.2', 'shine 5',
    `texture ${num(0.3 + rnd() * 0.7)}`, 'total_transformation 2', `rotate x ${num(-80 - rnd() * 10)}`, `translate 0 ${num(-2 - rnd())} 0`];
  for (let k = 0; k < n; k++) {
    const shape = ['sphere', 'cube', 'cone', 'cylinder'][Math.floor(rnd() * 4)];
    const depth = 4 + rnd() * 14, s = 0.4 + rnd() * 0.5;
    lines.push('', `object ${shape}`, 'Ka 0.1 0.1 0.1', `Kd ${num(rnd())} ${num(rnd())} ${num(rnd())}`, 'Ks 0.3 0.3 0.3', 'shine 8',
      'total_transformation 3', `scale ${num(s)} ${num(s)} ${num(s)}`, `rotate y ${num(rnd() * 90)}`,
      `translate ${num((rnd() - 0.5) * 0.6 * depth)} ${num(-1.5 + rnd() * 1.5)} ${num(-depth)}`);
  }
  return lines.join('\n') + '\n';
}

test('click-to-focus makes the clicked object the sharpest in random scenes', async () => {
  let clicked = 0;
  for (const seed of [1, 2, 3, 4, 5, 6]) {
    const name = `random scene ${seed}`;
    const r = await clickEachObject(name, { text: randomScene(seed, 3) });
    for (const s of r.skipped) console.log(`# ${name}: object ${s.id} not clicked: ${s.why}`);
    if (r.targets.length < 2) { console.log(`# ${name}: fewer than two objects apart in depth: no sharpest one`); continue; }
    assertClickedIsSharpest(name, r);
    clicked += r.targets.length;
  }
  assert.ok(clicked >= 10, `${clicked} objects clicked`);
});

test('a typed error marks its line with the parser message', async () => {
  const text = fs.readFileSync(path.join(root, 'scenes', 'paper-program1.scene'), 'utf8');
  const page = await openLink(`#scene=${b64url(text)}&width=${W}&height=${H}`);
  const lines = text.split('\n');
  // Errors of several kinds on lines spread over the file.
  const cases = [[3, 'image_distance 8 8', /image_distance takes 1 value/], [12, 'light_intensity 1 x 1', /not a number/],
    [20, 'Kd 0 0.5', /Kd takes 3 value/], [41, 'translate 0 -1', /translate takes 3 value/]];
  for (const [line, bad, message] of cases) {
    const edited = lines.map((l, i) => (i === line - 1 ? bad : l)).join('\n');
    await page.fill('#text', edited);
    await page.waitForFunction((n) => window.lensray.lastError?.line === n && window.lensray.errorId === window.lensray.renderId, line);
    assert.match(await page.textContent('#status'), new RegExp(`^line ${line}: `));
    assert.match(await page.textContent('#status'), message);
    assert.equal(await page.getAttribute(`#gutter [data-line="${line}"]`, 'class'), 'error');
    assert.equal(await page.locator('#gutter .error').count(), 1, 'only that line is marked');
    assert.equal(await page.isVisible('#marker'), true);
  }
  // Typed key by key at the end of the file: an unknown keyword on a new last line.
  await page.fill('#text', text);
  await page.waitForFunction(() => window.lensray.doneId === window.lensray.renderId && !window.lensray.lastError);
  assert.equal(await page.locator('#gutter .error').count(), 0, 'a good scene marks nothing');
  await page.focus('#text');
  await page.keyboard.press('Control+End');
  await page.keyboard.type('ligth_position 1 2 3');
  const n = text.split('\n').length;
  await page.waitForFunction((k) => window.lensray.lastError?.line === k, n);
  assert.equal(await page.textContent('#status'), `line ${n}: unknown keyword "ligth_position"`);
  assert.equal(await page.getAttribute(`#gutter [data-line="${n}"]`, 'class'), 'error');
  await page.close();
});

// The timings printed (medians over LENSRAY_TIMING_RUNS page loads, 1 by
// default): `cd web && LENSRAY_TIMING_RUNS=5 node --test --test-name-pattern='first preview' tests/`.
// Two renders a run: the one the page starts as it loads, and one an edit
// of the scene text starts in the loaded page.
test('Program 1 at 320x240: the first preview shows before the full render ends (timings reported)', async () => {
  const runs = Math.max(1, Number(process.env.LENSRAY_TIMING_RUNS) || 1);
  const all = { load: [], edit: [] };
  const line = (t) => `first frame ${t.firstFrame.toFixed(0)} ms, preview pass done ${t.previewDone.toFixed(0)} ms, ` +
    `full render ${t.done.toFixed(0)} ms (worker ${t.workerMs.toFixed(0)} ms, ${(t.rays / t.workerMs / 1000).toFixed(2)} Mrays/s); ` +
    `main thread: ${t.longTasks} long tasks (> 50 ms; [start, ms]: ${JSON.stringify(t.longTaskList)}), longest ${t.longestTask.toFixed(0)} ms, ` +
    `${t.longestTaskAfterFirstFrame.toFixed(0)} ms after the first frame; longest gap of a 10 ms timer ` +
    `${t.maxMainGap.toFixed(0)} ms, ${t.maxMainGapAfterFirstFrame.toFixed(0)} ms after the first frame (${t.ticks} ticks)`;
  for (let k = 0; k < runs; k++) {
    const page = await browser.newPage({ viewport: { width: 1300, height: 760 } });
    for (const kind of ['load', 'edit']) {
      if (kind === 'load') {
        await rendered(page, () => page.goto(base));
      } else {
        // An empty line typed at the end: the same picture, rendered anew.
        await rendered(page, async () => { await page.focus('#text'); await page.keyboard.press('Control+End'); await page.keyboard.press('Enter'); });
      }
      // Long-task entries come after their task: give the observer a moment.
      await page.waitForTimeout(200);
      const t = await page.evaluate(() => window.lensray.timings);
      assert.equal(`${t.width}x${t.height}`, '320x240');
      assert.equal(t.number, 'fixed');
      assert.ok(t.firstFrame !== null && t.previewDone !== null && t.previewDone < t.done, JSON.stringify(t));
      // The main thread ran its 10 ms timer all through the render.
      assert.ok(t.ticks > 0, 'the main thread ran while the worker rendered');
      all[kind].push(t);
      console.log(`# run ${k + 1}, render on ${kind}: Program 1 320x240 Q16.16: ${line(t)}`);
    }
    if (k === runs - 1 && process.env.LENSRAY_SCREENSHOTS) {
      await page.screenshot({ path: path.join(process.env.LENSRAY_SCREENSHOTS, 'web-page.png') });
    }
    await page.close();
  }
  for (const kind of ['load', 'edit']) {
    const median = (f) => { const v = all[kind].map(f).sort((p, q) => p - q); return v[(v.length - 1) >> 1].toFixed(0); };
    console.log(`# median of ${runs}, render on ${kind}: first frame ${median((t) => t.firstFrame)} ms, preview pass done ${median((t) => t.previewDone)} ms, ` +
      `full render ${median((t) => t.done)} ms, longest main-thread task ${median((t) => t.longestTask)} ms ` +
      `(${median((t) => t.longestTaskAfterFirstFrame)} ms after the first frame), longest timer gap ${median((t) => t.maxMainGap)} ms`);
  }
});
