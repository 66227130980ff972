// A model of the Sitronix ST7789 as a 240x320 SPI panel sees its 4-line
// serial interface: bytes with D/CX low are commands, bytes with D/CX high are
// their parameters or, after RAMWR, pixel data. It keeps the frame memory and
// the state the picture depends on (MADCTL, COLMOD, inversion, sleep, display
// on) and refuses, with a PanelError, what a real panel would get wrong or
// silently garble: data with no command to take it, pixels past the address
// window, a window off the frame memory, pixels in a format other than the one
// COLMOD set, a command that is not in the table below.
//
// MADCTL as the datasheet's "memory data access control" (section 8.12): the
// window's column counter runs first, then the row counter; MV exchanges the
// two before MX mirrors the frame memory's columns and MY its rows (the order
// mipidsi's MemoryMapping also uses). RGB/BGR (bit 3) says which end of a
// pixel word drives the red sub-pixels. INVON inverts what the glass shows; the
// common IPS modules show the inverse of the frame memory unless it is on, so
// `invertedGlass` (true by default) says the module is of that kind.

export const COLUMNS = 240; // frame memory columns (the short side)
export const ROWS = 320; // frame memory rows

/** What a real panel would get wrong: the stream the firmware sent is bad. */
export class PanelError extends Error {}

// Commands: name, and how many parameter bytes follow (RAMWR: any number).
const COMMANDS = new Map([
  [0x00, ['NOP', 0]],
  [0x01, ['SWRESET', 0]],
  [0x10, ['SLPIN', 0]],
  [0x11, ['SLPOUT', 0]],
  [0x12, ['PTLON', 0]],
  [0x13, ['NORON', 0]],
  [0x20, ['INVOFF', 0]],
  [0x21, ['INVON', 0]],
  [0x28, ['DISPOFF', 0]],
  [0x29, ['DISPON', 0]],
  [0x2a, ['CASET', 4]],
  [0x2b, ['RASET', 4]],
  [0x2c, ['RAMWR', Infinity]],
  [0x33, ['VSCRDEF', 6]],
  [0x34, ['TEOFF', 0]],
  [0x35, ['TEON', 1]],
  [0x36, ['MADCTL', 1]],
  [0x37, ['VSCSAD', 2]],
  [0x38, ['IDMOFF', 0]],
  [0x39, ['IDMON', 0]],
  [0x3a, ['COLMOD', 1]],
]);

const MADCTL_MY = 0x80;
const MADCTL_MX = 0x40;
const MADCTL_MV = 0x20;
const MADCTL_BGR = 0x08;
/** COLMOD's interface format for 16 bits a pixel (RGB 5-6-5). */
const COLMOD_16BIT = 0x5;

const hex = (v) => '0x' + v.toString(16).padStart(2, '0');

export class ST7789 {
  /**
   * @param {object} options
   * @param {boolean} [options.invertedGlass=true] the module shows the inverse of its frame memory unless INVON
   * @param {() => number} [options.nanos] the time now, for the datasheet's waits after SWRESET and SLPOUT
   */
  constructor({ invertedGlass = true, nanos = () => 0 } = {}) {
    this.invertedGlass = invertedGlass;
    this.nanos = nanos;
    this.memory = new Uint16Array(COLUMNS * ROWS);
    this.written = new Uint8Array(COLUMNS * ROWS);
    this.commands = []; // names, in the order received
    this.pixelsWritten = 0;
    this.reset();
  }

  /** The state after a hardware or software reset (the frame memory keeps what it had). */
  reset() {
    this.madctl = 0;
    this.colmod = 0x66; // 18 bits a pixel after reset
    this.inverted = false;
    this.sleeping = true;
    this.displayOn = false;
    this.xs = 0;
    this.xe = COLUMNS - 1;
    this.ys = 0;
    this.ye = ROWS - 1;
    this.command = null; // the command taking parameters, or null
    this.params = [];
    this.ramwr = null; // {x, y, high} while RAMWR streams pixels
    this.busyUntil = this.nanos() + 5e6; // 5 ms before the next command after a reset
  }

  /** RESX low: a hardware reset. */
  hardwareReset() {
    this.reset();
  }

  /** One byte on the serial interface, D/CX sampled with its last bit. */
  byte(value, dc) {
    if (!dc) {
      this.startCommand(value);
    } else if (this.ramwr) {
      this.pixelByte(value);
    } else if (this.command) {
      this.params.push(value);
      if (this.params.length === this.command[1]) {
        this.finishCommand();
      }
    } else {
      throw new PanelError(`data byte ${hex(value)} with no command to take it (a pixel before RAMWR, or a parameter too many)`);
    }
  }

  startCommand(code) {
    if (this.ramwr && this.ramwr.high !== null) {
      throw new PanelError(`RAMWR ended in the middle of a 16-bit pixel (one byte of it sent)`);
    }
    if (this.command && this.command[1] !== Infinity) {
      throw new PanelError(`${this.command[0]} got ${this.params.length} of its ${this.command[1]} parameters before the next command`);
    }
    this.ramwr = null;
    this.command = null;
    const entry = COMMANDS.get(code);
    if (!entry) {
      throw new PanelError(`unknown command ${hex(code)}`);
    }
    const [name, count] = entry;
    if (this.nanos() < this.busyUntil && name !== 'NOP') {
      throw new PanelError(`${name} less than 5 ms after a reset or SLPOUT (the panel ignores it)`);
    }
    this.commands.push(name);
    this.params = [];
    this.command = entry;
    if (count === 0) {
      this.finishCommand();
    } else if (count === Infinity) {
      this.startRamwr();
    }
  }

