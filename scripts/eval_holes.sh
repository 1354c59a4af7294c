#!/usr/bin/env bash
# The hole fill's protocol (docs/quality.md, Holes): scores the default fill against the nearest
# texel on the generated set's validation split (out/eval_holes/validation), where the choice is
# made, then on its test split and on the seven hand-written scenes (out/eval_holes/test,
# out/eval_holes/hand_written), which it was not chosen on. Renders what is missing at 640x360:
# the generated splits as scripts/eval_generated.sh does (13 frames: 6 targets), the
# hand-written scenes as scripts/eval.sh does (17 frames: 8 targets). Publishes the three
# tables into docs/results/. The guide's other findings (windows, widths, on-screen holes only)
# come from the same run with fill_holes.wgsl's constants or warp_gbuffer.wgsl's deferral
# edited.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/scenes.sh
source scripts/lib/results.sh
methods=copy,occlusion-motion,gbuffer,gbuffer-nearest-fill
for which in validation test; do
    datasets=()
    for scene in $(split "$which"); do
        render_once "scenes/generated/$scene.toml" 13 "out/eval_generated/datasets/$scene"
        datasets+=("out/eval_generated/datasets/$scene")
    done
    target/release/patchex eval "${datasets[@]}" --methods "$methods" --out "out/eval_holes/$which"
done
datasets=()
for scene in scenes/*.toml; do
    name=$(basename "$scene" .toml)
    render_once "$scene" 17 "out/datasets/$name"
    datasets+=("out/datasets/$name")
done
target/release/patchex eval "${datasets[@]}" --methods "$methods" --out out/eval_holes/hand_written
for which in validation test hand_written; do
    publish "out/eval_holes/$which/eval.md" "eval_holes_$which.md"
done
