# Sourced by scripts/firmware-tests.sh and scripts/bench.sh: installs what the
# firmware needs where it is missing (thumb and RISC-V targets,
# qemu-system-arm, qemu-system-riscv32, a size tool for both) and sets $size_tool.
installed=$(rustup target list --installed)
for t in thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf riscv32imac-unknown-none-elf; do
  if ! grep -qx "$t" <<<"$installed"; then rustup target add "$t"; fi
done
as_root_apt() {
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null
  else
    return 1
  fi
}
if ! command -v qemu-system-arm >/dev/null 2>&1; then
  as_root_apt qemu-system-arm || {
    echo "qemu-system-arm is missing: install it (Debian: sudo apt-get install qemu-system-arm) and run again" >&2
    exit 1
  }
fi
# The RISC-V board (sifive-e): Debian puts qemu-system-riscv32 in qemu-system-misc.
if ! command -v qemu-system-riscv32 >/dev/null 2>&1; then
  as_root_apt qemu-system-misc || {
    echo "qemu-system-riscv32 is missing: install it (Debian: sudo apt-get install qemu-system-misc) and run again" >&2
    exit 1
  }
fi
# llvm-size reads Arm and RISC-V ELFs alike (arm-none-eabi-size only Arm).
size_tool=""
if command -v llvm-size >/dev/null 2>&1; then
  size_tool=llvm-size
else
  rustup component add llvm-tools
  size_tool="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin/llvm-size"
fi
# The Pico's emulator: Node (18 or later) and rp2040js from the committed lockfile.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  as_root_apt nodejs npm || {
    echo "node and npm are missing: install Node.js 18 or later (Debian: sudo apt-get install nodejs npm) and run again" >&2
    exit 1
  }
fi
pico_emu="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/firmware/pico/emu"
if [ ! -f "$pico_emu/node_modules/rp2040js/package.json" ] ||
   [ "$pico_emu/package-lock.json" -nt "$pico_emu/node_modules/.package-lock.json" ]; then
  (cd "$pico_emu" && npm ci --no-audit --no-fund --loglevel=error)
fi
