#!/usr/bin/env bash
# lensray's longer test campaigns: what the test command (scripts/test-all.sh)
# runs only briefly or not at all.
#   bash scripts/campaigns.sh                 ten minutes of fuzzing the parser
#       and renderer together (the test command gives it 20 s)
#   LENSRAY_FUZZ_SECS=3600 LENSRAY_FUZZ_SEED=7 bash scripts/campaigns.sh
#                                             an hour, from another seed
#   bash scripts/campaigns.sh --exhaustive    also the library's checks over
#       every 32-bit input (the square root and the divisor's reciprocal)
# The random-scene sweeps and the benchmarks are their own commands (README).
set -euo pipefail
cd "$(dirname "$0")/.."

exhaustive=0
for arg in "$@"; do
  case "$arg" in
    --exhaustive) exhaustive=1 ;;
    *) echo "usage: bash scripts/campaigns.sh [--exhaustive]" >&2; exit 2 ;;
  esac
done

step() { printf '\n==> [%d:%02d] %s\n' $((SECONDS / 60)) $((SECONDS % 60)) "$*"; }

fuzz_secs=${LENSRAY_FUZZ_SECS:-600}
step "fuzz: parser and renderer together, ${fuzz_secs} s (LENSRAY_FUZZ_SECS)"
LENSRAY_FUZZ_SECS=$fuzz_secs cargo test -p lensray-host --test fuzz fuzz_parser_and_renderer -- --ignored --nocapture

if [ "$exhaustive" = 1 ]; then
  step "the library's exhaustive checks over every 32-bit input"
  cargo test -p lensray --lib exhaustive -- --ignored
fi
step "campaigns passed"
