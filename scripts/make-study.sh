#!/usr/bin/env bash
# Regenerates the grid-refinement studies committed in docs/study/ (tables shown in docs/guide/solving.md):
# Hertz against the closed form, cube A against its finest grid.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/grasp-target}"
cargo build --release -p grasp-cli
grasp="$CARGO_TARGET_DIR/release/grasp"
mkdir -p docs/study
"$grasp" study examples/hertz_sphere_on_flat.json --grids 5,9,17,25,33,41 --reference hertz \
  --csv docs/study/hertz.csv --plot docs/study/hertz.svg --force | tee docs/study/hertz.md
"$grasp" study examples/cube_a.json --grids 3,5,9,13,17 --reference finest \
  --csv docs/study/cube_a.csv --plot docs/study/cube_a.svg --force | tee docs/study/cube_a.md
