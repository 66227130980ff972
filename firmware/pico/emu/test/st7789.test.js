// The ST7789 model: it shows what a good stream draws, in every MADCTL
// orientation, with inversion and colour order as the glass shows them, and
// refuses each kind of bad stream. Run: `npm test` (node --test).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { ST7789, PanelError, COLUMNS, ROWS } from '../st7789.js';

/** A panel on a clock the test moves, past the reset's 5 ms. */
function panel(options = {}) {
  const clock = { t: 0 };
  const p = new ST7789({ nanos: () => clock.t, ...options });
  clock.t = 10e6;
  p.clock = clock;
  return p;
}

const cmd = (p, code, ...params) => {
  p.byte(code, false);
  for (const b of params) p.byte(b, true);
};

/** The start-up mipidsi sends, then the display on. */
function init(p, { madctl = 0, colmod = 0x55, invert = true } = {}) {
  cmd(p, 0x11); // SLPOUT
  p.clock.t += 10e6;
  cmd(p, 0x36, madctl);
  cmd(p, invert ? 0x21 : 0x20);
  cmd(p, 0x3a, colmod);
  cmd(p, 0x29); // DISPON
}

const window = (p, x0, y0, x1, y1) => {
  cmd(p, 0x2a, x0 >> 8, x0 & 0xff, x1 >> 8, x1 & 0xff);
  cmd(p, 0x2b, y0 >> 8, y0 & 0xff, y1 >> 8, y1 & 0xff);
};

const pixels = (p, words) => {
  p.byte(0x2c, false);
  for (const w of words) {
    p.byte(w >> 8, true);
    p.byte(w & 0xff, true);
  }
};

/** Fills the whole frame memory (portrait) with one word. */
function clear(p, word) {
  const madctl = p.madctl;
  cmd(p, 0x36, 0);
  window(p, 0, 0, COLUMNS - 1, ROWS - 1);
  pixels(p, new Array(COLUMNS * ROWS).fill(word));
  cmd(p, 0x36, madctl);
}

test('a window of pixels lands where MADCTL puts it, for all eight orientations', () => {
  // The reference: mipidsi's MemoryMapping (swap rows and columns, then
  // reverse the frame memory's columns (MX) and rows (MY)) on a 3x2 block at
  // the window's origin; values 1..6 in the order the counters run.
  for (let madctl = 0; madctl < 8; madctl++) {
    const bits = madctl << 5; // MV, MX, MY
    const p = panel();
    init(p, { madctl: bits });
    clear(p, 0);
    window(p, 0, 0, 2, 1);
    pixels(p, [1, 2, 3, 4, 5, 6]);
    let n = 1;
    for (let y = 0; y < 2; y++) {
      for (let x = 0; x < 3; x++, n++) {
        let [col, row] = bits & 0x20 ? [y, x] : [x, y];
        if (bits & 0x40) col = COLUMNS - 1 - col;
        if (bits & 0x80) row = ROWS - 1 - row;
        // Inverted glass with INVON: the stored word is what shows.
        assert.equal(p.shown(col, row), n, `MADCTL 0x${bits.toString(16)}: pixel ${n}`);
      }
    }
  }
});

test('landscape is the panel turned so that Rotation::Deg90 (MV|MX) reads upright', () => {
  const p = panel();
  init(p, { madctl: 0x60 });
  window(p, 0, 0, 319, 239);
  const words = Array.from({ length: 320 * 240 }, (_, i) => (i * 7919) & 0xffff);
  pixels(p, words);
  assert.deepEqual(Array.from(p.picture('landscape', 320, 240)), words);
  // A corner of it in portrait: the host's (0, 0) is the frame memory's top-right.
  assert.equal(p.shown(COLUMNS - 1, 0), words[0]);
});

test('inversion and colour order as the glass shows them', () => {
  const red = 0xf800;
  for (const [invertedGlass, invon, bgr, want] of [
    [true, true, false, red],
    [true, false, false, red ^ 0xffff],
    [false, false, false, red],
    [false, true, false, red ^ 0xffff],
    [true, true, true, 0x001f], // red data drives the blue sub-pixels
  ]) {
    const p = panel({ invertedGlass });
    init(p, { madctl: bgr ? 0x08 : 0, invert: invon });
    window(p, 5, 6, 5, 6);
    pixels(p, [red]);
    assert.equal(p.shown(5, 6), want, `glass inverted ${invertedGlass}, INVON ${invon}, BGR ${bgr}`);
  }
});

