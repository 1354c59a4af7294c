#!/usr/bin/env bash
# The test command: installs what is missing, checks formatting and lints, builds the plugin's
# shared library, and runs every test of the workspace on lavapipe with validation on.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
# Tests load target/debug/libpatchex.so through libloading, as an engine would.
cargo build -p patchex
cargo test --workspace
