#!/usr/bin/env bash
# The test command: installs what is missing, checks formatting and lints, builds the plugin's
# shared library, runs every test of the workspace on lavapipe with validation on, then the Bevy
# example in its check mode.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
# Tests load target/debug/libpatchex.so through libloading, as an engine would.
cargo build -p patchex
cargo test --workspace
# Bevy generating frames with patchex: an engine this project did not write, checked against its
# own frames under validation (docs/integration-bevy.md). Its own workspace, so Bevy stays out of
# the library's build; it adds about twelve minutes, eleven of them compiling Bevy.
(
    cd examples/bevy
    cargo fmt --check
    cargo clippy --locked --all-targets -- -D warnings
    cargo run --locked -- --check --min-gain 8
)
