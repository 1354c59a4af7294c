#!/usr/bin/env bash
# The main job: renders a real scene, extrapolates every target frame through the plugin and
# writes picture strips and a quality/GPU-time table to out/demo (arguments go to `patchex demo`).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
target/release/patchex demo "$@"