  finishCommand() {
    const [name] = this.command;
    const p = this.params;
    this.command = null;
    switch (name) {
      case 'SWRESET':
        this.reset();
        break;
      case 'SLPIN':
        this.sleeping = true;
        break;
      case 'SLPOUT':
        this.sleeping = false;
        this.busyUntil = this.nanos() + 5e6;
        break;
      case 'INVOFF':
        this.inverted = false;
        break;
      case 'INVON':
        this.inverted = true;
        break;
      case 'DISPOFF':
        this.displayOn = false;
        break;
      case 'DISPON':
        this.displayOn = true;
        break;
      case 'MADCTL':
        this.madctl = p[0];
        break;
      case 'COLMOD':
        this.colmod = p[0];
        break;
      case 'CASET':
      case 'RASET': {
        const start = (p[0] << 8) | p[1];
        const end = (p[2] << 8) | p[3];
        // The counter's range depends on MV: columns are the long side when exchanged.
        const exchanged = !!(this.madctl & MADCTL_MV);
        const limit = (name === 'CASET') !== exchanged ? COLUMNS : ROWS;
        if (start > end || end >= limit) {
          throw new PanelError(`${name} ${start}..${end}: outside 0..${limit - 1} or backwards`);
        }
        if (name === 'CASET') {
          this.xs = start;
          this.xe = end;
        } else {
          this.ys = start;
          this.ye = end;
        }
        break;
      }
      default:
        break; // NOP, NORON, PTLON, TEON/TEOFF, VSCRDEF, VSCSAD, IDMON/IDMOFF: no effect on the picture here
    }
  }

  startRamwr() {
    if ((this.colmod & 0x7) !== COLMOD_16BIT) {
      throw new PanelError(`RAMWR with COLMOD ${hex(this.colmod)}: the pixels are 16-bit RGB 5-6-5, which needs COLMOD 0x55`);
    }
    // The window as set; MADCTL may have changed since CASET/RASET, so check it again.
    const exchanged = !!(this.madctl & MADCTL_MV);
    const [cols, rows] = exchanged ? [ROWS, COLUMNS] : [COLUMNS, ROWS];
    if (this.xe >= cols || this.ye >= rows) {
      throw new PanelError(`RAMWR into a window (columns ${this.xs}..${this.xe}, rows ${this.ys}..${this.ye}) off the ${cols}x${rows} frame memory`);
    }
    this.ramwr = { x: this.xs, y: this.ys, high: null, done: false };
  }

  pixelByte(value) {
    const w = this.ramwr;
    if (w.high === null) {
      w.high = value;
      return;
    }
    const word = (w.high << 8) | value;
    w.high = null;
    if (w.done) {
      throw new PanelError(
        `pixel past the end of the window (columns ${this.xs}..${this.xe}, rows ${this.ys}..${this.ye}); the panel would wrap it to the window's start`,
      );
    }
    this.store(w.x, w.y, word);
    this.pixelsWritten++;
    if (w.x < this.xe) {
      w.x++;
    } else {
      w.x = this.xs;
      if (w.y < this.ye) {
        w.y++;
      } else {
        w.done = true;
      }
    }
  }

  /** Frame memory index of the window's (x, y) under MADCTL. */
  index(x, y) {
    let [col, row] = this.madctl & MADCTL_MV ? [y, x] : [x, y];
    if (this.madctl & MADCTL_MX) col = COLUMNS - 1 - col;
    if (this.madctl & MADCTL_MY) row = ROWS - 1 - row;
    return row * COLUMNS + col;
  }

  store(x, y, word) {
    const i = this.index(x, y);
    this.memory[i] = word;
    this.written[i] = 1;
  }

  /**
   * What the glass shows at frame memory (col, row), as an RGB 5-6-5 word
   * (red in the top bits), or null where nothing was ever written.
   */
  shown(col, row) {
    const i = row * COLUMNS + col;
    if (!this.written[i]) return null;
    let word = this.memory[i];
    if (this.inverted !== this.invertedGlass) word ^= 0xffff;
    if (this.madctl & MADCTL_BGR) {
      // The word's top five bits drive the blue sub-pixels.
      word = ((word & 0x1f) << 11) | (word & 0x07e0) | (word >> 11);
    }
    return word;
  }

  /**
   * The picture as the viewer sees it, `width` x `height` from its top-left
   * corner: `view` "portrait" (the frame memory as it is) or "landscape" (the
   * module turned a quarter turn counterclockwise, so that its right edge is
   * on top: how mipidsi's Rotation::Deg90 is seen upright). An array of RGB
   * 5-6-5 words, row by row. Refuses a picture the panel does not show: asleep,
   * display off, or any pixel never written.
   */
  picture(view, width, height) {
    if (this.sleeping) throw new PanelError('the panel is still asleep (no SLPOUT)');
    if (!this.displayOn) throw new PanelError('the display is off (no DISPON)');
    const landscape = view === 'landscape';
    const [vw, vh] = landscape ? [ROWS, COLUMNS] : [COLUMNS, ROWS];
    if (width > vw || height > vh) throw new Error(`${width}x${height} is larger than the ${vw}x${vh} ${view} panel`);
    const out = new Uint16Array(width * height);
    for (let vy = 0; vy < height; vy++) {
      for (let vx = 0; vx < width; vx++) {
        const [col, row] = landscape ? [COLUMNS - 1 - vy, vx] : [vx, vy];
        const word = this.shown(col, row);
        if (word === null) {
          throw new PanelError(`pixel (${vx}, ${vy}) of the ${view} picture was never written`);
        }
        out[vy * width + vx] = word;
      }
    }
    return out;
  }
}
