#!/usr/bin/env bash
# Builds the web page into web/dist/, a plain static folder:
#   bash web/build.sh
# The library compiled to WebAssembly (web/wasm, wasm32-unknown-unknown; the
# target comes by rustup where missing), the hand-written page (no JS build
# step), and the presets: every scenes/*.scene, copied.
set -euo pipefail
web="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$web")"

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
cargo build --release --target wasm32-unknown-unknown --manifest-path "$web/wasm/Cargo.toml"

dist="$web/dist"
rm -rf "$dist.tmp"
mkdir -p "$dist.tmp/scenes"
cp "$web/wasm/target/wasm32-unknown-unknown/release/lensray_wasm.wasm" "$dist.tmp/lensray.wasm"
cp "$web"/index.html "$web"/style.css "$web"/app.js "$web"/worker.js "$web"/png.js "$dist.tmp/"
: >"$dist.tmp/scenes/index.txt"
for f in "$root"/scenes/*.scene; do
  name="$(basename "$f" .scene)"
  cp "$f" "$dist.tmp/scenes/"
  echo "$name" >>"$dist.tmp/scenes/index.txt"
done
# Swap in whole: a failed build never leaves a half-written dist/.
rm -rf "$dist"
mv "$dist.tmp" "$dist"
echo "built $dist ($(wc -l <"$dist/scenes/index.txt") presets, lensray.wasm $(wc -c <"$dist/lensray.wasm") bytes)"
