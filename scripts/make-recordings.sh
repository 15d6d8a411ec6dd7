#!/usr/bin/env bash
# Regenerates recordings/: the two thesis hand-offs as .rrd, .mcap, force-history .csv and
# .svg plot (thesis figures 15 and 17). Overwrites the previous recordings.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/grasp-target}"
cargo build --release -p grasp-cli
grasp="$CARGO_TARGET_DIR/release/grasp"
mkdir -p recordings
for case in plate disc; do
  "$grasp" transfer "examples/${case}_transfer.json" \
    --schedule "examples/${case}_transfer.schedule.json" \
    --rrd "recordings/${case}_transfer.rrd" --mcap "recordings/${case}_transfer.mcap" \
    --csv "recordings/${case}_transfer.csv" --plot "recordings/${case}_transfer.svg" --force
done
