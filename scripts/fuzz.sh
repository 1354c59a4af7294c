#!/usr/bin/env bash
# Fuzzes the C ABI with libFuzzer and AddressSanitizer on lavapipe, validation on:
#   [FUZZ_JOBS=N] scripts/fuzz.sh [RUNS] [extra libFuzzer flags]   (default 1000000 runs)
# With FUZZ_JOBS=N, N processes each make RUNS runs (their logs: fuzz/fuzz-*.log). Not part of
# the test command: it needs the nightly toolchain, and one process makes about 250 runs a
# second here. Findings land in fuzz/artifacts/abi_calls/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
RUNS="${1:-1000000}"
shift || true
rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
cd fuzz
mkdir -p corpus/abi_calls
# Leak checks after every input would run LeakSanitizer on most inputs (the driver allocates
# during submissions), a hundredfold slowdown: leaks are checked by the soak and the object
# counting tests instead; the driver's own allocations are suppressed at exit.
export LSAN_OPTIONS="suppressions=$PWD/lsan.supp:print_suppressions=0"
jobs="${FUZZ_JOBS:-1}"
parallel=()
[ "$jobs" -gt 1 ] && parallel=(-jobs="$jobs" -workers="$jobs")
cargo +nightly fuzz run abi_calls corpus/abi_calls -- \
    -runs="$RUNS" -detect_leaks=0 -rss_limit_mb=4096 -print_final_stats=1 "${parallel[@]}" "$@"
