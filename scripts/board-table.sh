#!/usr/bin/env bash
# Every QEMU board's Program 1 figures beside its parse-on-device build (for
# flash and stack), measured under QEMU with -icount shift=0 (instructions,
# not cycles); BENCHMARKS.md has the baked builds alone (scripts/bench.sh):
#   bash scripts/board-table.sh [OUT]     (OUT: a Markdown file; default stdout)
# For each board: Program 1 at 160x120 as a pinhole (radius 0) and with 16
# lens samples, Q16.16 and f32, from the scene baked at build time; the same
# pinhole Q16.16 build with the scene parsed on the device, for its flash and
# stack; and seconds for Program 1 pinhole at 320x240 computed from the
# per-pixel counts at each class's usual clock. About 15 firmware builds:
# 15-25 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
out=${1:-/dev/stdout}
unset LENSRAY_SCENE LENSRAY_WIDTH LENSRAY_HEIGHT LENSRAY_SAMPLES LENSRAY_FLOAT LENSRAY_FAULT LENSRAY_FIRMWARE_DIR
# shellcheck source=firmware-tools.sh
source "$root/scripts/firmware-tools.sh" >&2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{ cat scenes/paper-program1.scene; printf '\nradius 0\n'; } >"$work/program1-pinhole.scene"
# Adaptive off: every one of the 16 samples is cast (instructions a ray).
{ cat scenes/paper-program1.scene; printf '\nadaptive off\n'; } >"$work/program1-lens.scene"
cargo build --release -q -p lensray-host >&2
lensray="$root/target/release/lensray"
field() { sed -n 's/^report //p' "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }
W=160
H=120

# board core target clock-MHz clock-note
boards=(
  "microbit Cortex-M0 thumbv6m-none-eabi 16 nRF51 (micro:bit)"
  "mps2-an385 Cortex-M3 thumbv7m-none-eabi 72 STM32F103"
  "mps2-an386 Cortex-M4F thumbv7em-none-eabihf 168 STM32F4"
  "sifive-e RV32IMAC riscv32imac-unknown-none-elf 160 ESP32-C3"
)
table="| board (core) | number | pinhole instr./pixel | lens instr./ray (16 samples) | flash (.text+.rodata), baked | static RAM | peak stack, baked | flash, parsed on device | peak stack, parsed |
|---|---|---|---|---|---|---|---|---|"
secs="| board (core) | clock (class) | Program 1 pinhole 320x240, Q16.16 | f32 |
|---|---|---|---|"
for b in "${boards[@]}"; do
  read -r board core target mhz note <<<"$b"
  # The firmware's cargo profile for the board (lensray emulate builds with it).
  profile=release
  [ "$board" = microbit ] && profile=microbit
  declare -A pp=()
  for number in q16 f32; do
    extra=()
    [ $number = f32 ] && extra=(--float)
    echo "== $board $number" >&2
    "$lensray" emulate "$work/program1-pinhole.scene" --board "$board" --width $W --height $H "${extra[@]}" -o "$work/p.bmp" >"$work/pin.log"
    flash=$(field "$work/pin.log" flash)
    # .text + .rodata of the ELF that just ran (flash in the report also counts .data's image).
    ft=$("$size_tool" -A "firmware/target/$target/$profile/lensray-firmware" | awk '$1 == ".text" || $1 == ".rodata" || $1 == ".vector_table" { s += $2 } END { print s }')
    "$lensray" emulate "$work/program1-lens.scene" --board "$board" --width $W --height $H --samples 16 "${extra[@]}" -o "$work/l.bmp" >"$work/lens.log"
    frame=$(field "$work/lens.log" frame)
    per_ray=$(( (frame + W * H * 8) / (W * H * 16) ))
    parsed_flash="-"; parsed_stack="-"
    if [ $number = q16 ]; then
      "$lensray" emulate "$work/program1-pinhole.scene" --board "$board" --width $W --height $H --parse-on-device -o "$work/pp.bmp" >"$work/parsed.log"
      parsed_flash=$("$size_tool" -A "firmware/target/$target/$profile/lensray-firmware" | awk '$1 == ".text" || $1 == ".rodata" || $1 == ".vector_table" { s += $2 } END { print s }')
      parsed_stack=$(field "$work/parsed.log" peak_stack)
    fi
    pp[$number]=$(field "$work/pin.log" per_pixel)
    table+="
| $board ($core) | $([ $number = q16 ] && echo Q16.16 || echo f32) | ${pp[$number]} | $per_ray | $ft | $(field "$work/pin.log" static_ram) | $(field "$work/pin.log" peak_stack) | $parsed_flash | $parsed_stack |"
  done
  s() { awk -v p="$1" -v m="$mhz" 'BEGIN { printf "%.1f s", p * 320 * 240 / (m * 1e6) }'; }
  secs+="
| $board ($core) | $mhz MHz ($note) | $(s "${pp[q16]}") | $(s "${pp[f32]}") |"
done
{
  echo "$table"
  echo
  echo "Seconds for Program 1 pinhole at 320x240, **computed** as instructions a pixel x 76,800 / clock (one instruction a cycle: an estimate, not a measurement):"
  echo
  echo "$secs"
} >"$out"
