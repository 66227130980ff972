#!/usr/bin/env node
// Runs lensray's Raspberry Pi Pico firmware under rp2040js with a model of
// its ST7789 panel (st7789.js) on SPI0 and the wiring of firmware/pico:
// GP16 D/CX, GP17 CS, GP20 RESX, GP25 the LED lit while the frame renders.
//
//   node run.js FIRMWARE.elf --width W --height H --out PICTURE.rgb565 [--view landscape|portrait]
//
// The ELF's segments go to flash; the core starts from the firmware's own
// vector table after boot2 (no boot ROM: rp2040js ships none and none is
// vendored; flash reads need no boot2 set-up in the emulator). Each SPI byte
// takes its 8 bit times at the clock the firmware set, so a full FIFO stalls
// the firmware as on the board. The frame is timed between the LED's rise and
// fall, in cycles of the 125 MHz system clock.
//
// On success: the picture's top-left W x H as RGB 5-6-5 words (little-endian,
// row by row) in PICTURE, and one line on stdout:
//   emu setup_cycles=... frame_cycles=... total_cycles=... instructions_cycles=... spi_bytes=... pixels_written=... commands=...
// Exit status 3 and `panel: ...` on stderr for a stream the panel refuses;
// 4 and `firmware: ...` for a panic, a fault or a hang; 1 for bad arguments.

import { readFileSync, writeFileSync, renameSync } from 'node:fs';
import { RP2040, GPIOPinState } from 'rp2040js';
import { loadSegments } from './elf.js';
import { ST7789, PanelError } from './st7789.js';

const FLASH = 0x10000000;
const VECTORS = FLASH + 0x100; // after the 256 bytes of boot2
const PIN_DC = 16;
const PIN_CS = 17;
const PIN_RST = 20;
const PIN_LED = 25;
const PIN_BAND = 22; // toggles as core 0 starts each band
const NS_PER_CYCLE = 8; // 125 MHz
/** The ST7789's fastest serial write clock (a 16 ns cycle). */
const MAX_SPI_HZ = 62.5e6;
/** The breakpoint the firmware's panic handler stops at, message in r0/r1. */
const PANIC_BKPT = 0x50;

class FirmwareError extends Error {}

function usage(msg) {
  process.stderr.write(`run.js: ${msg}\nusage: node run.js FIRMWARE.elf --width W --height H --out FILE [--view landscape|portrait]\n`);
  process.exit(1);
}

function parseArgs(argv) {
  const o = { view: 'landscape' };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      return argv[++i];
    };
    if (a === '--width' || a === '--height') {
      const n = Number(value());
      if (!Number.isInteger(n) || n < 1) usage(`${a} must be a whole number from 1`);
      o[a.slice(2)] = n;
    } else if (a === '--out') o.out = value();
    else if (a === '--view') {
      o.view = value();
      if (o.view !== 'landscape' && o.view !== 'portrait') usage('--view must be landscape or portrait');
    } else if (a.startsWith('-')) usage(`unknown option ${a}`);
    else if (o.elf) usage('one firmware file only');
    else o.elf = a;
  }
  if (!o.elf || !o.width || !o.height || !o.out) usage('FIRMWARE, --width, --height and --out are needed');
  return o;
}

