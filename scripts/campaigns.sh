#!/usr/bin/env bash
# lensray's longer test campaigns: what a plain `cargo test` leaves out.
#   bash scripts/campaigns.sh                 the host tests marked
#       #[ignore = "campaign: ..."] and a minute of fuzzing (about 2 minutes on
#       2 cores once built; scripts/test-all.sh leaves them out, for time)
#   LENSRAY_FUZZ_SECS=3600 bash scripts/campaigns.sh
#                                             the same with an hour of fuzzing
#   bash scripts/campaigns.sh --exhaustive    also the library's checks over
#       every 32-bit input (the square root and the divisor's reciprocal)
# The firmware's tests under QEMU and rp2040js are scripts/firmware-tests.sh's.
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

step "host tests' campaigns (#[ignore = \"campaign: ...\"] in host-tests/tests/)"
# Found by their marker, so a new campaign cannot be left out; the fuzz test runs next, timed.
if grep -rln 'ignore = "campaign' src host-tests/src host-tests/testkit; then
  echo "campaign tests are run from host-tests/tests/ only: move the ones above there" >&2
  exit 1
fi
campaigns=()
for f in $(grep -l 'ignore = "campaign' host-tests/tests/*.rs); do
  name=$(basename "$f" .rs)
  if [ "$name" != fuzz ]; then campaigns+=(--test "$name"); fi
done
cargo test -p lensray-host "${campaigns[@]}" -- --ignored

fuzz_secs=${LENSRAY_FUZZ_SECS:-60}
step "fuzz: parser and renderer together, ${fuzz_secs} s (LENSRAY_FUZZ_SECS)"
LENSRAY_FUZZ_SECS=$fuzz_secs cargo test -p lensray-host --test fuzz fuzz_parser_and_renderer -- --ignored --nocapture

if [ "$exhaustive" = 1 ]; then
  step "the library's exhaustive checks over every 32-bit input"
  cargo test -p lensray --lib exhaustive -- --ignored
fi
step "campaigns passed"
