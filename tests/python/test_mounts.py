"""Mounted fingers in Python: a solve's finger records carry each mounted core's displacement
(the spring's own law, `-F / k`, to round-off), a servo-released hand-off's CSV written by
`grasp.transfer` equals the CLI's, mount columns included, and a sweep over a mount's stiffness
reports every variant's core."""

import csv
import json

import grasp
from conftest import EXAMPLES


def test_a_mounted_fingers_record_has_its_cores_displacement():
    sol = grasp.solve(grasp.Scene(EXAMPLES / "servo_pinch.json"))
    servo, fixed = sol.fingers
    k = 1000.0  # the example's servo stiffness, N/m
    core = servo["mount_displacement"]
    assert abs(core["normal_m"] + servo["normal_force_n"] / k) < 1e-12
    assert core["translation_m"][0] == core["normal_m"]  # the servo's normal is +x
    assert servo["approach_m"] == 5e-4
    assert "mount_displacement" not in fixed


def test_a_servo_released_hand_off_writes_the_clis_mount_columns(run_cli, tmp_path):
    scene = EXAMPLES / "plate_transfer_servo.json"
    schedule = EXAMPLES / "plate_transfer_servo.schedule.json"
    ours = tmp_path / "py.csv"
    run = grasp.transfer(grasp.Scene(scene), schedule, csv=ours)
    assert set(run.statuses) == {"solved"}
    theirs = tmp_path / "cli.csv"
    proc = run_cli("transfer", scene, "--schedule", schedule, "--csv", theirs)
    assert proc.returncode == 0, proc.stderr
    a = list(csv.DictReader(open(ours, newline="")))
    b = list(csv.DictReader(open(theirs, newline="")))
    columns = [f"{n}_{c}" for n in ("f1", "f2", "f3", "f4")
               for c in ("approach_m", "core_along_n_m", "core_moved_m")]
    assert set(columns) <= set(a[0])
    for ra, rb in zip(a, b, strict=True):
        assert [ra[c] for c in columns] == [rb[c] for c in columns]
    # The servo's jaws pass first touch at 13 s: from then on they carry nothing.
    for r in a:
        if float(r["time_s"]) >= 13.0:
            assert abs(float(r["f1_normal_force_n"])) < 1e-9


def test_a_sweep_over_a_mounts_stiffness_reports_each_core(run_cli, tmp_path):
    out = tmp_path / "sweep.jsonl"
    proc = run_cli("sweep", EXAMPLES / "servo_pinch.json", "--vary",
                   "fingers[0].mount.normal_n_per_m=100,1000", "--run", "--out", out)
    assert proc.returncode == 0, proc.stderr
    lines = [json.loads(line) for line in open(out)]
    assert [line["vary"]["fingers[0].mount.normal_n_per_m"] for line in lines] == [100.0, 1000.0]
    squeezes = []
    for line in lines:
        k = line["vary"]["fingers[0].mount.normal_n_per_m"]
        servo, fixed = line["fingers"]
        assert abs(servo["mount_displacement"]["normal_m"] + servo["normal_force_n"] / k) < 1e-12
        assert "mount_displacement" not in fixed
        squeezes.append(servo["normal_force_n"])
    # A stiffer servo at the same jaw position squeezes harder.
    assert squeezes[0] < squeezes[1]