/** Sets up the chip, the firmware and the panel; returns what run() needs. */
export function boot(elfBytes) {
  const mcu = new RP2040(); // on its own simulation clock, advanced below
  const clock = mcu.clock;
  const state = { fault: null, ledOnNanos: null, ledOffNanos: null, spiBytes: 0 };
  const fail = (msg) => {
    if (!state.fault) state.fault = msg;
  };
  // rp2040js logs what it cannot do (bad addresses, unknown instructions): on a board each is a fault.
  const log = (level) => (component, message) => fail(`${level} from the emulated ${component}: ${message} (pc ${hex32(mcu.core.PC)})`);
  mcu.logger = { debug() {}, info() {}, warn: log('warning'), error: log('error') };

  for (const { paddr, bytes } of loadSegments(elfBytes)) {
    const at = paddr - FLASH;
    if (at < 0 || at + bytes.length > mcu.flash.length) {
      throw new Error(`segment at ${hex32(paddr)} is not in the 2 MiB of flash`);
    }
    mcu.flash.set(bytes, at);
  }
  mcu.core.VTOR = VECTORS;
  mcu.core.reset(); // SP and PC from the firmware's vector table

  // Core 1's mailbox (SIO FIFO), which rp2040js lacks: there is no core 1 to
  // answer, so writes go nowhere and the read side is always empty.
  const sio = mcu.sio;
  const sioRead = sio.readUint32.bind(sio);
  const sioWrite = sio.writeUint32.bind(sio);
  const FIFO_ST = 0x50, FIFO_WR = 0x54, FIFO_RD = 0x58;
  sio.readUint32 = (offset) => (offset === FIFO_ST ? 0b10 /* RDY, not VLD */ : offset === FIFO_RD ? 0 : sioRead(offset));
  sio.writeUint32 = (offset, value) => {
    if (offset !== FIFO_WR && offset !== FIFO_ST) sioWrite(offset, value);
  };

  mcu.onBreak = (code) => {
    const pc = (mcu.core.PC - mcu.core.breakRewind) >>> 0;
    if (code === PANIC_BKPT && mcu.readUint16(pc) === (0xbe00 | PANIC_BKPT)) {
      const ptr = mcu.core.registers[0] >>> 0;
      const len = Math.min(mcu.core.registers[1] >>> 0, 4096);
      const bytes = Buffer.alloc(len);
      for (let i = 0; i < len; i++) bytes[i] = mcu.readUint8(ptr + i);
      fail(`panicked: ${bytes.toString('utf8')}`);
    } else {
      // A breakpoint with no debugger, or an undefined instruction: a HardFault on the board.
      fail(`HardFault at pc ${hex32(pc)} (${mcu.readUint16(pc) >> 8 === 0xbe ? 'bkpt' : 'udf'} #${code})`);
    }
  };

  const panel = new ST7789({ nanos: () => clock.nanos });
  const pin = (n) => mcu.gpio[n];
  const low = (n) => pin(n).value === GPIOPinState.Low;
  pin(PIN_RST).addListener((s, old) => {
    if (s === GPIOPinState.High && old === GPIOPinState.Low) panel.hardwareReset();
  });
  pin(PIN_LED).addListener((s) => {
    if (s === GPIOPinState.High && state.ledOnNanos === null) state.ledOnNanos = clock.nanos;
    if (s === GPIOPinState.Low && state.ledOnNanos !== null && state.ledOffNanos === null) state.ledOffNanos = clock.nanos;
  });

  // Band boundaries while the frame renders, for the two-core estimate.
  state.bandNanos = [];
  pin(PIN_BAND).addListener((s, old) => {
    if (state.ledOnNanos !== null && state.ledOffNanos === null && s !== old) state.bandNanos.push(clock.nanos);
  });

  const spi = mcu.spi[0];
  const done = clock.createAlarm(() => {
    const value = state.inFlight;
    state.inFlight = null;
    // The panel samples D/CX with the byte's last bit, and listens only with CS low.
    if (low(PIN_CS)) {
      state.spiBytes++;
      try {
        panel.byte(value, !low(PIN_DC));
      } catch (e) {
        if (!(e instanceof PanelError)) throw e;
        state.panelError = `${e.message} (SPI byte ${state.spiBytes}; commands so far: ${panel.commands.slice(-6).join(', ')})`;
      }
    }
    spi.completeTransmit(0);
  });
  spi.onTransmit = (value) => {
    const hz = spi.clockFrequency;
    if (spi.dataBits !== 8) state.panelError = `SPI frames of ${spi.dataBits} bits; the panel takes bytes`;
    else if (spiMode(spi) !== 0 && spiMode(spi) !== 3) state.panelError = `SPI mode ${spiMode(spi)}: the panel samples on the rising edge (mode 0 or 3)`;
    else if (!(hz > 0) || hz > MAX_SPI_HZ) state.panelError = `SPI clock ${hz} Hz: above the panel's ${MAX_SPI_HZ} Hz`;
    state.inFlight = value;
    done.schedule((8 * 1e9) / hz);
  };

  return { mcu, clock, panel, state, spi };
}

/** Runs until the frame is done (the LED goes out), a fault, or a refused byte. */
export function run({ mcu, clock, state, spi }) {
  const core = mcu.core;
  for (;;) {
    for (let i = 0; i < 100000; i++) {
      if (core.waiting) {
        const wait = clock.nanosToNextAlarm;
        if (wait <= 0) {
          if (state.ledOffNanos !== null) return;
          throw new FirmwareError('waits for an interrupt that nothing will raise, before the frame is done (the LED still on)');
        }
        clock.tick(wait);
      } else {
        clock.tick(core.executeInstruction() * NS_PER_CYCLE);
      }
      if (state.fault) throw new FirmwareError(state.fault);
      if (state.panelError) throw new PanelError(state.panelError);
      if (state.ledOffNanos !== null && !spi.busy && spi.txFIFO.empty) return;
    }
  }
}

/**
 * The pass of each band, from the image's height and the band count: the
 * schedule of firmware/pico (8x8 blocks, a one-ray preview when the frame
 * has more rays, then 4x4, 2x2, 1x1), as lensray::progressive::Schedule makes it.
 */
