#!/usr/bin/env bash
# Renders every scene in scenes/ at 640x360 (17 frames: 8 targets between rendered frames), fits
# the segmentation's k_x and k_y on them, and scores every method against the ground truth.
# Writes out/datasets/, out/calibration.json and out/eval/ (eval.md, eval.json, strips/); then
# renders three scenes as 3x streams and scores both instants into out/eval_3x/; last, PatchEX
# and its ablations on the two test scenes into out/eval_networks/. Publishes the tables and
# strips the quality guide shows into docs/results/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/results.sh
datasets=()
for scene in scenes/*.toml; do
    name=$(basename "$scene" .toml)
    target/release/patchex render "$scene" --frames 17 --size 640x360 --out "out/datasets/$name"
    datasets+=("out/datasets/$name")
done
target/release/patchex calibrate "${datasets[@]}" --json out/calibration.json
target/release/patchex eval "${datasets[@]}" --out out/eval "$@"
# 3x frame generation: two targets (alpha 1/3 and 2/3) between rendered frames.
datasets_3x=()
for name in crossing_street fast_run shadow_terrain; do
    target/release/patchex render "scenes/$name.toml" --frames 13 --size 640x360 \
        --targets-between 2 --out "out/datasets_3x/$name"
    datasets_3x+=("out/datasets_3x/$name")
done
target/release/patchex eval "${datasets_3x[@]}" --out out/eval_3x \
    --methods copy,motion-vector,occlusion-motion,gbuffer,gbuffer-shadows
# PatchEX and its ablations on the test scenes, which the shipped networks never saw in training.
target/release/patchex eval out/datasets/crossing_street out/datasets/fast_run --out out/eval_networks \
    --methods copy,motion-vector,occlusion-motion,gbuffer,gbuffer-shadows,patchex,patchex-every-pixel,patchex-no-shadows,patchex-whole-frame,patchex-no-perceptual,interpolation
publish out/eval/eval.md eval.md
publish out/eval/eval.json eval.json
publish out/eval/strips/fast_run.png eval_strip.png
publish out/eval/strips/fast_run_shadows.png shadow_strip.png
publish out/eval_3x/eval.md eval_3x.md
publish out/eval_networks/eval.md eval_networks.md
publish out/eval_networks/eval.json eval_networks.json
