#!/usr/bin/env bash
# The project's whole test command (README "The two commands"; .ci/run calls exactly this).
# 1. installs the independent checker (Python package rerun-sdk==0.36.3, for `rerun rrd verify`
#    and `rerun mcap check`) into a cached virtualenv;
# 2. builds and tests the workspace in the release profile (the only profile built, shared with
#    `cargo run --release`; CARGO_TARGET_DIR is honoured; every crate's layering, tests/layering.rs, is one of its tests), runs the
#    tests that need root when run as root and runs the API docs' examples (the lints, formatting, clippy and
#    the docs built with warnings denied, are scripts/lint.sh, which CI runs first);
# 3. installs the Python package from this checkout with the README's command (`pip install .`, in the
#    virtualenv; maturin builds in the same target folder and profile) and runs its pytest tests, the Ray
#    example on a local runtime and the Slurm scripts included.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-checkers.sh
# The checkers were just installed: a missing one fails the Python tests instead of skipping them.
export GRASP_REQUIRE_CHECKERS=1
export GRASP_RERUN_CLI="${GRASP_RERUN_CLI:-$HOME/.cache/grasp-venv/bin/rerun}"
status=0
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
# grasp-py is an extension module (it links against the interpreter that loads it), so it has no Rust test
# binary: its tests are the pytest suite below.
cargo test --release --workspace --exclude grasp-py --lib --bins --tests --no-fail-fast -- --show-output 2>&1 | tee "$log" || status=$?
# Tests ignored because they need root (a tmpfs mounted): run here when the command runs as root, where a
# mount that fails is a failure, not a skip.
if [ "$(id -u)" = 0 ]; then
    cargo test --release --workspace --exclude grasp-py --test outputs -- --ignored --show-output 2>&1 | tee -a "$log" || status=$?
fi
# The examples in the API docs run (`cargo test --doc` cannot be mixed with the targets above).
cargo test --release --workspace --exclude grasp-py --doc 2>&1 | tee -a "$log" || status=$?
venv="$HOME/.cache/grasp-venv"
target="$(cd "${CARGO_TARGET_DIR:-target}" && pwd)"
export GRASP_BIN="$target/release/grasp"
# The Python module must resolve the same crate features alone as in the workspace, or `pip install .`
# compiles Rerun's crates a second time (see crates/grasp-py/Cargo.toml).
python3 scripts/feature-parity.py || status=$?
"$venv/bin/pip" install --quiet --disable-pip-version-check . || status=$?
"$venv/bin/python" -m pytest tests/python -p no:cacheprovider -rs --continue-on-collection-errors 2>&1 | tee -a "$log" || status=$?
# One closing line with the totals over every Rust test binary and the Python tests.
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed/) p += $(i-1); if ($i ~ /^failed/) f += $(i-1) } }
     /^=+ .* in [0-9.]+s/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed/) p += $(i-1); if ($i ~ /^(failed|errors?)/) f += $(i-1) } }
     END { printf "%d passed, %d failed\n", p, f }' "$log"
exit "$status"