export function bandPasses(height, count) {
  for (const steps of [[8, 8, 4, 2, 1], [8, 4, 2, 1]]) {
    const passes = steps.flatMap((step, p) => new Array(Math.ceil(height / step)).fill(p));
    if (passes.length === count) return passes;
  }
  return null;
}

/** Core 1's recorders: two_cores.rs's `SLOTS` (the tests check they agree). */
export const SLOTS = 2;

/**
 * An estimate of the bands' time on two cores (ns), following two_cores.rs:
 * bands taken in order by whichever core asks first; core 1 records each band
 * in the next of its `slots` recorders and goes on, waiting only when every
 * slot holds a band core 0 has not drawn; core 0, between two of its own
 * bands, draws core 1's recorded bands in order, and waits for core 1's band
 * before drawing one of a later pass. Each band costs what it cost core 0
 * alone (render, record, draw on the panel), so core 1's share is slightly
 * overcounted (it does not draw) and core 0's drawing of core 1's bands left
 * out: an estimate, not a measurement.
 */
export function twoCores(durations, passes, slots = SLOTS) {
  const n = durations.length;
  let next = 0;
  let t0 = 0; // core 0's time
  const held = []; // core 1's bands not yet drawn, in order: { k, done }
  let core1Asks = 0; // when core 1 next asks for a band (null: none left)
  for (;;) {
    // Core 1 takes bands while it asks no later than core 0 and has a free slot.
    while (core1Asks !== null && held.length < slots && core1Asks <= t0) {
      if (next < n) {
        core1Asks += durations[next];
        held.push({ k: next, done: core1Asks });
        next++;
      } else core1Asks = null;
    }
    if (next >= n) break;
    const k = next++;
    t0 += durations[k];
    // Core 0 draws core 1's bands: each done by now, or of an earlier pass (waiting for it).
    while (held.length && (passes[held[0].k] < passes[k] || held[0].done <= t0)) {
      const full = held.length === slots;
      t0 = Math.max(t0, held.shift().done);
      // A slot freed: core 1, if it waited for one, asks now.
      if (full && core1Asks !== null) core1Asks = Math.max(core1Asks, t0);
    }
  }
  for (const band of held) t0 = Math.max(t0, band.done);
  return t0;
}

/** SPI mode from SSPCR0's SPO (CPOL, bit 6) and SPH (CPHA, bit 7); rp2040js's own `spiMode` swaps 2 and 3. */
function spiMode(spi) {
  return (((spi.control0 >> 6) & 1) << 1) | ((spi.control0 >> 7) & 1);
}

function hex32(v) {
  return '0x' + (v >>> 0).toString(16).padStart(8, '0');
}

function main() {
  const o = parseArgs(process.argv.slice(2));
  let elf;
  try {
    elf = readFileSync(o.elf);
  } catch (e) {
    usage(`${o.elf}: ${e.message}`);
  }
  let emu;
  try {
    emu = boot(elf);
    run(emu);
    const picture = emu.panel.picture(o.view, o.width, o.height);
    const tmp = `${o.out}.tmp`;
    writeFileSync(tmp, Buffer.from(picture.buffer, picture.byteOffset, picture.byteLength));
    renameSync(tmp, o.out);
  } catch (e) {
    if (e instanceof PanelError) {
      process.stderr.write(`panel: ${e.message}\n`);
      process.exit(3);
    }
    if (e instanceof FirmwareError) {
      process.stderr.write(`firmware: ${e.message}\n`);
      process.exit(4);
    }
    throw e;
  }
  const { state, clock, mcu, panel } = emu;
  const cycles = (nanos) => Math.round(nanos / NS_PER_CYCLE);
  const bands = [];
  for (let i = 1; i < state.bandNanos.length; i++) bands.push(state.bandNanos[i] - state.bandNanos[i - 1]);
  const passes = bandPasses(o.height, bands.length);
  const estimate = passes
    ? state.bandNanos[0] - state.ledOnNanos + twoCores(bands, passes) + (state.ledOffNanos - state.bandNanos.at(-1))
    : 0;
  process.stdout.write(
    `emu setup_cycles=${cycles(state.ledOnNanos)} frame_cycles=${cycles(state.ledOffNanos - state.ledOnNanos)} ` +
      `total_cycles=${cycles(clock.nanos)} core_cycles=${mcu.core.cycles} spi_bytes=${state.spiBytes} ` +
      `pixels_written=${panel.pixelsWritten} bands=${bands.length} ` +
      `two_core_estimate_cycles=${cycles(estimate)} ` +
      `commands=${[...new Set(panel.commands)].join(',')}\n`,
  );
}

if (import.meta.url === `file://${process.argv[1]}`) main();
