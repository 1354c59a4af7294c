#!/usr/bin/env bash
# Measures revision REV (default HEAD, committed work only) against the working tree's build,
# side by side in one run: `patchex bench` with each build in turn, ROUNDS times, alternating so
# that both see the same load on a shared machine. Prints each configuration's mean GPU ms per
# target (timestamp queries) with both builds, their ratio, and the change in PSNR on the same
# targets (the bench's test scenes); then the same for each stage. On a machine without cargo
# (a lent GPU), --tools names two built `patchex` tools instead, each with its libpatchex.so
# beside it, and nothing is built.
#
#   scripts/bench_builds.sh [REV] [--sizes WxH,...] [--configurations LIST] [--frames N]
#                           [--rounds N] [--scenes LIST] [--input-formats F]
#                           [--tools BEFORE AFTER]
set -euo pipefail
cd "$(dirname "$0")/.."
rev=HEAD
sizes=1920x1080
configurations=motion-vector,occlusion-motion,gbuffer
frames=5
rounds=2
scenes=scenes/crossing_street.toml,scenes/fast_run.toml
input_formats=float32
before_tool=
after_tool=target/release/patchex
while [ $# -gt 0 ]; do
    case "$1" in
        --sizes) sizes=$2; shift 2 ;;
        --configurations) configurations=$2; shift 2 ;;
        --frames) frames=$2; shift 2 ;;
        --rounds) rounds=$2; shift 2 ;;
        --scenes) scenes=$2; shift 2 ;;
        --input-formats) input_formats=$2; shift 2 ;;
        --tools) before_tool=$2; after_tool=$3; rev=$2; shift 3 ;;
        *) rev=$1; shift ;;
    esac
done
out=out/bench_builds
if [ -z "$before_tool" ]; then
    scripts/install-deps.sh
    cargo build --release -p patchex -p patchex-cli
    source scripts/lib/revision.sh
    build_revision "$rev"
fi
rm -rf "$out"
for round in $(seq "$rounds"); do
    for build in before after; do
        if [ $build = before ]; then tool=$before_tool; else tool=$after_tool; fi
        echo "round $round: $build" >&2
        "$tool" bench --scenes "$scenes" --sizes "$sizes" --configurations "$configurations" \
            --frames "$frames" --input-formats "$input_formats" --out "$out/$build-$round" >/dev/null
    done
done
python3 - "$out" "$rounds" "$rev" <<'PY'
import json, sys
out, rounds, rev = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def rows(build):
    table = {}
    for r in range(1, rounds + 1):
        for row in json.load(open(f"{out}/{build}-{r}/bench.json"))["rows"]:
            key = (row["label"], row["width"], row["height"])
            table.setdefault(key, []).append(row)
    return table
before, after = rows("before"), rows("after")
mean = lambda values: sum(values) / len(values)
# GPU times are fractions of a millisecond, lavapipe's hundreds.
ms = lambda x: f"{x:.3f}" if x < 10 else f"{x:.1f}"
print(f"| configuration | size | {rev} ms | this build ms | ratio | PSNR change dB |")
print("|---|---|---|---|---|---|")
for key, runs in before.items():
    then, now = mean([r["total_gpu_ms"] for r in runs]), mean([r["total_gpu_ms"] for r in after[key]])
    print(f"| {key[0]} | {key[1]}x{key[2]} | {ms(then)} | {ms(now)} | {now / then:.2f} | "
          f"{after[key][0]['psnr'] - runs[0]['psnr']:+.3f} |")
print()
print(f"| configuration | size | stage | {rev} ms | this build ms | ratio |")
print("|---|---|---|---|---|---|")
for key, runs in before.items():
    # A stage one build records and the other does not shows as "-" there.
    stages = list(runs[0]["costs"]["stages"])
    stages += [s for s in after[key][0]["costs"]["stages"] if s not in stages]
    for stage in stages:
        stage_ms = lambda rs: (mean([r["costs"]["stages"][stage]["gpu_ms"] for r in rs])
                               if stage in rs[0]["costs"]["stages"] else None)
        then, now = stage_ms(runs), stage_ms(after[key])
        shown = lambda x: "-" if x is None else ms(x)
        ratio = f"{now / then:.2f}" if then and now is not None else "-"
        print(f"| {key[0]} | {key[1]}x{key[2]} | {stage} | {shown(then)} | {shown(now)} | {ratio} |")
PY
