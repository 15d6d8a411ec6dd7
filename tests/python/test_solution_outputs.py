"""A solution's element fields in every form agree exactly: `grasp solve --json` (records up to
64 x 64 elements a finger, one array per field above), `grasp solve --npz` read back with NumPy
(an independent reader of the format), Python's `Solution` arrays, `Solution.element_fields`,
`Solution.to_npz` and `Solution.to_json`. Every comparison is exact: each form carries the
solver's float64 values (JSON's shortest round-trip text reads back to the same float)."""

import json

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, element_records

FIELDS = ["index", "local_m", "position_m", "normal_force_n", "tangential_force_n", "pressure_pa",
          "traction_pa", "gap_m", "slip_m", "step_slip_m", "state"]


def hertz(tmp_path, n):
    """The Hertz example on an n x n grid, as a scene file."""
    scene = json.loads((EXAMPLES / "hertz_sphere_on_flat.json").read_text())
    scene["fingers"][0]["patch"]["grid"] = [n, n]
    path = tmp_path / f"hertz_{n}.json"
    path.write_text(json.dumps(scene))
    return path


def scenes(tmp_path):
    """A fine patch (72 x 72, columns), a small one (records), several fingers, friction."""
    return [hertz(tmp_path, 72), hertz(tmp_path, 21), EXAMPLES / "cube_a.json",
            EXAMPLES / "plate_transfer.json"]


def test_cli_npz_equals_cli_json_exactly(run_cli, tmp_path):
    for scene in scenes(tmp_path):
        out_json, out_npz = tmp_path / "s.json", tmp_path / "s.npz"
        proc = run_cli("solve", scene, "--json", out_json, "--npz", out_npz, "--force")
        assert proc.returncode == 0, proc.stderr
        written = json.loads(out_json.read_text())
        arrays = np.load(out_npz)
        names = [f["name"] for f in written["fingers"]]
        assert sorted(arrays.files) == sorted(["state_names"] + [f"{n}/{f}" for n in names for f in FIELDS + ["grid"]])
        assert list(arrays["state_names"]) == ["stick", "slip", "separated", "off_surface", "frictionless"]
        for finger in written["fingers"]:
            fine = len(element_records(finger)) > 64 * 64
            assert ("element_fields" in finger) == fine and ("elements" in finger) != fine
            records = element_records(finger)
            for field in FIELDS:
                from_json = np.array([e[field] for e in records])
                from_npz = arrays[f"{finger['name']}/{field}"]
                if field == "state":
                    assert from_npz.dtype == np.uint8
                    from_npz = arrays["state_names"][from_npz]
                assert from_npz.shape == from_json.shape, field
                assert np.array_equal(from_npz, from_json), (scene.name, field)
            assert arrays[f"{finger['name']}/pressure_pa"].dtype == np.float64
            assert arrays[f"{finger['name']}/index"].dtype == np.int64


