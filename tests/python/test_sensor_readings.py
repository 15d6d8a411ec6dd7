"""Tactile readings in Python: `Solution.sensor(finger)` gives the arrays `grasp solve --npz`
writes (the CLI's path, compared bit for bit), a finger without a sensor is a KeyError naming
the fix, and `Transfer.sensor_history(finger)` stacks every step's readings with NaN where the
finger is not held, each step equal to that step's `Solution.sensor`."""

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES


def test_a_solves_sensor_arrays_are_the_clis_npz(run_cli, tmp_path):
    scene = EXAMPLES / "hertz_taxels.json"
    sol = grasp.solve(grasp.Scene(scene))
    read = sol.sensor("tip")
    assert set(read) == {"taxels"}
    t = read["taxels"]
    assert t["force_n"].shape == (5, 5, 3) and t["centre_m"].shape == (5, 5, 2)
    npz = tmp_path / "cli.npz"
    proc = run_cli("solve", scene, "--npz", npz)
    assert proc.returncode == 0, proc.stderr
    cli = np.load(npz)
    assert np.array_equal(t["force_n"], cli["tip/taxels/force_n"])
    assert np.array_equal(t["centre_m"], cli["tip/taxels/centre_m"])
    assert t["depth_m"] == float(cli["tip/taxels/depth_m"])
    # The Python solution's own .npz carries the readings too.
    ours = tmp_path / "py.npz"
    sol.to_npz(ours)
    assert np.array_equal(np.load(ours)["tip/taxels/force_n"], t["force_n"])
    markers = grasp.solve(grasp.Scene(EXAMPLES / "hertz_markers.json"))
    name = markers.finger_names[0]
    m = markers.sensor(name)["markers"]
    assert m["displacement_m"].shape == (9, 9, 3) and m["position_m"].shape == (9, 9, 2)


def test_a_finger_without_a_sensor_is_a_key_error_with_the_fix():
    sol = grasp.solve(grasp.Scene(EXAMPLES / "plate_transfer.json"))
    with pytest.raises(KeyError, match="give the finger a `sensor`"):
        sol.sensor("f1")


def test_a_hand_offs_npz_carries_each_steps_readings(run_cli, tmp_path):
    scene = EXAMPLES / "plate_transfer_taxels.json"
    schedule = EXAMPLES / "plate_transfer_taxels.schedule.json"
    npz = tmp_path / "run.npz"
    proc = run_cli("transfer", scene, "--schedule", schedule, "--npz", npz)
    assert proc.returncode == 0, proc.stderr
    cli = np.load(npz)
    history = grasp.transfer(grasp.Scene(scene), schedule).sensor_history("f3")
    forces = history["taxels"]["force_n"]
    for k in (0, 100, 199):
        name = f"step_{k:05d}/f3/taxels/force_n"
        if np.isnan(forces[k]).all():
            assert name not in cli.files  # released: no entry
        else:
            assert np.array_equal(cli[name], forces[k])


