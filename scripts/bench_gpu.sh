#!/usr/bin/env bash
# The speed guide's GPU measurements, for a machine with a GPU: the three presets at 1920x1080
# (both test scenes, 7 frames) and 3840x2160 (fast_run, 5 frames), the G-buffer in a deferred
# renderer's formats, each call warmed up so that the GPU runs at its full clock; then
# `patchex selftest` on the same GPU. Writes one report, headed by the device and its driver,
# section by section as each part finishes (a run cut short keeps what it measured), and the
# two bench.json files beside it in out/bench_gpu/.
#   scripts/bench_gpu.sh [PATCHEX [REPORT]]
#     PATCHEX: the tool to run, target/release/patchex by default
#     REPORT: where the report goes, out/bench_gpu/bench_gpu.md by default
set -euo pipefail
cd "$(dirname "$0")/.."
patchex=${1:-target/release/patchex}
out=out/bench_gpu
report=${2:-$out/bench_gpu.md}
mkdir -p "$out" "$(dirname "$report")"
presets=gbuffer,gbuffer-shadows,patchex
gpu=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1 || true)
echo "# patchex bench${gpu:+ on $gpu (name, driver)}" > "$report"
section() {  # section TITLE FILE
    { echo; echo "## $1"; echo; cat "$2"; } >> "$report"
}
"$patchex" bench --scenes scenes/crossing_street.toml,scenes/fast_run.toml --sizes 1920x1080 \
    --configurations "$presets" --input-formats engine --frames 7 --out "$out/1080p" >/dev/null
section 1080p "$out/1080p/bench.md"
"$patchex" bench --scenes scenes/fast_run.toml --sizes 3840x2160 \
    --configurations "$presets" --input-formats engine --frames 5 --out "$out/2160p" >/dev/null
section 2160p "$out/2160p/bench.md"
# The self-test's verdict is its exit code; the report keeps its lines either way.
status=0
"$patchex" selftest > "$out/selftest.txt" 2>&1 || status=$?
{ echo '```'; cat "$out/selftest.txt"; echo '```'; } > "$out/selftest.md"
section "selftest (exit $status)" "$out/selftest.md"
echo "written: $report"
exit "$status"
