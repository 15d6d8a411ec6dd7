#!/usr/bin/env bash
# Regenerates the disturbance margins committed in docs/margins/ (summarised in docs/guide/margins.md): each
# thesis example under its own (energy) model and under the coulomb model, and the hand-offs'
# least safe steps.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/grasp-target}"
cargo build --release -p grasp-cli
grasp="$CARGO_TARGET_DIR/release/grasp"
mkdir -p docs/margins
for name in plate_four_fingers disc_three_fingers pipe_three_fingers cube_a cube_b plate_handoff_coulomb; do
  for model in energy coulomb; do
    # Exit 2 (the grasp does not hold in this model) is a result, recorded like the others.
    "$grasp" margin "examples/$name.json" --model "$model" \
      --json "docs/margins/$name.$model.json" --force > "docs/margins/$name.$model.txt" || true
  done
done
"$grasp" margin examples/plate_handoff_coulomb.json --plot docs/margins/plate_handoff_coulomb.svg \
  --force > /dev/null
for name in plate_transfer disc_transfer plate_handoff_coulomb; do
  "$grasp" transfer "examples/$name.json" --schedule "examples/$name.schedule.json" --margins \
    --csv "docs/margins/$name.transfer.csv" --force > "docs/margins/$name.transfer.txt"
done
