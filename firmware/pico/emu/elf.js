// The loadable segments of a 32-bit little-endian ARM ELF file: what a
// programmer writes to flash (each PT_LOAD segment's file bytes at its
// physical address, so .data's initial values land where the start-up code
// copies them from).

const PT_LOAD = 1;
const EM_ARM = 40;

/** Segments `{ paddr, bytes }` of an ELF image, or an Error saying what is wrong with it. */
export function loadSegments(buf) {
  if (buf.length < 52 || buf.readUInt32BE(0) !== 0x7f454c46) throw new Error('not an ELF file');
  if (buf[4] !== 1 || buf[5] !== 1) throw new Error('not a 32-bit little-endian ELF file');
  if (buf.readUInt16LE(18) !== EM_ARM) throw new Error('not an ARM ELF file');
  const phoff = buf.readUInt32LE(28);
  const phentsize = buf.readUInt16LE(42);
  const phnum = buf.readUInt16LE(44);
  const segments = [];
  for (let i = 0; i < phnum; i++) {
    const at = phoff + i * phentsize;
    if (at + 32 > buf.length) throw new Error('program header past the end of the file');
    if (buf.readUInt32LE(at) !== PT_LOAD) continue;
    const offset = buf.readUInt32LE(at + 4);
    const paddr = buf.readUInt32LE(at + 12);
    const filesz = buf.readUInt32LE(at + 16);
    if (filesz === 0) continue; // .bss and the stack: nothing to program
    if (offset + filesz > buf.length) throw new Error(`segment ${i} past the end of the file`);
    segments.push({ paddr, bytes: buf.subarray(offset, offset + filesz) });
  }
  return segments;
}
