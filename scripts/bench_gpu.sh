#!/usr/bin/env bash
# The speed guide's GPU measurements, for a machine with a GPU: the three presets at 1920x1080
# (both test scenes, 7 frames) and 3840x2160 (fast_run, 5 frames), the G-buffer in a deferred
# renderer's formats, each call warmed up so that the GPU runs at its full clock. Writes
# out/bench_gpu/bench_gpu.md, headed by the device and its driver, and the two bench.json files.
#   scripts/bench_gpu.sh [PATCHEX]     (PATCHEX: the tool to run, target/release/patchex by default)
set -euo pipefail
cd "$(dirname "$0")/.."
patchex=${1:-target/release/patchex}
out=out/bench_gpu
mkdir -p "$out"
presets=gbuffer,gbuffer-shadows,patchex
"$patchex" bench --scenes scenes/crossing_street.toml,scenes/fast_run.toml --sizes 1920x1080 \
    --configurations "$presets" --input-formats engine --frames 7 --out "$out/1080p" >/dev/null
"$patchex" bench --scenes scenes/fast_run.toml --sizes 3840x2160 \
    --configurations "$presets" --input-formats engine --frames 5 --out "$out/2160p" >/dev/null
gpu=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1 || true)
{
    echo "# patchex bench${gpu:+ on $gpu (name, driver)}"
    for size in 1080p 2160p; do
        echo
        echo "## $size"
        echo
        cat "$out/$size/bench.md"
    done
} > "$out/bench_gpu.md"
echo "written: $out/bench_gpu.md"
