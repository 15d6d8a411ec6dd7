#!/usr/bin/env bash
# Regenerates the gallery's pictures (docs/gallery/<scene>.svg, one `grasp plot` per scene of
# examples/README.md; docs/gallery/contact/<scene>.svg, the contact maps of `grasp solve --plot`
# for a few scenes; docs/gallery/tactile/<scene>.png, the gel images of `grasp solve --gel-png`).
# crates/grasp-cli/tests/gallery.rs regenerates each and compares it with
# the committed file, so run this after a change that moves a picture, and commit the result.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/grasp-target}"
scenes="plate_four_fingers disc_three_fingers pipe_three_fingers cube_a cube_b hertz_sphere_on_flat
        plate_transfer disc_transfer plate_handoff_coulomb
        box_pinch sphere_three_fingers mug_power_grasp cylinder_handoff pad_pinch cylinder_handoff_pads
        edge_pinch handle_handoff ridged_pad_pinch rough_object_pinch"
for s in $scenes; do
  cargo run --release --quiet -- plot "examples/$s.json" --out "docs/gallery/$s.svg" --force
done
for s in cube_a hertz_sphere_on_flat mug_power_grasp; do
  cargo run --release --quiet -- solve "examples/$s.json" --plot "docs/gallery/contact/$s.svg" --force >/dev/null
done
mkdir -p docs/gallery/tactile
for s in ridged_gel; do
  cargo run --release --quiet -- solve "examples/$s.json" --gel-png "docs/gallery/tactile/$s.png" --force >/dev/null
done
