#!/usr/bin/env bash
# Renders every scene in scenes/ at 640x360 (17 frames: 8 targets between rendered frames), fits
# the segmentation's k_x and k_y on them, and scores every method against the ground truth.
# Writes out/datasets/, out/calibration.json and out/eval/ (eval.md, eval.json, strips/).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
datasets=()
for scene in scenes/*.toml; do
    name=$(basename "$scene" .toml)
    target/release/patchex render "$scene" --frames 17 --size 640x360 --out "out/datasets/$name"
    datasets+=("out/datasets/$name")
done
target/release/patchex calibrate "${datasets[@]}" --json out/calibration.json
target/release/patchex eval "${datasets[@]}" --out out/eval "$@"
