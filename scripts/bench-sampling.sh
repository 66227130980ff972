#!/usr/bin/env bash
# Lens sampling alone (the "Lens sampling" section of BENCHMARKS.md): the
# default render (stratified, adaptive) of every lens scene in scenes/ and
# host-tests/extra-scenes/ and of forty generated lens scenes, against
# converged references, beside `point` independent samples and plain
# stratified samples at the same rays; the floors as distributions (min,
# median, max). Prints the tables, writes them to target/sampling.md and the
# curves of scenes/ to docs/sampling.png.
#   bash scripts/bench-sampling.sh
# Settings: LENSRAY_SAMPLING_WIDTH (320), LENSRAY_SAMPLING_REFERENCE (2048),
# LENSRAY_SAMPLING_FIRST_SEED (31000) and LENSRAY_SAMPLING_GENERATED (40):
# the generated block (its references stay cached from one run to the next).
# References are rendered once (about a minute a scene at 320x240 on 2
# cores) and cached in target/converged/.
set -euo pipefail
cd "$(dirname "$0")/.."
LENSRAY_SAMPLING_FIRST_SEED=${LENSRAY_SAMPLING_FIRST_SEED:-31000} cargo bench -q -p lensray-host --bench sampling
