#!/usr/bin/env bash
# Regenerates recordings/: the two thesis hand-offs, the coulomb plate hand-off, the padded
# cylinder and the thin handle (exact gaps) hand-offs as .rrd,
# .mcap, force-history .csv and .svg plot (thesis figures 15 and 17). Overwrites the previous
# recordings.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/grasp-target}"
cargo build --release -p grasp-cli
grasp="$CARGO_TARGET_DIR/release/grasp"
mkdir -p recordings
for case in plate_transfer disc_transfer plate_handoff_coulomb cylinder_handoff_pads handle_handoff; do
  "$grasp" transfer "examples/${case}.json" \
    --schedule "examples/${case}.schedule.json" \
    --rrd "recordings/${case}.rrd" --mcap "recordings/${case}.mcap" \
    --csv "recordings/${case}.csv" --plot "recordings/${case}.svg" --force
done
