#!/usr/bin/env bash
# Every benchmark, measured from scratch, written to BENCHMARKS.md:
#   bash scripts/bench.sh [OUT]        (OUT defaults to BENCHMARKS.md)
# - Cortex-M0 (microbit) and Cortex-M4F (mps2-an386) under QEMU with
#   -icount shift=0: instructions per pixel and per ray for Program 1 at
#   160x120, pinhole (radius 0) and with 16 lens samples, Q16.16 and f32, the
#   f32 / Q16.16 ratio per core, flash, static RAM and peak stack;
# - the issue-5 floors on the M0 (checked, printed, never a test failure);
# - a per-operation profile on the M0 (firmware feature `profile`);
# - host rays per second (criterion, host-tests/benches/render.rs), one thread
#   and all cores, with the machine's load, and the parallel speedup measured
#   in pairs beside the machine's ceiling for the same work (whole frames side
#   by side: host-tests/benches/speedup.rs);
# - lens sampling: the adaptive render against converged references, beside
#   `point` independent samples and plain stratified samples at its rays, as
#   distributions over the scenes (host-tests/benches/sampling.rs; the curves
#   of scenes/ in docs/sampling.png).
# Takes about 15-25 minutes on 2 cores (firmware builds with fat LTO dominate).
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

rows=()
declare -A per_pixel
for board in microbit mps2-an386; do
  case $board in microbit) core="Cortex-M0"; target=thumbv6m-none-eabi ;; *) core="Cortex-M4F"; target=thumbv7em-none-eabihf ;; esac
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
      label=$([ $number = q16 ] && echo "Q16.16" || { [ $board = microbit ] && echo "f32 (software)" || echo "f32 (FPU, vsqrt.f32)"; })
      rows+=("| $board ($core) | $([ $mode = pinhole ] && echo "pinhole (radius 0)" || echo "lens, radius 0.2") | $rays | $label | $pp | $per_ray | $text | $((data + bss)) | $(field "$log" peak_stack) |")
    done
  done
done

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
m0_fixed=${per_pixel[microbit-pinhole-q16]}
m0_f32=${per_pixel[microbit-pinhole-f32]}
m0_ratio=$(ratio "$m0_f32" "$m0_fixed")
floor_ins=$([ "$m0_fixed" -le 8000 ] && echo met || echo "NOT met")
floor_ratio=$(awk -v r="$m0_ratio" 'BEGIN { print (r >= 2.5) ? "met" : "NOT met" }')

speedups=()
ceilings=""
for n in Q16.16 f32; do
  for m in pinhole lens16; do
    speedups+=("$(paired "program1-160x120/$n/$m" median)")
    ceilings+="${ceilings:+, }$(paired "program1-160x120/$n/$m" ceiling)"
  done
done
min_speedup=$(printf '%s\n' "${speedups[@]}" | sort -g | head -1)
floor_speedup=$(awk -v r="$min_speedup" 'BEGIN { print (r >= 1.8) ? "met" : "NOT met" }')

# Lens sampling against converged references (host-tests/benches/sampling.rs;
# alone: bash scripts/bench-sampling.sh). References are cached in target/converged/.
step "host: lens sampling against converged references (host-tests/benches/sampling.rs)"
# Forty generated lens scenes from seed 31000 (a block whose references the
# sampling campaign of issue 53 cached), with every lens scene of scenes/ and
# host-tests/extra-scenes/.
LENSRAY_SAMPLING_FIRST_SEED=31000 LENSRAY_SAMPLING_OUT="$work/sampling.md" cargo bench -q -p lensray-host --bench sampling >&2

