"""A frictionless finger has no tangential unknowns: its elements in contact are
"frictionless", neither stick nor slip, in every output (Solution.states, the JSON and its
counts, the .npz, the MCAP's patches and fingers, the CSV's slip fraction). A finger with
friction never has that state, so the tests tell the two apart."""

import csv
import json

import numpy as np

import grasp
from conftest import EXAMPLES, checker

ONE_STEP = {"description": "one step: the scene as it is", "time": {"times": [0.0]}, "fingers": {}}


def hertz():
    """One frictionless steel fingertip (mu = 0) under a flat steel object."""
    return grasp.Scene(EXAMPLES / "hertz_sphere_on_flat.json")


def test_a_frictionless_fingers_contact_elements_are_frictionless_not_slip():
    sol = grasp.solve(hertz())
    assert sol.status == "solved"
    states = sol.states
    loaded = sol.normal_forces_n > 0
    assert set(states) == {"frictionless", "separated"}
    assert np.all(states[loaded] == "frictionless")
    (finger,) = sol.to_dict()["fingers"]
    assert finger["stick_count"] == finger["slip_count"] == 0
    assert finger["frictionless_count"] == int(np.sum(states == "frictionless")) > 0
    assert {e["state"] for e in finger["elements"]} == {"frictionless", "separated"}


def test_a_finger_with_friction_has_no_frictionless_element():
    sol = grasp.solve(grasp.Scene(EXAMPLES / "cube_a.json"))
    assert "frictionless" not in set(sol.states)
    assert all("frictionless_count" not in f for f in sol.to_dict()["fingers"])


def test_the_npz_names_the_frictionless_state(tmp_path):
    sol = grasp.solve(hertz())
    path = tmp_path / "hertz.npz"
    sol.to_npz(path)
    with np.load(path) as arrays:
        names = arrays["state_names"][arrays["tip/state"]]
    assert list(names) == list(sol.states)


def test_the_hand_off_outputs_count_no_slip_on_a_frictionless_finger(tmp_path):
    mcap_reader = checker("mcap.reader", reason="mcap is installed by scripts/install-checkers.sh")
    files = {"mcap": tmp_path / "hertz.mcap", "csv": tmp_path / "hertz.csv"}
    run = grasp.transfer(hertz(), ONE_STEP, **files)
    assert list(run.statuses) == ["solved"]
    with open(files["csv"], newline="") as f:
        (row,) = list(csv.DictReader(f))
    assert float(row["tip_slip_fraction"]) == 0.0
    with open(files["mcap"], "rb") as f:
        reader = mcap_reader.make_reader(f)
        messages = {channel.topic: json.loads(msg.data) for _, channel, msg in reader.iter_messages(
            topics=["/grasp/patches", "/grasp/fingers"])}
    (patch,) = messages["/grasp/patches"]["patches"]
    states = [e["state"] for e in patch["elements"]]
    assert states == list(run.step(0).states) and "frictionless" in states and "slip" not in states
    (finger,) = messages["/grasp/fingers"]["fingers"]
    assert finger["slip_fraction"] == 0.0
