"""Layered pads from Python: a material's layer_thickness_m round-trips through
grasp.Scene, a bad one is a SceneError naming the field, the warnings of an unresolved layer
reach the solution, and the padded pinch is stiffer than its half-space twin (smaller contact,
higher peak pressure) with the same resultants."""

import json

import pytest

import grasp
from conftest import EXAMPLES


def test_layer_thickness_round_trips_and_bad_values_name_the_field():
    d = json.loads((EXAMPLES / "pad_pinch.json").read_text())
    scene = grasp.Scene(d)
    assert scene.to_dict()["fingers"][0]["material"]["layer_thickness_m"] == 0.001
    d["fingers"][1]["material"] = dict(d["fingers"][1]["material"], layer_thickness_m=-0.001)
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(d)
    paths = [p["path"] for p in e.value.problems]
    assert "fingers[1].material.layer_thickness_m" in paths


def test_an_unresolved_layer_is_warned_about():
    d = json.loads((EXAMPLES / "pad_pinch.json").read_text())
    for f in d["fingers"]:
        f["patch"]["grid"] = [5, 5]  # elements of 1.2 mm on a 1 mm pad
    sol = grasp.solve(grasp.Scene(d))
    assert any(w.startswith("fingers[0].material.layer_thickness_m") and "cannot resolve" in w
               for w in sol.warnings), sol.warnings


def test_padded_pinch_is_stiffer_than_half_space_pads():
    pads = grasp.solve(grasp.Scene(EXAMPLES / "pad_pinch.json")).to_dict()
    half = grasp.solve(grasp.Scene(EXAMPLES / "pad_pinch_halfspace.json")).to_dict()
    for a, b in zip(pads["fingers"], half["fingers"]):
        # Equilibrium fixes the resultants (to the solver's tolerance) ...
        assert a["normal_force_n"] == pytest.approx(b["normal_force_n"], rel=1e-9)
        assert a["tangential_magnitude_n"] == pytest.approx(b["tangential_magnitude_n"], rel=1e-6)
        # ... the pad's stiffness moves the contact: about 20 % smaller, 1.9 times the peak.
        assert a["contact_area_m2"] < 0.7 * b["contact_area_m2"]
        assert a["peak_pressure_pa"] > 1.7 * b["peak_pressure_pa"]
