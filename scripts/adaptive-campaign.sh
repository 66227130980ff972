#!/usr/bin/env bash
# The adaptive floors (issue 14) over many of the scene generator's lens
# scenes: for each seed, the default render (Q16.16, stratified, adaptive)
# against a converged f32 reference, beside `point` independent samples and
# stratified samples at 40 % of `point` for every pixel.
#   bash scripts/adaptive-campaign.sh [FIRST_SEED] [SEEDS] [WIDTH] [REFERENCE]
# Defaults: seeds 1..40, 160x120, 1024 reference samples (references cached
# in target/converged/); about a minute a seed at 160x120 on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run -q --release -p lensray-host --example adaptive_campaign -- "$@"
