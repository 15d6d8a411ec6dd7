#!/usr/bin/env bash
# The project's lints, run by CI (.ci/run) before the test command: formatting, ARCHITECTURE.md's
# generated parts and the rules it states (scripts/architecture.py), clippy on every target (benches included) and the API
# docs built without a broken link, warnings as errors. Kept apart from scripts/test.sh because
# clippy and rustdoc compile every dependency in check mode: a fresh clone's test command would
# build them twice (the check build took about 6 minutes on a 2-core machine). Needs the rustfmt and clippy components (`rustup component add rustfmt
# clippy`). CARGO_TARGET_DIR is honoured.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
cargo fmt --all -- --check || status=$?
# ARCHITECTURE.md's dependency and file tables are generated: stale (a file added or moved, a first doc line
# or a Cargo.toml changed) fails here; `python3 scripts/architecture.py --write` regenerates them. The same
# check fails when a path "Where things go" names is missing, and on every breach of its "Code shape" (a
# tuple parameter in library code, a library function over 80 lines or a CLI one over 100, a library file
# over 800 lines; tests excluded), each named with its file and line.
python3 scripts/architecture.py --check || status=$?
cargo clippy --release --workspace --all-targets -- -D warnings || status=$?
# grasp-py is an extension module (it links against the interpreter that loads it): its docs are the
# Python package's.
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --workspace --exclude grasp-py || status=$?
exit "$status"
