#!/usr/bin/env bash
# The firmware's checks, run by scripts/test-all.sh (or alone):
#   bash scripts/firmware-tests.sh
# Installs what is missing (thumb targets, qemu-system-arm, a size tool, Node
# and rp2040js; the RISC-V target and qemu-system-riscv32), then: format and lint of the firmware crates (outside the main
# workspace, so the workspace's clippy does not see them), the QEMU tests (both
# boards, bit for bit against the host's render, instruction counts, RAM,
# faults, the micro:bit's 40 KiB flash floor), the Raspberry Pi Pico under rp2040js (its ST7789 model's own tests,
# then the panel bit for bit against the host's Rgb565 render, and faults) and
# the memory sizes.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

# Each step prints the time since the script started (bash's SECONDS).
step() { printf '\n==> [%d:%02d] %s\n' $((SECONDS / 60)) $((SECONDS % 60)) "$*"; }

# The build-time settings of the firmware come from these; start clean.
unset LENSRAY_SCENE LENSRAY_WIDTH LENSRAY_HEIGHT LENSRAY_SAMPLES LENSRAY_FLOAT LENSRAY_FAULT LENSRAY_FIRMWARE_DIR

step "firmware: tools"
# shellcheck source=firmware-tools.sh
source "$root/scripts/firmware-tools.sh"
qemu-system-arm --version | head -1
qemu-system-riscv32 --version | head -1
echo "size tool: $size_tool"

cd "$root/firmware"
step "firmware: format and lint (microbit, mps2-an385, mps2-an386, sifive-e, pico)"
cargo fmt --all --check
cargo clippy --release --features microbit --target thumbv6m-none-eabi -- -D warnings
cargo clippy --release --features microbit,profile --target thumbv6m-none-eabi -- -D warnings
cargo clippy --release --features microbit,parse-on-device --target thumbv6m-none-eabi -- -D warnings
cargo clippy --release --features mps2-an385 --target thumbv7m-none-eabi -- -D warnings
cargo clippy --release --features mps2-an386,hw-sqrt --target thumbv7em-none-eabihf -- -D warnings
cargo clippy --release --features sifive-e --target riscv32imac-unknown-none-elf -- -D warnings
# The Pico from its own directory, whose .cargo/config.toml adds to this one's, as it is flashed.
(cd pico && cargo clippy --release -p lensray-pico --target thumbv6m-none-eabi -- -D warnings)

step "firmware: Raspberry Pi Pico with an ST7789 panel (the default build: Program 1, 320x240, 8 rays)"
(cd pico && cargo build --release -p lensray-pico --target thumbv6m-none-eabi)
"$size_tool" target/thumbv6m-none-eabi/release/lensray-pico

step "firmware: under QEMU on every board, bit for bit against the host"
cd "$root"
start=$(date +%s)
cargo test -p lensray-host --test firmware -- --ignored --nocapture
echo "QEMU tests took $(( $(date +%s) - start )) s (builds included)"

step "firmware: the Pico under rp2040js, its panel bit for bit against the host's Rgb565 render"
start=$(date +%s)
(cd "$root/firmware/pico/emu" && node --test)
cargo test -p lensray-host --test pico -- --ignored --nocapture
echo "Pico tests took $(( $(date +%s) - start )) s (builds included)"

step "firmware: memory of the default build (Program 1 baked at its defaults, 160x120)"
cd "$root/firmware"
# board target features profile
for board in "microbit thumbv6m-none-eabi microbit microbit" "mps2-an386 thumbv7em-none-eabihf mps2-an386,hw-sqrt release" "sifive-e riscv32imac-unknown-none-elf sifive-e release"; do
  set -- $board
  cargo build -q --profile "$4" --features "$3" --target "$2"
  echo "$1 (text + data = flash; data + bss = static RAM; the stack is measured by the tests above):"
  "$size_tool" "target/$2/$4/lensray-firmware"
done
