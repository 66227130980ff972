#!/usr/bin/env bash
# The pictures of README.md and docs/, each from the command beside it:
#   bash scripts/doc-images.sh          (about 5 minutes on 2 cores, the Pico's run most of it)
# docs/sampling.png comes from scripts/bench-sampling.sh; docs/web-page.png and
# docs/web-error.png are screenshots of the page (bash web/build.sh && bash
# web/serve.sh, then a browser at http://localhost:8000/).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
lensray=$(pwd)/target/release/lensray
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# README: the paper's Program 1, and the camera statements.
"$lensray" render scenes/paper-program1.scene --width 400 --height 300 -o docs/program1.png
"$lensray" render scenes/camera-features.scene --width 320 -o docs/camera-features.png

# README: the paper's figures 8 to 11 on one sheet.
"$lensray" sheet scenes/paper-fig8-pinhole.scene scenes/paper-fig9a.scene scenes/paper-fig9b.scene \
  scenes/paper-fig10a-focus-cylinder.scene scenes/paper-fig10b-focus-box.scene \
  scenes/paper-fig11a-distance-6.scene scenes/paper-fig11b-distance-10.scene \
  --columns 4 --width 180 --title "Hartanto & Rosalina, figures 8-11, rendered by lensray (Q16.16)" \
  -o docs/paper-figures.png

# docs/accuracy.md: Q16.16 against f32, like for like (as the tests and
# scripts/bench.sh measure it), each render beside its heat map.
alike() { # scene extra-statements -> a copy with them appended
  { cat "$1"; printf '\n%s\n' "$2"; } >"$work/$(basename "$1")"
  echo "$work/$(basename "$1")"
}
for s in pinhole-shapes camera-features; do
  scene=$(alike "scenes/$s.scene" $'adaptive off\nsampler independent')
  "$lensray" render "$scene" --width 200 --height 150 -o "docs/accuracy-$s.png"
  "$lensray" compare "$scene" --width 200 --height 150 --diff "docs/accuracy-$s-heat.png"
done
scene=$(alike host-tests/tests/stress/edge-of-range.scene 'adaptive off')
"$lensray" render "$scene" --width 200 --height 150 -o docs/accuracy-edge-of-range.png
"$lensray" compare "$scene" --width 200 --height 150 --diff docs/accuracy-edge-of-range-heat.png

# docs/boards.md: the progressive passes a display shows, and the Pico's panel
# under its emulator (Program 1, 320x240, the firmware's 8 rays a pixel).
"$lensray" render scenes/paper-program1.scene --width 160 --height 120 --passes "$work/passes" -o "$work/p1.png"
for i in 1 2 3 4 5; do cp "$work/passes/pass-$i.png" "docs/pass-$i.png"; done
"$lensray" emulate scenes/paper-program1.scene --board pico --width 320 --height 240 --samples 8 -o docs/pico-panel.png
