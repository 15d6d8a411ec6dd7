"""Hands and servos in Python: a solve reports each hand's and servo's load and motion (the
springs' own laws, `-F / k`, to round-off), the dict and JSON forms carry them, a hand-off
written by `grasp.transfer` has the CLI's hand and servo columns, and a sweep over a hand's
stiffness reports every variant's hand.

Tolerances: 1e-12 relative where a number is the spring's own law applied to the reported
load (the same arithmetic in another order); exact equality where two writers print one
number."""

import csv
import json

import grasp
from conftest import EXAMPLES

SCENE = EXAMPLES / "plate_transfer_gripper.json"
SCHEDULE = EXAMPLES / "plate_transfer_gripper.schedule.json"


def test_a_solve_reports_each_hand_and_servo_by_its_springs_law():
    sol = grasp.solve(grasp.Scene(SCENE))
    spec = json.loads(SCENE.read_text())
    k_servo = spec["servos"][0]["stiffness_n_per_m"]
    assert [h["name"] for h in sol.hands] == [h["name"] for h in spec["hands"]]
    for hand, written in zip(sol.hands, spec["hands"]):
        k = written["translational_n_per_m"]
        for c in range(3):
            assert abs(hand["translation_m"][c] + hand["force_n"][c] / k) <= 1e-12 * 1e-2
    # The two arms carry the weight between them.
    lift = sum(h["force_n"][2] for h in sol.hands)
    assert abs(lift - spec["object"]["weight"]) <= 1e-9 * lift
    (gripper,) = sol.servos
    assert gripper["name"] == "gripper"
    jaws = {f["name"]: f["normal_force_n"] for f in sol.fingers}
    assert abs(gripper["force_n"] - (jaws["f1"] + jaws["f2"])) <= 1e-12 * gripper["force_n"]
    assert abs(gripper["travel_m"] + gripper["force_n"] / k_servo) <= 1e-12 * 1e-2
    d = sol.to_dict()
    assert d["hands"] == sol.hands and d["servos"] == sol.servos
    assert json.loads(sol.to_json())["servos"] == sol.servos


def test_a_gripper_hand_off_writes_the_clis_hand_and_servo_columns(run_cli, tmp_path):
    ours = tmp_path / "py.csv"
    run = grasp.transfer(grasp.Scene(SCENE), SCHEDULE, csv=ours)
    assert set(run.statuses) == {"solved"}
    theirs = tmp_path / "cli.csv"
    proc = run_cli("transfer", SCENE, "--schedule", SCHEDULE, "--csv", theirs)
    assert proc.returncode == 0, proc.stderr
    a = list(csv.DictReader(open(ours, newline="")))
    b = list(csv.DictReader(open(theirs, newline="")))
    columns = [f"arm_translation_{c}_m" for c in "xyz"] + ["gripper_force_n", "gripper_travel_m"]
    assert set(columns) <= set(a[0])
    for ra, rb in zip(a, b, strict=True):
        assert [ra[c] for c in columns] == [rb[c] for c in columns]
    # At the end the arm carries the weight alone: its base sits W / k lower.
    weight = json.loads(SCENE.read_text())["object"]["weight"]
    assert abs(float(a[-1]["arm_translation_z_m"]) + weight / 1000.0) <= 1e-9 * weight / 1000.0


def test_a_sweep_over_a_hands_stiffness_reports_each_hand(run_cli, tmp_path):
    out = tmp_path / "sweep.jsonl"
    key = "hands[1].translational_n_per_m"  # the receiving arm
    proc = run_cli("sweep", SCENE, "--vary", f"{key}=500,2000", "--run", "--out", out)
    assert proc.returncode == 0, proc.stderr
    lines = [json.loads(line) for line in open(out)]
    assert [line["vary"][key] for line in lines] == [500.0, 2000.0]
    for line in lines:
        arm = next(h for h in line["hands"] if h["name"] == "arm")
        k = line["vary"][key]
        assert abs(arm["translation_m"][2] + arm["force_n"][2] / k) <= 1e-12 * 1e-2
        assert line["servos"][0]["name"] == "gripper"


def test_the_npz_carries_the_hands_servos_and_mounted_cores(run_cli, tmp_path):
    import numpy as np

    npz, out = tmp_path / "g.npz", tmp_path / "g.json"
    proc = run_cli("solve", SCENE, "--npz", npz, "--json", out)
    assert proc.returncode == 0, proc.stderr
    sol = json.loads(out.read_text())
    arrays = np.load(npz)
    for hand in sol["hands"]:
        for field in ("force_n", "moment_nm", "translation_m", "rotation_rad"):
            assert arrays[f"{hand['name']}/{field}"].tolist() == hand[field]
    for servo in sol["servos"]:
        assert arrays[f"{servo['name']}/force_n"].shape == ()
        assert float(arrays[f"{servo['name']}/travel_m"]) == servo["travel_m"]
    for finger in sol["fingers"]:
        core = finger.get("mount_displacement")
        key = f"{finger['name']}/core_translation_m"
        assert (key in arrays) == (core is not None)
        if core is not None:
            assert arrays[key].tolist() == core["translation_m"]