def test_a_hand_offs_sensor_history_is_each_steps_readings():
    run = grasp.transfer(grasp.Scene(EXAMPLES / "plate_transfer_taxels.json"),
                         EXAMPLES / "plate_transfer_taxels.schedule.json")
    steps = len(run.times_s)
    for name in ("f1", "f3"):
        h = run.sensor_history(name)["taxels"]["force_n"]
        assert h.shape == (steps, 4, 2, 3)
        column = run.finger_names.index(name)
        held = run.normal_forces_n[:, column] > 0
        for k in (0, steps // 2, steps - 1):
            if np.isnan(h[k]).all():
                with pytest.raises(KeyError):
                    run.step(k).sensor(name)
            else:
                assert np.array_equal(h[k], run.step(k).sensor(name)["taxels"]["force_n"])
        # A finger carrying load is read at that step.
        assert not np.isnan(h[held]).any()
    # f3 is released at t = 0 (the receivers take the plate later): no reading there.
    assert np.isnan(run.sensor_history("f3")["taxels"]["force_n"][0]).all()
    with pytest.raises(KeyError, match="has no sensor"):
        grasp.transfer(grasp.Scene(EXAMPLES / "plate_transfer.json"),
                       EXAMPLES / "plate_transfer.schedule.json").sensor_history("f1")


def test_a_batch_line_carries_the_sensors_and_the_stick_fraction(run_cli, tmp_path):
    """A tactile dataset's line: `grasp batch` writes each scene's readings as `grasp solve
    --json` does, and each finger's stick fraction (stick over stick and slip elements) as the
    solve's element counts give it."""
    import json
    scene = json.loads((EXAMPLES / "hertz_taxels.json").read_text())
    scenes = tmp_path / "scenes.jsonl"
    scenes.write_text(json.dumps({"id": "taxels", "scene": scene}) + "\n"
                      + json.dumps({"id": "plain", "scene": json.loads(
                          (EXAMPLES / "cube_a.json").read_text())}) + "\n")
    out = tmp_path / "results.jsonl"
    proc = run_cli("batch", scenes, "--out", out)
    assert proc.returncode == 0, proc.stderr
    lines = {line["id"]: line for line in map(json.loads, open(out))}
    solved = tmp_path / "solve.json"
    proc = run_cli("solve", EXAMPLES / "hertz_taxels.json", "--json", solved)
    assert proc.returncode == 0, proc.stderr
    theirs = json.load(open(solved))
    assert lines["taxels"]["sensors"] == theirs["sensors"]
    assert "sensors" not in lines["plain"]
    assert "stick_fraction" not in lines["taxels"]["fingers"][0]  # frictionless tip
    cube_json = tmp_path / "cube.json"
    proc = run_cli("solve", EXAMPLES / "cube_a.json", "--json", cube_json)
    assert proc.returncode == 0, proc.stderr
    cube = json.load(open(cube_json))
    for ours, f in zip(lines["plain"]["fingers"], cube["fingers"], strict=True):
        stick, slip = f["stick_count"], f["slip_count"]
        assert stick + slip > 0
        assert ours["stick_fraction"] == stick / (stick + slip)


def test_a_batch_writes_a_tactile_dataset_of_each_grasps_arrays_and_labels(run_cli, tmp_path):
    """`grasp sweep --run --npz` (and `grasp batch --npz`): per grasp with a sensor its arrays,
    as `grasp solve --npz` writes them, and its labels, equal to its result line's numbers bit
    for bit; `grasps` lists the indices; a grasp without a sensor has no entry."""
    import json
    scene = json.loads((EXAMPLES / "hertz_taxels.json").read_text())
    scene["fingers"][0]["friction"] = {"mu": 0.5}
    scene["object"]["external_forces"] = [{"force": [1.0, 0.0, 0.0], "at": [0.0, 0.0, 0.0]}]
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    out, npz = tmp_path / "sweep.jsonl", tmp_path / "dataset.npz"
    proc = run_cli("sweep", path, "--vary", "fingers[0].friction.mu=0.2:0.8:4", "--run",
                   "--out", out, "--npz", npz)
    assert proc.returncode == 0, proc.stderr
    d = np.load(npz)
    lines = [json.loads(line) for line in open(out)]
    assert list(d["grasps"]) == [line["index"] for line in lines] == [0, 1, 2, 3]
    for line in lines:
        g = f"g{line['index']:08d}/tip/"
        f = line["fingers"][0]
        assert float(d[g + "normal_force_n"]) == f["normal_force_n"]
        assert list(d[g + "tangential_force_n"]) == f["tangential_force_n"]
        assert float(d[g + "friction_utilization"]) == f["friction_utilization"]
        assert float(d[g + "stick_fraction"]) == f["stick_fraction"]
        taxels = np.array(line["sensors"][0]["force_n"]).reshape(5, 5, 3)
        assert np.array_equal(d[g + "taxels/force_n"], taxels)
    # Stuck more firmly as mu grows: the labels move as the physics says.
    stick = [float(d[f"g{k:08d}/tip/stick_fraction"]) for k in range(4)]
    assert stick == sorted(stick), stick
    # A batch mixing a plain scene: no entry for it; --npz with --resume is refused.
    scenes = tmp_path / "mixed.jsonl"
    scenes.write_text(json.dumps({"id": "plain", "scene": json.loads(
        (EXAMPLES / "cube_a.json").read_text())}) + "\n" + json.dumps({"id": "taxels", "scene": scene}) + "\n")
    out2, npz2 = tmp_path / "mixed.jsonl.out", tmp_path / "mixed.npz"
    proc = run_cli("batch", scenes, "--out", out2, "--npz", npz2)
    assert proc.returncode == 0, proc.stderr
    assert list(np.load(npz2)["grasps"]) == [1]
    proc = run_cli("batch", scenes, "--out", out2, "--npz", tmp_path / "again.npz", "--resume")
    assert proc.returncode != 0 and "--npz with --resume" in proc.stderr, proc.stderr


def test_a_gel_image_is_the_clis_npz_and_each_steps_history(run_cli, tmp_path):
    # examples/ridged_gel.json: a 90 x 90 gel image on the element lattice. Python's arrays
    # are the CLI's .npz bit for bit; the hand-off's history stacks each step's image.
    scene = EXAMPLES / "ridged_gel.json"
    sol = grasp.solve(grasp.Scene(scene))
    g = sol.sensor("gel")["gel"]
    assert g["height_m"].shape == (90, 90)
    assert g["normal"].shape == (90, 90, 3) and g["rgb"].shape == (90, 90, 3)
    assert g["position_m"].shape == (90, 90, 2) and len(g["pixel_m"]) == 2
    npz = tmp_path / "gel.npz"
    proc = run_cli("solve", scene, "--npz", npz)
    assert proc.returncode == 0, proc.stderr
    cli = np.load(npz)
    for field in ("height_m", "normal", "rgb"):
        assert np.array_equal(g[field], cli[f"gel/gel/{field}"]), field
    assert np.array_equal(np.round(g["rgb"] * 255).astype(np.uint8), cli["gel/gel/rgb8"])
    # Unit normals toward the camera.
    assert np.allclose(np.linalg.norm(g["normal"], axis=2), 1.0, atol=1e-12)
    assert (g["normal"][..., 2] > 0).all()
    run = grasp.transfer(grasp.Scene(scene), EXAMPLES / "ridged_gel.schedule.json")
    h = run.sensor_history("gel")["gel"]
    steps = len(run.times_s)
    assert h["height_m"].shape == (steps, 90, 90) and h["rgb"].shape == (steps, 90, 90, 3)
    for k in range(steps):
        assert np.array_equal(h["height_m"][k], run.step(k).sensor("gel")["gel"]["height_m"])
    # The push grows step by step: the dimple deepens.
    deepest = h["height_m"].max(axis=(1, 2))
    assert (np.diff(deepest) > 0).all(), deepest
