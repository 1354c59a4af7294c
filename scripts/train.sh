#!/usr/bin/env bash
# Retrains the shipped inpainting networks on the generated scene set's training split, with its
# validation split for early stopping (scenes/generated/split.toml; the test split and the
# hand-written test scenes crossing_street and fast_run never reach training). Renders 33 frames
# at 640x360 per scene (16 targets each), writes their FI and near-BE patches, and trains both
# networks with seed 1 for the plugin's default blend (corrections kept in holes only).
# Writes out/datasets_train/, out/patches/ and out/networks/ (weights, manifest.json,
# loss_curve.png, per-epoch checkpoints); copy the weights and manifest to assets/networks/ to
# ship them. An interrupted run goes on where it stopped: run it again. PyTorch (~3 GB) goes into
# out/torchenv; rendering and patches take minutes, training about 5 minutes on two CPU
# cores (early stopping ends it after 5 or 6 epochs). Arguments are passed to
# training/train.py (e.g. --vgg16 PATH, --epochs N, --every-pixel for the paper's blend).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/training.sh
training=$(split training)
validation=$(split validation)
datasets=()
for name in $training $validation; do
    render_once "scenes/generated/$name.toml" 33 "out/datasets_train/$name"
    datasets+=("out/datasets_train/$name")
done
if [ ! -f out/patches/done ]; then
    rm -rf out/patches
    target/release/patchex patches "${datasets[@]}" --out out/patches
    touch out/patches/done
fi
test_scenes=$(split test | tr ' ' ',')
out/torchenv/bin/python training/train.py --patches out/patches --seed 1 --out out/networks \
    --validation-scenes "$(echo $validation | tr ' ' ',')" \
    --test-scenes "crossing_street,fast_run,$test_scenes" \
    --epochs 20 --steps 80 --lr 1e-3 --patience 4 --resume "$@"
