#!/usr/bin/env bash
# Retrains the shipped inpainting networks: renders the five training scenes (65 frames at
# 640x360: 32 targets each; crossing_street and fast_run are the test scenes and are never
# rendered here), writes their FI and near-BE patches, and trains both networks with seed 1.
# Writes out/datasets_train/, out/patches/ and out/networks/ (weights, manifest.json,
# loss_curve.png); copy out/networks/* to assets/networks/ to ship them. PyTorch (~3 GB) goes
# into out/torchenv; about 15 minutes of training on two CPU cores, less on a GPU.
# Arguments are passed to training/train.py (e.g. --vgg16 PATH, --epochs N); the ablation without
# the perceptual term is `scripts/train.sh --no-perceptual --out out/networks_no_perceptual`
# (shipped in assets/networks/ablations/no_perceptual/).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh python3-venv
cargo build --release -p patchex-cli
if [ ! -x out/torchenv/bin/python ]; then
    python3 -m venv out/torchenv
    out/torchenv/bin/pip install --quiet -r training/requirements.txt
fi
datasets=()
for name in dance_static follow_chase forest_walk orbit_plaza shadow_terrain; do
    if [ ! -d "out/datasets_train/$name" ]; then
        target/release/patchex render "scenes/$name.toml" --frames 65 --size 640x360 \
            --out "out/datasets_train/$name"
    fi
    datasets+=("out/datasets_train/$name")
done
rm -rf out/patches
target/release/patchex patches "${datasets[@]}" --out out/patches
out/torchenv/bin/python training/train.py --patches out/patches --seed 1 \
    --test-scenes crossing_street,fast_run --out out/networks "$@"
