#!/usr/bin/env bash
# The speed guide's measurements: `patchex bench` over every configuration at 360p to 1080p on
# the test scenes, with the G-buffer in a deferred renderer's formats, then the networks' FP16
# against FP32 tensors. Publishes the tables and the quality-against-time plot into
# docs/results/. Arguments go to the first bench (e.g. --sizes).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/results.sh
# A CPU driver has no idle clock to leave: no warm-up.
target/release/patchex bench --input-formats engine --warm-up-ms 0 --out out/bench "$@"
target/release/patchex bench --configurations patchex,patchex-fp32 --sizes 640x360,1280x720 \
    --warm-up-ms 0 --out out/bench_precision
publish out/bench/bench.md bench.md
publish out/bench/bench.json bench.json
publish out/bench/trade.png trade.png
publish out/bench_precision/bench.md bench_precision.md
