#!/usr/bin/env bash
# Every benchmark, measured from scratch, written to BENCHMARKS.md:
#   bash scripts/bench.sh [OUT]        (OUT defaults to BENCHMARKS.md)
# - Q16.16 against f32 on scenes/ and the stress scenes (lensray compare);
# - every QEMU board (micro:bit Cortex-M0, MPS2 Cortex-M3 and Cortex-M4F,
#   SiFive E RV32) with -icount shift=0: instructions per pixel and per ray for
#   Program 1 at 160x120, pinhole and with 16 lens samples, Q16.16 and f32,
#   flash, static RAM and peak stack, with the instructions as bar charts
#   (docs/bench-boards-*.png); the micro:bit's default build; the Pico
#   under rp2040js (cycles a pixel, Program 1 as a pinhole);
# - the boards' figures at the commit where the speed work began, beside
#   today's (scripts/bench-before.sh; LENSRAY_BENCH_BEFORE=REF for another);
# - a per-operation profile on the Cortex-M0 (firmware feature `profile`);
# - host rays per second (criterion, host-tests/benches/render.rs), one thread
#   and all cores, with the machine's load, and the parallel speedup measured
#   in pairs beside the machine's ceiling for the same work (whole frames side
#   by side: host-tests/benches/speedup.rs);
# - lens sampling: the adaptive render against converged references, beside
#   `point` independent samples and plain stratified samples at its rays, as
#   distributions over the scenes (host-tests/benches/sampling.rs; the curves
#   of scenes/ in docs/sampling.png).
# Each table in OUT names the command that makes it. Installs what the
# firmware needs where missing (scripts/firmware-tools.sh). About 25 minutes
# on 2 cores (the firmware builds, with fat LTO, are most of it).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
out=${1:-BENCHMARKS.md}
unset LENSRAY_SCENE LENSRAY_WIDTH LENSRAY_HEIGHT LENSRAY_SAMPLES LENSRAY_FLOAT LENSRAY_FAULT LENSRAY_FIRMWARE_DIR

step() { printf '\n==> %s\n' "$*" >&2; }

step "tools"
# shellcheck source=firmware-tools.sh
source "$root/scripts/firmware-tools.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Program 1 as a pinhole (the last camera statement stands) and as written (radius 0.2).
{ cat scenes/paper-program1.scene; printf '\nradius 0\n'; } >"$work/program1-pinhole.scene"
# Adaptive off: every one of the 16 samples is cast (instructions a ray).
{ cat scenes/paper-program1.scene; printf '\nadaptive off\n'; } >"$work/program1-lens.scene"
W=160
H=120

step "host: building lensray"
cargo build --release -q
lensray="$root/target/release/lensray"

# The host first: criterion wants the cores quiet, and the firmware builds are long.
step "host: criterion (host-tests/benches/render.rs)"
load_before=$(uptime | sed 's/.*load average: //')
cargo bench -p lensray-host --bench render 2>&1 | tee "$work/criterion.log" >&2
load_after=$(uptime | sed 's/.*load average: //')
# name -> rays per second (the middle of criterion's throughput estimate).
awk '
  /^program1-160x120\// { name = $1 }
  /thrpt:/ && name != "" {
    gsub(/[\[\]]/, ""); v = $4; u = $5
    m = (u ~ /^K/) ? 1e3 : (u ~ /^M/) ? 1e6 : (u ~ /^G/) ? 1e9 : 1
    printf "%s %.0f\n", name, v * m; name = ""
  }' "$work/criterion.log" >"$work/rays.txt"
rate() { awk -v n="$1" '$1 == n { print $2 }' "$work/rays.txt"; }

# The speedup in pairs: one thread and all cores back to back, median of the rounds' ratios.
step "host: paired speedup (host-tests/benches/speedup.rs)"
cargo bench -p lensray-host --bench speedup 2>&1 | tee "$work/speedup.log" >&2
# name key -> value of a speedup line.
paired() { awk -v n="$1" -v k="$2" '$1 == "speedup" && $2 == n { for (i = 3; i <= NF; i++) { split($i, kv, "="); if (kv[1] == k) print kv[2] } }' "$work/speedup.log"; }

