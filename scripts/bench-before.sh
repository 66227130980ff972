#!/usr/bin/env bash
# The boards' figures of an earlier commit, for bench.sh's before-and-after table:
#   bash scripts/bench-before.sh REF OUT
# Builds lensray at REF in a temporary git worktree and runs there what
# bench.sh runs on the QEMU boards (Program 1 at 160x120, pinhole and 16 lens
# samples, Q16.16 and f32; the micro:bit's default build), writing one line
# "KEY INSTRUCTIONS-A-PIXEL" each to OUT (KEY: board-pinhole|lens16-q16|f32,
# or microbit-default). Fresh builds of every firmware target: about 10 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
ref=$1
out=$(realpath -m "$2")
unset LENSRAY_SCENE LENSRAY_WIDTH LENSRAY_HEIGHT LENSRAY_SAMPLES LENSRAY_FLOAT LENSRAY_FAULT LENSRAY_FIRMWARE_DIR
work=$(mktemp -d)
git worktree add -q --detach "$work/tree" "$ref"
trap 'git worktree remove --force "$work/tree"; rm -rf "$work"' EXIT
{ cat scenes/paper-program1.scene; printf '\nradius 0\n'; } >"$work/program1-pinhole.scene"
{ cat scenes/paper-program1.scene; printf '\nadaptive off\n'; } >"$work/program1-lens.scene"
cd "$work/tree"
cargo build --release -q -p lensray-host >&2
lensray="$work/tree/target/release/lensray"
per_pixel() { sed -n 's/^report //p' "$1" | tr ' ' '\n' | sed -n 's/^per_pixel=//p'; }
: >"$out"
for board in microbit mps2-an385 mps2-an386 sifive-e; do
  for mode in pinhole lens16; do
    for number in q16 f32; do
      args=(--board "$board" --width 160 --height 120)
      scene="$work/program1-pinhole.scene"
      if [ $mode = lens16 ]; then scene="$work/program1-lens.scene"; args+=(--samples 16); fi
      if [ $number = f32 ]; then args+=(--float); fi
      printf '\n==> before (%s): %s %s %s\n' "$ref" "$board" "$mode" "$number" >&2
      "$lensray" emulate "$scene" "${args[@]}" -o "$work/out.bmp" >"$work/run.log"
      echo "$board-$mode-$number $(per_pixel "$work/run.log")" >>"$out"
    done
  done
done
printf '\n==> before (%s): microbit default build\n' "$ref" >&2
"$lensray" emulate scenes/paper-program1.scene --board microbit -o "$work/out.bmp" >"$work/run.log"
echo "microbit-default $(per_pixel "$work/run.log")" >>"$out"
