#!/usr/bin/env bash
# The web page's checks: the wasm crate's format, lint and native tests, the
# library for wasm32-unknown-unknown, the page's build, and the browser tests
# (Playwright driving Debian's Chromium, headless). Installs what is missing:
# the wasm target (rustup), chromium (apt), playwright-core (npm ci, lockfile).
#   bash scripts/web-tests.sh
set -euo pipefail
cd "$(dirname "$0")/.."

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
if [ ! -x /usr/bin/chromium ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium >/dev/null
  else
    echo "chromium is missing: install it (Debian: sudo apt-get install chromium) and run again" >&2
    exit 1
  fi
fi
if ! command -v node >/dev/null 2>&1; then
  echo "node is missing (Node 20 or later): install it and run again" >&2
  exit 1
fi
if [ ! -d web/node_modules/playwright-core ]; then
  (cd web && npm ci --no-audit --no-fund)
fi

cargo build -p lensray --release --target wasm32-unknown-unknown
(cd web/wasm && cargo fmt --check && cargo clippy --all-targets -- -D warnings && cargo test)
bash web/build.sh
(cd web && node --test tests/)
