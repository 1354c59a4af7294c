#!/usr/bin/env bash
# Where patchex sits in the engine's post-processing (quality guide, Post-processing): scores the
# generated validation and test splits as the player sees them after bloom and tone mapping
# (`patchex_scene::render::post`), with patchex on the HDR colour before post (the engine then
# runs its post-processing on the generated frame) and on the colour after it. Decisions on
# validation, the guide reports test. Renders the splits as scripts/eval_generated.sh does where
# its datasets are missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/scenes.sh
source scripts/lib/results.sh
methods=copy,gbuffer,gbuffer-shadows,gbuffer-translucency,interpolation
# Called before the translucency pass, patchex is before post as well: scored in that placement.
before_methods=$methods,gbuffer-before-translucency
for which in validation test; do
    datasets=()
    for scene in $(split "$which"); do
        dataset="out/eval_generated/datasets/$scene"
        render_once "scenes/generated/$scene.toml" 13 "$dataset"
        datasets+=("$dataset")
    done
    for placement in before after; do
        placement_methods=$methods
        [ "$placement" = before ] && placement_methods=$before_methods
        target/release/patchex eval "${datasets[@]}" --methods "$placement_methods" --post "$placement" \
            --out "out/eval_post/$which/$placement"
        publish "out/eval_post/$which/$placement/eval.md" "eval_post_${placement}_$which.md"
    done
done
