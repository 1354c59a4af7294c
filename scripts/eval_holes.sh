#!/usr/bin/env bash
# The hole fill's protocol (README, Holes): renders every scene at 640x360 (9 frames: 4 targets),
# compares the fills on the validation scenes (out/eval_holes/validation), where the choice is
# made, and reports them on the test scenes the networks never saw (out/eval_holes/test).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
validation=(dance_static follow_chase forest_walk orbit_plaza shadow_terrain)
test=(crossing_street fast_run)
for scene in "${validation[@]}" "${test[@]}"; do
    target/release/patchex render "scenes/$scene.toml" --frames 9 --size 640x360 \
        --out "out/eval_holes/datasets/$scene"
done
methods=copy,occlusion-motion,gbuffer,gbuffer-nearest-fill
target/release/patchex eval "${validation[@]/#/out/eval_holes/datasets/}" \
    --methods "$methods" --out out/eval_holes/validation
target/release/patchex eval "${test[@]/#/out/eval_holes/datasets/}" \
    --methods "$methods,interpolation" --out out/eval_holes/test
