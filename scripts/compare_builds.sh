#!/usr/bin/env bash
# Checks that a change keeps the plugin's outputs bit for bit: builds revision REV (default
# HEAD, committed work only) in a git worktree beside the working tree's build, renders every
# scene with each, runs every plugin method on them with `eval --write-frames`, and compares
# the datasets and every written frame byte for byte. Exits 1 on the first difference.
#
#   scripts/compare_builds.sh [REV] [--size WxH] [--frames N]
set -euo pipefail
cd "$(dirname "$0")/.."
rev=HEAD
size=320x180
frames=5
while [ $# -gt 0 ]; do
    case "$1" in
        --size) size=$2; shift 2 ;;
        --frames) frames=$2; shift 2 ;;
        *) rev=$1; shift ;;
    esac
done
out=out/compare_builds
scripts/install-deps.sh
cargo build --release -p patchex -p patchex-cli
source scripts/lib/revision.sh
build_revision "$rev"

methods=motion-vector,occlusion-motion,gbuffer,gbuffer-nearest-fill,gbuffer-shadows,patchex,patchex-no-shadows,patchex-whole-frame
for build in before after; do
    if [ $build = before ]; then tool=$before_tool; else tool=target/release/patchex; fi
    datasets=()
    for scene in scenes/*.toml; do
        name=$(basename "$scene" .toml)
        "$tool" render "$scene" --frames "$frames" --size "$size" --out "$out/$build/datasets/$name"
        datasets+=("$out/$build/datasets/$name")
    done
    "$tool" eval "${datasets[@]}" --methods "$methods" --write-frames --out "$out/$build/eval" >/dev/null
done

differing=0
compared=0
while IFS= read -r file; do
    compared=$((compared + 1))
    if ! cmp -s "$out/before/$file" "$out/after/$file"; then
        echo "differs: $file"
        differing=$((differing + 1))
    fi
done < <(cd "$out/before" && find datasets eval/frames -type f -name '*.exr' | sort)
if [ "$compared" -eq 0 ]; then
    echo "no frames were written" >&2
    exit 1
fi
if [ "$differing" -ne 0 ]; then
    echo "$differing of $compared frames differ between $rev and the working tree" >&2
    exit 1
fi
echo "all $compared frames (7 scenes' datasets and every plugin method's output) are identical to $rev"