# key=value of the firmware's report line.
field() { sed -n 's/^report //p' "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }

# The accuracy table: the same pairs the host tests measure (tests/accuracy.rs,
# tests/stress.rs): every scene of scenes/ at 320x240 with `adaptive off` and
# `sampler independent` appended, the stress scenes at 160x120 with
# `adaptive off`, so that both number types average the same lens samples.
step "host: Q16.16 against f32 (lensray compare)"
accuracy_rows=()
compare_row() { # scene-file label width height -> one table row
  local log="$work/compare.log"
  "$lensray" compare "$1" --width "$3" --height "$4" >"$log" 2>/dev/null
  awk -v name="$2" -v size="$3x$4" '
    /ray\(s\) a pixel/ { n = split($0, w, " "); for (i = 1; i <= n; i++) if (w[i] == "ray(s)") rays = w[i - 1] }
    $1 == "PSNR" { psnr = $2 " " $3 }
    $1 == "max" { mx = $3 }
    $1 == "within" && $2 == 1 { w1 = $3 " %" }
    $1 == "within" && $2 == 2 { w2 = $3 " %" }
    $1 == "worst" { if ($3 + 0 > line) line = $3 + 0 }
    $2 == "bias" { if ($3 + 0 > bias) bias = $3 + 0 }
    END { printf "| `%s` | %s | %s | %s | %s | %s | %s | %.4f | %.4f |\n", name, size, rays, psnr, mx, w1, w2, line, bias }' "$log"
}
for s in scenes/*.scene; do
  { cat "$s"; printf '\nadaptive off\nsampler independent\n'; } >"$work/alike.scene"
  accuracy_rows+=("$(compare_row "$work/alike.scene" "$(basename "$s")" 320 240)")
done
for s in host-tests/tests/stress/*.scene; do
  { cat "$s"; printf '\nadaptive off\n'; } >"$work/alike.scene"
  accuracy_rows+=("$(compare_row "$work/alike.scene" "stress/$(basename "$s")" 160 120)")
done

rows=()
declare -A per_pixel
boards=(microbit mps2-an385 mps2-an386 sifive-e)
for board in "${boards[@]}"; do
  case $board in
    microbit) core="Cortex-M0"; target=thumbv6m-none-eabi ;;
    mps2-an385) core="Cortex-M3"; target=thumbv7m-none-eabi ;;
    mps2-an386) core="Cortex-M4F"; target=thumbv7em-none-eabihf ;;
    sifive-e) core="RV32IMAC"; target=riscv32imac-unknown-none-elf ;;
  esac
  for mode in pinhole lens16; do
    for number in q16 f32; do
      args=(--board "$board" --width $W --height $H)
      scene="$work/program1-pinhole.scene"
      if [ $mode = lens16 ]; then scene="$work/program1-lens.scene"; args+=(--samples 16); fi
      if [ $number = f32 ]; then args+=(--float); fi
      step "$board: Program 1 $mode $number"
      log="$work/$board-$mode-$number.log"
      "$lensray" emulate "$scene" "${args[@]}" -o "$work/$board-$mode-$number.bmp" >"$log"
      # The micro:bit builds with its own profile, compiled for size (firmware/Cargo.toml).
      profile_dir=$([ $board = microbit ] && echo microbit || echo release)
      read -r text data bss _ < <("$size_tool" "firmware/target/$target/$profile_dir/lensray-firmware" | tail -1)
      pp=$(field "$log" per_pixel)
      frame=$(field "$log" frame)
      rays=$(field "$log" rays)
      per_pixel[$board-$mode-$number]=$pp
      per_ray=$(( (frame + W * H * rays / 2) / (W * H * rays) ))
      label=$([ $number = q16 ] && echo "Q16.16" || { [ $board = mps2-an386 ] && echo "f32 (FPU, vsqrt.f32)" || echo "f32 (software)"; })
      rows+=("| $board ($core) | $([ $mode = pinhole ] && echo "pinhole (radius 0)" || echo "lens, radius 0.2") | $rays | $label | $pp | $per_ray | $text | $((data + bss)) | $(field "$log" peak_stack) |")
    done
  done
done

# The boards' instructions a pixel as bar charts (host-tests/examples/bar_chart.rs).
step "plots: docs/bench-boards-pinhole.png, docs/bench-boards-lens.png"
board_label() {
  case $1 in
    microbit) echo "micro:bit (Cortex-M0)" ;;
    mps2-an385) echo "MPS2 AN385 (Cortex-M3)" ;;
    mps2-an386) echo "MPS2 AN386 (Cortex-M4F)" ;;
    sifive-e) echo "SiFive E (RV32IMAC)" ;;
  esac
}
bars() { # mode title out
  local groups=()
  for b in "${boards[@]}"; do groups+=("$(board_label "$b")=${per_pixel[$b-$1-q16]},${per_pixel[$b-$1-f32]}"); done
  cargo run --release -q -p lensray-host --example bar_chart -- "$3" "$2" "Q16.16,f32" "${groups[@]}" >&2
}
bars pinhole "Program 1 through a pinhole, ${W}x${H}: instructions a pixel under QEMU (fewer is faster)" docs/bench-boards-pinhole.png
bars lens16 "Program 1, radius 0.2, 16 lens samples, ${W}x${H}: instructions a pixel under QEMU" docs/bench-boards-lens.png

# The same runs at the commit where the speed work began (issue 55's start),
# built in a worktree, for the before-and-after table.
before_ref=${LENSRAY_BENCH_BEFORE:-cabfae5}
step "before: the boards at $before_ref (scripts/bench-before.sh)"
bash scripts/bench-before.sh "$before_ref" "$work/before.txt"
before() { awk -v k="$1" '$1 == k { print $2 }' "$work/before.txt"; }
change() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%+.1f %%", 100 * (b - a) / a }'; }

# The micro:bit's default build, as tests/firmware.rs holds it: Program 1 at
# its defaults (point 70, stratified and adaptive), baked, 160x120.
step "microbit: the default build (Program 1 at its defaults)"
"$lensray" emulate scenes/paper-program1.scene --board microbit -o "$work/microbit-default.bmp" >"$work/microbit-default.log"
default_rays=$("$lensray" render scenes/paper-program1.scene --width $W --height $H -o "$work/host-default.bmp" 2>/dev/null | sed -n 's/^rays per pixel: //p')

# The Pico under rp2040js, panel included: cycles of its 125 MHz clock.
step "pico: Program 1 pinhole at 320x240 under rp2040js"
"$lensray" emulate "$work/program1-pinhole.scene" --board pico --width 320 --height 240 -o "$work/pico.png" >"$work/pico.log"
pico() { sed -n 's/^report board=pico //p' "$work/pico.log" | tr ' ' '\n' | sed -n "s/^$1=//p"; }

step "microbit: per-operation profile (firmware feature profile)"
profile() { # scene width height samples -> profile lines
  (cd firmware && LENSRAY_SCENE="$1" LENSRAY_WIDTH=$2 LENSRAY_HEIGHT=$3 LENSRAY_SAMPLES=$4 \
    cargo run -q --profile microbit --features microbit,profile --target thumbv6m-none-eabi)
}
profile "$work/program1-pinhole.scene" 80 60 1 >"$work/profile-pinhole.log"
profile "$work/program1-lens.scene" 40 30 16 >"$work/profile-lens16.log"
# A table from the profile lines: calls a pixel, instructions a call, instructions a pixel, share of the pixel.
profile_table() {
  awk '
    /^profile op=/ {
      for (i = 2; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] }
      n++; op[n] = v["op"]; calls[n] = v["calls"]; ins[n] = v["instructions"]
      if (v["op"] == "pixel") px = v["calls"]
    }
    END {
      print "| operation | calls per pixel | instructions per call | instructions per pixel | share of a pixel |"
      print "|---|---|---|---|---|"
      total = 0; for (i = 1; i <= n; i++) if (op[i] == "pixel") total = ins[i]
      for (i = 1; i <= n; i++) {
        if (calls[i] == 0) continue
        printf "| %s | %.2f | %d | %d | %.1f %% |\n", op[i], calls[i] / px, ins[i] / calls[i], ins[i] / px, 100 * ins[i] / total
      }
    }' "$1"
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }

# Lens sampling against converged references (host-tests/benches/sampling.rs;
# alone: bash scripts/bench-sampling.sh). References are cached in target/converged/.
step "host: lens sampling against converged references (host-tests/benches/sampling.rs)"
# Forty generated lens scenes from a fixed first seed (their references stay
# cached from one run to the next), with every lens scene of scenes/ and
# host-tests/extra-scenes/.
LENSRAY_SAMPLING_FIRST_SEED=31000 LENSRAY_SAMPLING_OUT="$work/sampling.md" cargo bench -q -p lensray-host --bench sampling >&2

step "writing $out"
{
  echo "# lensray benchmarks"
  echo
  echo "Written by \`bash scripts/bench.sh\` on $(date -u '+%Y-%m-%d %H:%M UTC'), commit"
  echo "\`$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src firmware host-tests || echo ', with local changes')\`,"
  echo "$(rustc --version), $(qemu-system-arm --version | head -1), on $(nproc) cores."
  echo "Each table names the command that makes it; \`lensray\` is \`target/release/lensray\`"
  echo "(\`cargo run --release --\`). Instruction counts are exact and repeatable (QEMU"
  echo "\`-icount shift=0\`: the cycle counter counts instructions); instructions are not"
  echo "cycles (a Cortex-M4 \`vdiv\` counts one)."
  echo
  echo "## Q16.16 against f32"
  echo
  echo "Each scene rendered in both number types with the same lens samples:"
  echo "\`adaptive off\` appended (and \`sampler independent\` for \`scenes/\`), as the host"
  echo "tests render them, then"
  echo
  echo '```sh'
  echo "lensray compare SCENE --width 320 --height 240     # scenes/*.scene"
  echo "lensray compare SCENE --width 160 --height 120     # host-tests/tests/stress/*.scene"
  echo '```'
  echo
  echo "Levels are of 255; *within* counts pixels whose three channels are all that"
  echo "close; *worst line* is the largest mean error of a row or column, *bias* the"
  echo "largest mean signed error of a row or column in any channel (docs/accuracy.md)."
  echo
  echo "| scene | size | rays/pixel | PSNR | max error | within 1 | within 2 | worst line | bias |"
  echo "|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${accuracy_rows[@]}"
  echo
  echo "## Program 1 at ${W}x${H} on the boards"
  echo
  echo '```sh'
  echo "lensray emulate P1 --board BOARD --width $W --height $H [--float]                # P1: Program 1 with \"radius 0\" appended"
  echo "lensray emulate P1 --board BOARD --width $W --height $H --samples 16 [--float]   # P1: Program 1 with \"adaptive off\" appended"
  echo '```'
  echo
  echo "| board | camera | rays/pixel | number | instructions/pixel | instructions/ray | flash (text) bytes | static RAM bytes | peak stack bytes |"
  echo "|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "![Instructions a pixel on each QEMU board, Program 1 through a pinhole, Q16.16 and f32](docs/bench-boards-pinhole.png)"
  echo
  echo "![Instructions a pixel on each QEMU board, Program 1 with 16 lens samples, Q16.16 and f32](docs/bench-boards-lens.png)"
  echo
  echo "The two plots: the table's instructions a pixel, drawn by"
  echo "\`cargo run --release -p lensray-host --example bar_chart -- OUT TITLE SERIES LABEL=V,V...\`."
  echo
  echo "Flash is the firmware's \`.text\` (code and constants: the baked scene included;"
  echo "\`llvm-size\`); static RAM is \`.data\` + \`.bss\`; the peak stack is measured by"
  echo "painting. *f32 (software)*: the core has no FPU."
  echo
  echo "### f32 / Q16.16: how many times fewer instructions fixed point needs"
  echo
  echo "From the table above."
  echo
  echo "| board | pinhole | 16 lens samples |"
  echo "|---|---|---|"
  for b in "${boards[@]}"; do
    echo "| $b | $(ratio "${per_pixel[$b-pinhole-f32]}" "${per_pixel[$b-pinhole-q16]}") | $(ratio "${per_pixel[$b-lens16-f32]}" "${per_pixel[$b-lens16-q16]}") |"
  done
  echo
  echo "Below 1 means f32 is faster: the Cortex-M4F's FPU beats Q16.16."
  echo
  echo "### Before and after the speed work"
  echo
  echo '```sh'
  echo "bash scripts/bench-before.sh $before_ref OUT   # the runs above at commit $before_ref"
  echo '```'
  echo
  echo "Instructions a pixel at commit \`$before_ref\` and now, the same runs as the table above."
  echo
  echo "| board | pinhole Q16.16 | pinhole f32 | 16 lens samples Q16.16 | 16 lens samples f32 |"
  echo "|---|---|---|---|---|"
  for b in "${boards[@]}"; do
    cells=""
    for k in pinhole-q16 pinhole-f32 lens16-q16 lens16-f32; do
      was=$(before "$b-$k"); now=${per_pixel[$b-$k]}
      cells+=" $was -> $now ($(change "$was" "$now")) |"
    done
    echo "| $b |$cells"
  done
  echo
  echo "### The micro:bit's default build"
  echo
  echo '```sh'
  echo "lensray emulate scenes/paper-program1.scene --board microbit                   # 160x120, point 70, adaptive"
  echo "lensray render scenes/paper-program1.scene --width $W --height $H              # the rays a pixel"
  echo '```'
  echo
  echo "| flash bytes | static RAM bytes | peak stack bytes | instructions/pixel | at \`$before_ref\` | rays/pixel (mean) |"
  echo "|---|---|---|---|---|---|"
  d="$work/microbit-default.log"
  echo "| $(field "$d" flash) (floor 40,960) | $(field "$d" static_ram) | $(field "$d" peak_stack) (with the statics, floor 8,192) | $(field "$d" per_pixel) | $(before microbit-default) ($(change "$(before microbit-default)" "$(field "$d" per_pixel)")) | $default_rays |"
  echo
  echo "Flash here is the report's \`.text\` + \`.rodata\` + \`.data\`. The floors are"
  echo "\`host-tests/tests/firmware.rs\`'s (with $(sed -n 's/^const MICROBIT_PINHOLE: u64 = \([0-9]*\);/\1/p' host-tests/tests/firmware.rs) instructions a pixel for Program 1"
  echo "pinhole); the adaptive pre-pass runs on the host when the scene is baked."
  echo
  echo "### Raspberry Pi Pico under rp2040js"
  echo
  echo '```sh'
  echo "lensray emulate P1 --board pico --width 320 --height 240     # P1: Program 1 with \"radius 0\" appended"
  echo '```'
  echo
  echo "| scene | size | rays/pixel | cycles/pixel | frame at 125 MHz, one core | two cores (estimate) |"
  echo "|---|---|---|---|---|---|"
  echo "| Program 1 pinhole (radius 0) | 320x240 | $(pico rays) | $(pico cycles_per_pixel) | $(awk -v s="$(pico seconds_125mhz)" 'BEGIN { printf "%.2f s", s }') | $(awk -v s="$(pico two_core_estimate_seconds_125mhz)" 'BEGIN { printf "%.2f s", s }') |"
  echo
  echo "Cycles are rp2040js's (one a plain instruction, more for loads, branches and"
  echo "peripherals), from the LED's rise to its fall: the progressive passes and the"
  echo "SPI transfers to the panel model included. rp2040js runs one core; the two-core"
  echo "figure replays the firmware's band protocol on the bands' measured cycles."
  echo "It leaves out what the cores contend for: the flash behind the XIP cache, the"
  echo "SIO FIFO and spinlock between the bands, the SPI bus to the panel; a real"
  echo "board's two-core frame is this figure or slower."
  echo
  echo "## Where the Cortex-M0's instructions go (Program 1, Q16.16)"
  echo
  echo '```sh'
  echo "cd firmware && LENSRAY_SCENE=P1 LENSRAY_WIDTH=80 LENSRAY_HEIGHT=60 LENSRAY_SAMPLES=1 \\"
  echo "  cargo run --profile microbit --features microbit,profile --target thumbv6m-none-eabi"
  echo '```'
  echo
  echo "(P1 as above; 40x30 and \`LENSRAY_SAMPLES=16\` for the lens.) The firmware's"
  echo "\`profile\` feature (firmware/src/profile.rs) times each operation on its own"
  echo "through the library's API, over every pixel. The search meets each object"
  echo "with its cone test first (can a ray from the lens reach the object's bounding"
  echo "sphere at all: src/render/cull.rs); the intersections are the tests of the"
  echo "objects it keeps, limited by the nearest hit so far. *Shading* is the trace"
  echo "less the nearest-hit search (the normal, the texture, the ambient term and"
  echo "every light), and light k's share is what the trace costs more with lights"
  echo "1..k than with 1..k-1. Shading calls count the rays that hit."
  echo
  echo "### Pinhole, 80x60"
  echo
  profile_table "$work/profile-pinhole.log"
  echo
  echo "### Radius 0.2, 16 lens samples, 40x30"
  echo
  profile_table "$work/profile-lens16.log"
  echo
  echo "## Host: rays per second (Program 1 at ${W}x${H})"
  echo
  echo '```sh'
  echo "cargo bench -p lensray-host --bench render"
  echo '```'
  echo
  echo "criterion's medians on $(nproc) cores; load average before the run $load_before,"
  echo "after it $load_after (the machine is shared: a load above about 1 means other"
  echo "work took cores and the all-cores figures are low). Both columns run the same"
  echo "\`render_image\` (rows in parallel, one row a task); one thread is a rayon pool"
  echo "of one."
  echo
  echo "| number | camera | 1 thread, rays/s | all cores, rays/s |"
  echo "|---|---|---|---|"
  for n in Q16.16 f32; do
    for m in pinhole lens16; do
      one=$(rate "program1-160x120/$n/1-thread/$m")
      all=$(rate "program1-160x120/$n/all-cores/$m")
      echo "| $n | $([ $m = pinhole ] && echo pinhole || echo "16 lens samples") | $one | $all |"
    done
  done
  echo
  echo "## Host: parallel speedup, in pairs (Program 1 at ${W}x${H})"
  echo
  echo '```sh'
  echo "cargo bench -p lensray-host --bench speedup"
  echo '```'
  echo
  echo "$(paired "program1-160x120/Q16.16/pinhole" rounds) repetitions a render, each rendering the frame for about 40 ms on one"
  echo "thread and as long on all $(paired "program1-160x120/Q16.16/pinhole" threads) cores, back to back (criterion's two"
  echo "columns above are minutes apart, so their ratio also measures the neighbours),"
  echo "and measuring the *ceiling* in the same repetition: as many whole frames, each"
  echo "rendered row after row by one thread, one after another on one thread or side"
  echo "by side, one a core: the same work with nothing split or shared, the best this"
  echo "machine gives it at that moment. The *efficiency* is a repetition's speedup over"
  echo "its ceiling, what splitting a frame's rows costs. Medians over the repetitions; *best* is"
  echo "the fastest one-thread batch over the fastest all-cores batch; *steal* the share"
  echo "of CPU time the hypervisor took."
  echo
  echo "| number | camera | speedup: median (quartiles) | best | ceiling | efficiency | steal |"
  echo "|---|---|---|---|---|---|---|"
  for n in Q16.16 f32; do
    for m in pinhole lens16; do
      key="program1-160x120/$n/$m"
      echo "| $n | $([ $m = pinhole ] && echo pinhole || echo "16 lens samples") | $(paired "$key" median) ($(paired "$key" q1) to $(paired "$key" q3)) | $(paired "$key" best) | $(paired "$key" ceiling) | $(paired "$key" efficiency) | $(paired "$key" steal) |"
    done
  done
  echo
  echo "An efficiency of 1 or more means the render uses all the parallelism the"
  echo "machine gave; a speedup below the core count with the ceiling below it too is"
  echo "the machine's, not the code's."
  echo
  echo "## Lens sampling"
  echo
  echo '```sh'
  echo "LENSRAY_SAMPLING_FIRST_SEED=31000 cargo bench -p lensray-host --bench sampling   # or: bash scripts/bench-sampling.sh"
  echo '```'
  echo
  echo "![PSNR against converged references over mean rays a pixel, a panel for each lens scene of scenes/](docs/sampling.png)"
  echo
  echo "The plot (written by the same command): each lens scene of \`scenes/\`, PSNR over mean"
  echo "rays a pixel for independent (grey) and plain stratified samples (blue), and the"
  echo "default render (red). The tables: every lens scene of \`scenes/\` and"
  echo "\`host-tests/extra-scenes/\`, and forty of the scene generator's lens scenes"
  echo "(docs/sampling.md says how the sampler works)."
  echo
  cat "$work/sampling.md"
} >"$out"
cat "$out"
lines=$(wc -l <"$out")
if [ "$lines" -gt 400 ]; then
  echo "bench.sh: $out has $lines lines, more than the 400 it should hold" >&2
  exit 1
fi
