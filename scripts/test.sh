#!/usr/bin/env bash
# The project's whole test command (README "Test"; .ci/run calls exactly this).
# 1. installs the independent checker (Python package rerun-sdk==0.36.3, for `rerun rrd verify`
#    and `rerun mcap check`) into a cached virtualenv;
# 2. checks formatting, builds and tests the workspace in the release profile (the only profile
#    built, shared with `cargo run --release`; CARGO_TARGET_DIR is honoured).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-checkers.sh
export GRASP_RERUN_CLI="${GRASP_RERUN_CLI:-$HOME/.cache/grasp-venv/bin/rerun}"
cargo fmt --all -- --check
cargo test --release --workspace --no-fail-fast
