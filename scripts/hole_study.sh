#!/usr/bin/env bash
# The hole study (training/hole_study.py): can a network repair the warp's holes anywhere
# in the frame, and what must it read? Renders the generated set at 640x360 with 33 frames a
# scene (training and validation into out/datasets_train, as scripts/train.sh does; test into
# out/datasets_test), writes every target's whole frame with `patchex patches --holes` (about
# 6 GB), and trains one network per input set with seed 1 on two CPU cores (about 10 minutes
# each). Writes out/hole_study/results.{md,json} and publishes the table into docs/results/.
# Arguments are passed to hole_study.py.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/training.sh
samples() { # dataset folder, sample folder, then the scenes
    local datasets=$1 samples=$2
    shift 2
    if [ -f "$samples/done" ]; then return; fi
    rm -rf "$samples"
    for name in "$@"; do
        render_once "scenes/generated/$name.toml" 33 "$datasets/$name"
        target/release/patchex patches "$datasets/$name" --holes --out "$samples"
    done
    touch "$samples/done"
}
samples out/datasets_train out/hole_samples $(split training) $(split validation)
samples out/datasets_test out/hole_samples_test $(split test)
out/torchenv/bin/python training/hole_study.py --samples out/hole_samples \
    --test-samples out/hole_samples_test --seed 1 --out out/hole_study "$@"
source scripts/lib/results.sh
publish out/hole_study/results.md hole_study.md
