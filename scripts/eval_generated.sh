#!/usr/bin/env bash
# The generated scene set's protocol (README, Evaluation on generated scenes): renders the
# validation and test splits of scenes/generated/split.toml at 640x360 (13 frames: 6 targets
# each) and scores the methods on each split apart: decisions are made on
# out/eval_generated/validation, the guides report out/eval_generated/test. Publishes both
# tables and the test split's strip into docs/results/. Arguments are passed to both evals (e.g.
# --methods).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/scenes.sh
source scripts/lib/results.sh
methods=copy,occlusion-motion,gbuffer,gbuffer-bilinear,gbuffer-highlights,gbuffer-translucency,gbuffer-translucency-opaque,gbuffer-before-translucency,gbuffer-shadows,gbuffer-sun-highlights,gbuffer-shadows-highlights,gbuffer-shadows-highlights-before-translucency,gbuffer-target-shadows,gbuffer-target-shadows-highlights,patchex,patchex-every-pixel,interpolation
for which in validation test; do
    datasets=()
    for scene in $(split "$which"); do
        target/release/patchex render "scenes/generated/$scene.toml" --frames 13 --size 640x360 \
            --out "out/eval_generated/datasets/$scene"
        datasets+=("out/eval_generated/datasets/$scene")
    done
    target/release/patchex eval "${datasets[@]}" --methods "$methods" \
        --out "out/eval_generated/$which" "$@"
done
publish out/eval_generated/validation/eval.md eval_generated_validation.md
publish out/eval_generated/test/eval.md eval_generated_test.md
publish out/eval_generated/test/eval.json eval_generated_test.json
publish out/eval_generated/test/strips/desert_02.png eval_generated_strip.png
# The test scenes with particles, with the methods their strip compares.
target/release/patchex eval out/eval_generated/datasets/tokyo_04 out/eval_generated/datasets/desert_04 \
    --methods copy,gbuffer,gbuffer-translucency,gbuffer-translucency-opaque,gbuffer-before-translucency,interpolation \
    --out out/eval_generated/particles
publish out/eval_generated/particles/strips/tokyo_04.png eval_generated_particles_strip.png