step "writing $out"
{
  echo "# lensray benchmarks"
  echo
  echo "Produced by \`bash scripts/bench.sh\` on $(date -u '+%Y-%m-%d %H:%M UTC'), commit"
  echo "\`$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src firmware host-tests || echo ', with local changes')\`,"
  echo "$(rustc --version), $(qemu-system-arm --version | head -1)."
  echo "Instruction counts are exact and repeatable (QEMU \`-icount shift=0\`: SysTick counts"
  echo "instructions); instructions are not cycles (a Cortex-M4 \`vdiv\` counts one)."
  echo
  echo "## Program 1 at ${W}x${H} on the boards"
  echo
  echo "| board | camera | rays/pixel | number | instructions/pixel | instructions/ray | flash (text) bytes | static RAM bytes | peak stack bytes |"
  echo "|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "Flash is the firmware's \`.text\` (code and constants, the scene text included);"
  echo "static RAM is \`.data\` + \`.bss\`; the peak stack is measured by painting (the"
  echo "parser's working copy of the scene is most of it)."
  echo
  echo "### f32 / Q16.16: how many times fewer instructions fixed point needs"
  echo
  echo "| core | pinhole | 16 lens samples |"
  echo "|---|---|---|"
  for b in microbit mps2-an386; do
    echo "| $b | $(ratio "${per_pixel[$b-pinhole-f32]}" "${per_pixel[$b-pinhole-q16]}") | $(ratio "${per_pixel[$b-lens16-f32]}" "${per_pixel[$b-lens16-q16]}") |"
  done
  echo
  echo "Below 1 means f32 is faster: the Cortex-M4F's FPU beats Q16.16."
  echo
  echo "### Floors (issue 5), Cortex-M0, Program 1 pinhole, ${W}x${H}"
  echo
  echo "- at most 8,000 instructions per pixel in Q16.16: $m0_fixed, **$floor_ins**;"
  echo "- f32 (software) at least 2.5 times the instructions of Q16.16: ${m0_ratio}x, **$floor_ratio**;"
  echo "- host rows in parallel, speedup at least 1.8 on 2 cores: lowest ${min_speedup} (the paired medians of all four renders below; the ceiling, whole frames side by side in the same rounds: $ceilings), **$floor_speedup**."
  echo
  echo "## Where the Cortex-M0's instructions go (Program 1, Q16.16)"
  echo
  echo "Measured by the firmware's \`profile\` feature (firmware/src/profile.rs):"
  echo "each operation timed on its own with SysTick through the library's API, over"
  echo "every pixel. The search meets each object with its cone test first (can a"
  echo "ray from the lens reach the object's bounding sphere at all: src/render/cull.rs);"
  echo "*culled-objects* counts the objects it skips, and the intersections are the"
  echo "tests of the others, limited by the nearest hit so far. *Shading* is the"
  echo "trace less the nearest-hit search (the"
  echo "normal, the texture, the ambient term and every light), and light k's share"
  echo "is what the trace costs more with lights 1..k than with 1..k-1 (shadow rays"
  echo "included where the scene has them). Shading calls count the rays that hit."
  echo
  echo "### Pinhole, 80x60"
  echo
  profile_table "$work/profile-pinhole.log"
  echo
  echo "### Radius 0.2, 16 lens samples, 40x30"
  echo
  profile_table "$work/profile-lens16.log"
  echo
  echo "## Host: rays per second (criterion, Program 1 at ${W}x${H})"
  echo
  echo "\`cargo bench -p lensray-host --bench render\` on $(nproc) cores; load average"
  echo "before the run $load_before, after it $load_after (the machine is shared: a"
  echo "load above about 1 means other work took cores and the all-cores figures are low)."
  echo
  echo "Both columns run the same \`render_image\` (rows in parallel, one row a"
  echo "task); one thread is a rayon pool of one."
  echo
  echo "| number | camera | 1 thread, rays/s | all cores, rays/s | ratio of the two |"
  echo "|---|---|---|---|---|"
  for n in Q16.16 f32; do
    for m in pinhole lens16; do
      one=$(rate "program1-160x120/$n/1-thread/$m")
      all=$(rate "program1-160x120/$n/all-cores/$m")
      echo "| $n | $([ $m = pinhole ] && echo pinhole || echo "16 lens samples") | $one | $all | $(ratio "$all" "$one") |"
    done
  done
  echo
  echo "The ratio of criterion's medians compares runs made minutes apart, so it"
  echo "also measures how the neighbours' load changed in between (above 2 on 2"
  echo "cores is that). The speedup is measured in pairs instead:"
  echo
  echo "### Host: parallel speedup, in pairs (Program 1 at ${W}x${H})"
  echo
  echo "\`cargo bench -p lensray-host --bench speedup\` (host-tests/benches/speedup.rs):"
  echo "$(paired "program1-160x120/Q16.16/pinhole" rounds) rounds a render, each rendering the frame for about 40 ms on one"
  echo "thread and as long on all $(paired "program1-160x120/Q16.16/pinhole" threads) cores, back to back, and"
  echo "measuring the *ceiling* in the same round: as many whole frames, each"
  echo "rendered row after row by one thread, one after another on one thread or side"
  echo "by side, one a core. That is the same work with nothing split or shared, the"
  echo "best this machine gives it at that moment; the *efficiency* is a round's"
  echo "speedup over its ceiling, what splitting a frame's rows costs (above 1: the"
  echo "split frame did better than whole frames side by side). Medians over the"
  echo "rounds; *best* is the fastest one-thread batch over the fastest all-cores batch."
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
  echo "Steal is the share of CPU time the hypervisor took during a render's rounds."
  echo "An efficiency of 1 or more means the render uses all the parallelism the"
  echo "machine gave; a speedup below the floor with the ceiling below it too is the"
  echo "machine's, not the code's."
  echo
  echo "## Lens sampling"
  echo
  echo "\`LENSRAY_SAMPLING_FIRST_SEED=31000 cargo bench -p lensray-host --bench sampling\` (alone: \`bash scripts/bench-sampling.sh\`;"
  echo "plot: [docs/sampling.png](docs/sampling.png)). Every lens scene of \`scenes/\` and"
  echo "\`host-tests/extra-scenes/\`, and forty of the scene generator's lens scenes."
  echo
  cat "$work/sampling.md"
} >"$out"
cat "$out"