def test_npz_files_carry_each_patch_s_grid_shape(run_cli, tmp_path):
    """An archive's fields are one row per element: `<finger>/grid` gives the patch's
    `[nx, ny]` to reshape them into the patch's map, in the CLI's archive and Python's alike."""
    out = tmp_path / "s.npz"
    for n in [21, 31]:
        assert run_cli("solve", hertz(tmp_path, n), "--npz", out, "--force").returncode == 0
        arrays = np.load(out)
        assert arrays["tip/grid"].dtype == np.int64 and list(arrays["tip/grid"]) == [n, n]
        pressure = arrays["tip/pressure_pa"].reshape(arrays["tip/grid"])
        assert pressure[n // 2, n // 2] == arrays["tip/pressure_pa"].max()
        sol = grasp.solve(grasp.Scene(hertz(tmp_path, n)))
        assert list(sol.element_fields("tip")["grid"]) == [n, n]
    out_cube = tmp_path / "cube.npz"
    assert run_cli("solve", EXAMPLES / "cube_a.json", "--npz", out_cube).returncode == 0
    cube = np.load(out_cube)
    for name in ["f1", "f2", "f3"]:
        assert list(cube[f"{name}/grid"]) == [5, 5]


def test_python_arrays_equal_the_cli_json(run_cli, tmp_path):
    for scene in scenes(tmp_path):
        out = tmp_path / "s.json"
        assert run_cli("solve", scene, "--json", out, "--force").returncode == 0
        written = json.loads(out.read_text())
        sol = grasp.solve(grasp.Scene(scene))
        records = [e for f in written["fingers"] for e in element_records(f)]
        assert np.array_equal(sol.normal_forces_n, [e["normal_force_n"] for e in records])
        assert np.array_equal(sol.pressures_pa, [e["pressure_pa"] for e in records])
        assert np.array_equal(sol.positions_m, [e["position_m"] for e in records])
        assert np.array_equal(sol.slips_m, [e["slip_m"] for e in records])
        assert list(sol.states) == [e["state"] for e in records]
        for finger in written["fingers"]:
            fields = sol.element_fields(finger["name"])
            assert sorted(fields) == sorted(FIELDS + ["grid"])
            for field in FIELDS:
                want = np.array([e[field] for e in element_records(finger)])
                assert np.array_equal(fields[field], want), field
        # Resultants without their elements, as the JSON's.
        for mine, theirs in zip(sol.fingers, written["fingers"]):
            assert "elements" not in mine and "element_fields" not in mine
            assert mine["normal_force_n"] == theirs["normal_force_n"]
        # The same text but for the times measured anew; `to_dict` (built without a JSON
        # value in between) the same object as that text read back.
        assert without_times(json.loads(sol.to_json())) == without_times(written)
        assert without_times(sol.to_dict()) == without_times(written)


def test_to_dict_leaves_the_garbage_collector_as_it_was():
    """`to_dict` pauses Python's cyclic collector while it builds the dict: afterwards the
    collector is on or off as the caller had it."""
    import gc
    sol = grasp.solve(grasp.Scene(EXAMPLES / "cube_a.json"))
    assert gc.isenabled()
    sol.to_dict()
    assert gc.isenabled()
    gc.disable()
    try:
        sol.to_dict()
        assert not gc.isenabled()
    finally:
        gc.enable()


def without_times(v):
    """`v` without the wall times (`*time_s`), measured anew in every run."""
    if isinstance(v, dict):
        return {k: without_times(x) for k, x in v.items() if not k.endswith("time_s")}
    if isinstance(v, list):
        return [without_times(x) for x in v]
    return v


def test_to_npz_writes_the_cli_archive_and_keeps_existing_files(run_cli, tmp_path):
    scene = hertz(tmp_path, 72)
    assert run_cli("solve", scene, "--npz", tmp_path / "cli.npz").returncode == 0
    sol = grasp.solve(grasp.Scene(scene))
    sol.to_npz(tmp_path / "py.npz")
    cli, py = np.load(tmp_path / "cli.npz"), np.load(tmp_path / "py.npz")
    assert cli.files == py.files
    for name in cli.files:
        assert np.array_equal(cli[name], py[name]), name
    with pytest.raises(FileExistsError, match="overwrite=True"):
        sol.to_npz(tmp_path / "py.npz")
    sol.to_npz(tmp_path / "py.npz", overwrite=True)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        sol.to_npz(tmp_path / "missing" / "py.npz")
    with pytest.raises(KeyError, match="no finger `nope`"):
        sol.element_fields("nope")


def test_cli_npz_is_refused_over_an_existing_file_without_force(run_cli, tmp_path):
    target = tmp_path / "keep.npz"
    target.write_bytes(b"mine")
    proc = run_cli("solve", EXAMPLES / "cube_a.json", "--npz", target)
    assert proc.returncode == 1
    assert "already exists" in proc.stderr and "--force" in proc.stderr
    assert target.read_bytes() == b"mine"


def test_transfer_npz_holds_every_step_as_the_python_steps(run_cli, tmp_path):
    scene, schedule = EXAMPLES / "plate_transfer.json", EXAMPLES / "plate_transfer.schedule.json"
    out = tmp_path / "steps.npz"
    proc = run_cli("transfer", scene, "--schedule", schedule, "--npz", out)
    assert proc.returncode == 0, proc.stderr
    arrays = np.load(out)
    run = grasp.transfer(grasp.Scene(scene), str(schedule), npz=tmp_path / "py.npz")
    assert np.array_equal(arrays["times_s"], run.times_s)
    mine = np.load(tmp_path / "py.npz")
    assert mine.files == arrays.files
    for k in [0, 57, len(run.times_s) - 1]:
        step = run.step(k)
        for name in step.finger_names:
            fields = step.element_fields(name)
            for field in FIELDS:
                got = arrays[f"step_{k:05}/{name}/{field}"]
                if field == "state":
                    got = arrays["state_names"][got]
                assert np.array_equal(got, fields[field]), (k, name, field)
                assert np.array_equal(mine[f"step_{k:05}/{name}/{field}"], arrays[f"step_{k:05}/{name}/{field}"])
