#!/usr/bin/env bash
# The project's lints, run by CI (.ci/run) before the test command: formatting, ARCHITECTURE.md's
# generated parts (scripts/architecture.py), clippy on every target (benches included) and the API
# docs built without a broken link, warnings as errors. Kept apart from scripts/test.sh because
# clippy and rustdoc compile every dependency in check mode: a fresh clone's test command would
# build them twice (the check build took about 6 minutes on a 2-core machine). Needs the rustfmt and clippy components (`rustup component add rustfmt
# clippy`). CARGO_TARGET_DIR is honoured.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
cargo fmt --all -- --check || status=$?
# ARCHITECTURE.md's dependency and file tables are generated: stale (a file added or moved, a first doc line
# or a Cargo.toml changed) fails here; `python3 scripts/architecture.py --write` regenerates them.
python3 scripts/architecture.py --check || status=$?
cargo clippy --release --workspace --all-targets -- -D warnings || status=$?
# grasp-py is an extension module (it links against the interpreter that loads it): its docs are the
# Python package's.
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --workspace --exclude grasp-py || status=$?
exit "$status"
