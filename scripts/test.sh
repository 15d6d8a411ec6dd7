#!/usr/bin/env bash
# The project's whole test command (README "Test"; .ci/run calls exactly this).
# 1. installs the independent checker (Python package rerun-sdk==0.36.3, for `rerun rrd verify`
#    and `rerun mcap check`) into a cached virtualenv;
# 2. checks formatting and lints (clippy), builds and tests the workspace in the release profile (the only profile
#    built, shared with `cargo run --release`; CARGO_TARGET_DIR is honoured).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-checkers.sh
export GRASP_RERUN_CLI="${GRASP_RERUN_CLI:-$HOME/.cache/grasp-venv/bin/rerun}"
cargo fmt --all -- --check
# Lints of every target (benches included), warnings as errors.
cargo clippy --release --workspace --all-targets -- -D warnings
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
cargo test --release --workspace --lib --bins --tests --no-fail-fast -- --show-output 2>&1 | tee "$log" || status=$?
# One closing line with the totals over every test binary.
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed/) p += $(i-1); if ($i ~ /^failed/) f += $(i-1) } }
     END { printf "%d passed, %d failed\n", p, f }' "$log"
exit "$status"
