#!/usr/bin/env bash
# Lens sampling alone: PSNR against converged references as a function of mean
# rays a pixel, independent against stratified lens samples, and the default
# render (stratified, adaptive), for every lens scene in scenes/ (and the
# scenes in LENSRAY_SAMPLING_EXTRA, a folder, when set). Prints the table,
# writes it to target/sampling.md and the plot to docs/sampling.png.
#   bash scripts/bench-sampling.sh
# Settings: LENSRAY_SAMPLING_WIDTH (320), LENSRAY_SAMPLING_REFERENCE (2048).
# The first run renders the references (about 10 minutes on 2 cores at
# 320x240) and caches them in target/converged/; later runs take about 2.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench -q -p lensray-host --bench sampling
