"""The MCAP's compact maps of large patches (`/grasp/patch_maps`), read with the independent
`mcap` reader and decoded with base64 and NumPy, equal the solver's element values of the same
run (`grasp.transfer(...).step(i)`) rounded to float32 by NumPy: exactly, value for value.
The fine-patch example (`examples/plate_transfer_fine.json`, receivers on 128 x 128 elements)
on its schedule with three steps (0, 9.95 and 19.9 s) instead of 200."""

import base64
import json

import numpy as np

import grasp
from conftest import EXAMPLES, checker

mcap_reader = checker("mcap.reader", reason="mcap is installed by scripts/install-checkers.sh")

STATE_CODES = {"stick": 0, "slip": 1, "separated": 2, "off_surface": 3, "frictionless": 4}


def decoded(text, dtype):
    return np.frombuffer(base64.b64decode(text, validate=True), dtype=dtype)


def patch_maps(path):
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f)
        return [(schema.name, json.loads(msg.data))
                for schema, _, msg in reader.iter_messages(topics=["/grasp/patch_maps"])]


def check_patch(patch, sol, finger_index):
    mine = sol.finger == finger_index
    n = int(mine.sum())
    nx, ny = patch["grid"]
    assert (nx, ny, n) == (128, 128, 128 * 128)
    f32 = lambda key: decoded(patch[key], "<f4")  # noqa: E731
    np.testing.assert_array_equal(f32("normal_force_n"), sol.normal_forces_n[mine].astype(np.float32))
    np.testing.assert_array_equal(f32("pressure_pa"), sol.pressures_pa[mine].astype(np.float32))
    np.testing.assert_array_equal(f32("gap_m"), sol.gaps_m[mine].astype(np.float32))
    tangential = sol.tangential_forces_local_n[mine].astype(np.float32)
    np.testing.assert_array_equal(f32("tangential_force_n").reshape(n, 2), tangential)
    np.testing.assert_array_equal(f32("slip_m").reshape(n, 2), sol.slips_m[mine].astype(np.float32))
    codes = np.array([STATE_CODES[s] for s in sol.states[mine]], dtype=np.uint8)
    np.testing.assert_array_equal(decoded(patch["state"], "<u1"), codes)
    # Element k = i ny + j: the pressure as an (nx, ny) map peaks where the solver's does.
    pressure = f32("pressure_pa").reshape(nx, ny)
    k = int(np.argmax(sol.pressures_pa[mine]))
    assert pressure[k // ny, k % ny] == pressure.max()


def test_compact_maps_are_the_solver_s_values_as_float32(tmp_path):
    schedule = json.loads((EXAMPLES / "plate_transfer.schedule.json").read_text())
    schedule["time"]["step"] = 9.95
    path = tmp_path / "fine.mcap"
    run = grasp.transfer(grasp.Scene(EXAMPLES / "plate_transfer_fine.json"), schedule, mcap=path)
    found = patch_maps(path)
    assert len(found) == len(run) == 3
    names = run.finger_names
    checked = 0
    for i, (schema, message) in enumerate(found):
        assert schema == "grasp.PatchMaps" and message["step"] == i
        sol = run.step(i)
        for patch in message["patches"]:
            check_patch(patch, sol, sol.finger_names.index(patch["name"]))
            checked += 1
        # The receivers f3, f4 are released in the first step, loaded after it.
        assert [p["name"] for p in message["patches"]] == ([] if i == 0 else ["f3", "f4"])
    assert checked == 4 and names == ["f1", "f2", "f3", "f4"]
