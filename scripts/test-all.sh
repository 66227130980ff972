#!/usr/bin/env bash
# lensray's one test command: installs what is missing, then runs every check.
#   bash scripts/test-all.sh
# Steps: rustup targets and components, Debian's qemu-system-arm, format and
# lint, the host tests, 20 s of fuzzing, the no_std library for three Cortex-M targets, the
# firmware under QEMU and rp2040js, and the web page in a browser.
#
# What runs where, and what it costs on 2 cores (measured from a clean build,
# with the tools already installed and the crates downloaded):
#   format and lint (fmt, clippy, rustdoc)                         1 min
#   cargo test --workspace, a plain `cargo test`: the library's unit
#     tests and doctests, the test kit's, the fast host tests      3.5 min build, 0.5 min run
#   the slow host tests (#[ignore = "slow: ..."]: every scene in
#     Q16.16 against f32, generated scenes and the sweep's corpus
#     against their floors, renderer arguments at their extremes)  1 min
#   20 s of fuzzing the parser and renderer together               0.5 min
#   the no_std library for thumbv6m, thumbv7m, thumbv7em            1.5 min
#   scripts/firmware-tests.sh: lint, builds, QEMU and the Pico      7 min
#   scripts/web-tests.sh: wasm, the page's build, browser tests     3 min
#   in all                                                          11 to 17 min (10 min 21 s measured)
# Not run here: `bash scripts/campaigns.sh` (fuzzing for ten minutes, an
# hour with LENSRAY_FUZZ_SECS=3600; the exhaustive 32-bit checks with
# --exhaustive) and the benchmarks (scripts/bench.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step prints the time since the script started (bash's SECONDS).
step() { printf '\n==> [%d:%02d] %s\n' $((SECONDS / 60)) $((SECONDS % 60)) "$*"; }

# A clean clone's build took 7 GB with incremental caches and full debug info,
# and CI once ran out of disk on it: neither helps a one-off run.
export CARGO_INCREMENTAL=0
export CARGO_PROFILE_DEV_DEBUG=line-tables-only CARGO_PROFILE_TEST_DEBUG=line-tables-only
step "disk: $(df -Ph . | awk 'NR==2 {print $4}') free where the build goes"

step "toolchain: targets and components"
targets="thumbv6m-none-eabi thumbv7m-none-eabi thumbv7em-none-eabihf"
installed=$(rustup target list --installed)
for t in $targets; do
  if ! grep -qx "$t" <<<"$installed"; then rustup target add "$t"; fi
done
for c in clippy rustfmt; do
  if ! cargo "${c/rustfmt/fmt}" --version >/dev/null 2>&1; then rustup component add "$c"; fi
done

step "emulator: qemu-system-arm"
if ! command -v qemu-system-arm >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends qemu-system-arm >/dev/null
  else
    echo "qemu-system-arm is missing: install it (Debian: sudo apt-get install qemu-system-arm) and run again" >&2
    exit 1
  fi
fi

step "format and lint"
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc -p lensray --no-deps

step "host tests (the library's unit tests and doctests, the test kit's, the host's): a plain cargo test"
cargo test --workspace

step "host tests too slow for a plain cargo test (#[ignore = \"slow: ...\"])"
# Found by their marker, so a new slow test cannot be left out.
if grep -rln 'ignore = "slow' src host-tests/src host-tests/testkit; then
  echo "slow tests are run from host-tests/tests/ only: move the ones above there" >&2
  exit 1
fi
slow=()
for f in $(grep -l 'ignore = "slow' host-tests/tests/*.rs); do slow+=(--test "$(basename "$f" .rs)"); done
cargo test -p lensray-host "${slow[@]}" -- --ignored

step "fuzz: parser and renderer together, 20 s (scripts/campaigns.sh runs it longer)"
LENSRAY_FUZZ_SECS=20 cargo test -p lensray-host --test fuzz fuzz_parser_and_renderer -- --ignored --nocapture

step "fuzz/ (cargo fuzz's crate) resolves from its lock file (compiling libFuzzer's C++ is left to cargo fuzz)"
(cd fuzz && cargo metadata --locked --format-version 1 >/dev/null)

step "no_std library for Cortex-M0, Cortex-M3 and Cortex-M4F"
for t in $targets; do
  cargo build -p lensray --release --target "$t"
done

if [ -d firmware ]; then
  step "firmware"
  bash scripts/firmware-tests.sh
fi

step "web page: wasm, build, browser tests (scripts/web-tests.sh)"
bash scripts/web-tests.sh

step "all checks passed"