test('a software reset restores the defaults, among them the 18-bit format', () => {
  const p = panel();
  init(p);
  cmd(p, 0x01); // SWRESET
  p.clock.t += 6e6;
  window(p, 0, 0, 0, 0);
  assert.throws(() => pixels(p, [1]), /COLMOD 0x66/);
});

const refuses = (name, stream, message) =>
  test(`refuses ${name}`, () => {
    const p = panel();
    assert.throws(() => stream(p), (e) => e instanceof PanelError && message.test(e.message));
  });

refuses('a pixel past the end of the window', (p) => {
  init(p);
  window(p, 0, 0, 1, 1);
  pixels(p, [1, 2, 3, 4, 5]);
}, /past the end of the window/);

refuses('pixel data before RAMWR', (p) => {
  init(p);
  window(p, 0, 0, 1, 1);
  p.byte(0x12, true);
}, /no command to take it/);

refuses('pixels in a format other than the one set (COLMOD 18-bit)', (p) => {
  init(p, { colmod: 0x66 });
  window(p, 0, 0, 1, 1);
  pixels(p, [1]);
}, /COLMOD 0x66/);

refuses('a pixel cut in half by the next command', (p) => {
  init(p);
  window(p, 0, 0, 1, 1);
  p.byte(0x2c, false);
  p.byte(0xab, true);
  p.byte(0x00, false);
}, /middle of a 16-bit pixel/);

refuses('a window off the frame memory', (p) => {
  init(p);
  window(p, 0, 0, 240, 10);
}, /CASET 0\.\.240/);

refuses('a landscape window used after MADCTL turns back to portrait', (p) => {
  init(p, { madctl: 0x20 });
  window(p, 0, 0, 319, 10);
  cmd(p, 0x36, 0);
  pixels(p, [1]);
}, /off the 240x320 frame memory/);

refuses('a command with too few parameters', (p) => {
  init(p);
  p.byte(0x2a, false);
  p.byte(0, true);
  p.byte(0x29, false);
}, /CASET got 1 of its 4/);

refuses('an unknown command', (p) => {
  p.byte(0xc6, false);
}, /unknown command 0xc6/);

refuses('a command sooner than 5 ms after SLPOUT', (p) => {
  cmd(p, 0x11);
  p.clock.t += 1e6;
  cmd(p, 0x29);
}, /less than 5 ms/);

refuses('a picture with a pixel never written', (p) => {
  init(p);
  window(p, 0, 0, 1, 0);
  pixels(p, [1, 2]);
  p.picture('portrait', 2, 2);
}, /\(0, 1\).*never written/);

refuses('a picture while the display is off', (p) => {
  init(p);
  cmd(p, 0x28);
  p.picture('portrait', 1, 1);
}, /display is off/);

// The two-core estimate of run.js (not the panel, but pure arithmetic beside it).
import { twoCores, bandPasses, SLOTS } from '../run.js';

test('the two-core estimate: equal bands of one pass halve, one band does not, passes wait, two slots keep core 1 going', () => {
  assert.equal(twoCores([10, 10, 10, 10], [0, 0, 0, 0]), 20);
  assert.equal(twoCores([10], [0]), 10);
  // Core 1 takes the long band 0; core 0 cannot draw pass 1 before it is done, so it idles.
  assert.equal(twoCores([100, 1, 1, 1], [0, 0, 0, 0]), 100);
  assert.equal(twoCores([100, 1, 1, 1], [0, 1, 1, 1]), 101);
  // With one slot core 1 waits for core 0's long band to end before its next; with two it goes on.
  assert.equal(twoCores([1, 10, 1, 1], [0, 0, 0, 0], 1), 11);
  assert.equal(twoCores([1, 10, 1, 1], [0, 0, 0, 0], 2), 10);
  // The estimate's default is the firmware's slot count.
  const slots = readFileSync(new URL('../../src/two_cores.rs', import.meta.url), 'utf8').match(/pub const SLOTS: usize = (\d+);/);
  assert.ok(slots, 'two_cores.rs declares SLOTS');
  assert.equal(SLOTS, Number(slots[1]));
  assert.deepEqual(bandPasses(16, 2 + 2 + 4 + 8 + 16), [0, 0, 1, 1, 2, 2, 2, 2, ...new Array(8).fill(3), ...new Array(16).fill(4)]);
  assert.equal(bandPasses(16, 5), null);
});
