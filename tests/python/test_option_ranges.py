"""Numbers from Python that cannot crash, hang or run away.

- `grasp.solve`'s options go through the library's own check (`SolveOptions::validate`, the
  one the CLI calls): out-of-range and non-finite tolerances are a ValueError naming the
  keyword (`tolerance=`, respelled from the library's `SolveOptions::tolerance`), the value in
  readable form and the range; the ends of the range solve.
- Messages quote numbers in exponent form (no 309-digit 1e308), nested shape errors carry
  their path (`object.shape.mesh.unit`, not "mesh.unitunknown"), a mesh with a NaN vertex is
  refused at `object.shape.mesh.file` (not reported as a ray starting inside), and a bad
  external-load CSV column is one problem, not two.
"""

import json
import math
import re
import shutil

import pytest

import grasp
from conftest import EXAMPLES


def longest_digit_run(text):
    return max((len(m) for m in re.findall(r"\d+", text)), default=0)


@pytest.mark.parametrize(
    "value, shown",
    [
        (2e-16, "2e-16"),
        (1e-300, "1e-300"),
        (0.0, "0"),
        (-1e-10, "-1e-10"),
        (0.5, "0.5"),
        (1e308, "1e308"),
        (math.nan, "NaN"),
        (math.inf, "inf"),
        (-math.inf, "-inf"),
    ],
)
def test_a_tolerance_outside_its_range_names_the_keyword_and_the_range(value, shown):
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    with pytest.raises(ValueError) as e:
        grasp.solve(scene, tolerance=value)
    message = str(e.value)
    assert message.startswith(f"`tolerance=` is {shown};"), message
    assert "[1e-14, 0.01]" in message and "e.g. 1e-10" in message, message
    assert "SolveOptions" not in message, message
    assert longest_digit_run(message) <= 20, message


def test_the_ends_of_the_tolerance_range_solve():
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    for tolerance in (1e-14, 1e-2):
        sol = grasp.solve(scene, tolerance=tolerance)
        # The tightest end may not be met on every grasp: then an outcome with a reason.
        assert sol.status in ("solved", "no_convergence"), sol.status
        assert sol.has_forces or sol.reason


def test_an_unknown_solver_names_the_keyword():
    with pytest.raises(ValueError, match="solver="):
        grasp.solve(grasp.Scene(EXAMPLES / "cube_a.json"), solver="fast")


def test_library_option_names_reach_python_as_keywords(cube_a_dict):
    """The library names an option as its Rust API spells it (`SolveOptions::compliance`); the
    module respells every such name as its keyword argument (`keywords.rs`, `in_keywords`). A
    message from deep in the library, not from the module's own argument checks: Clarabel
    refusing an FFT compliance too large to write out (40 x 40 elements, 4800 unknowns)."""
    cube_a_dict["fingers"][0]["patch"]["grid"] = [40, 40]
    scene = grasp.Scene(cube_a_dict)
    with pytest.raises(grasp.GraspError) as e:
        grasp.solve(scene, solver="clarabel", compliance="fft")
    message = str(e.value)
    assert "set `compliance=` to dense" in message, message
    assert "SolveOptions" not in message, message
    # A scene problem (a dense compliance too large for a 100 x 100 patch with friction)
    # names the keyword too, in the message and in its problems' fix.
    cube_a_dict["fingers"][0]["patch"]["grid"] = [100, 100]
    with pytest.raises(grasp.SceneError) as e:
        grasp.solve(grasp.Scene(cube_a_dict), compliance="dense")
    assert "SolveOptions" not in str(e.value), str(e.value)
    assert any("`compliance=`" in p["fix"] for p in e.value.problems), e.value.problems


def test_extreme_scene_numbers_are_quoted_in_exponent_form(cube_a_dict):
    for value in (1e308, -1e308, 5e-324):
        for where in ("weight", "youngs_modulus", "poisson_ratio", "size"):
            if where == "poisson_ratio" and value == 5e-324:
                continue  # a valid ratio
            d = json.loads(json.dumps(cube_a_dict))
            if where == "weight":
                d["object"]["weight"] = value
            elif where == "size":
                d["fingers"][0]["patch"]["size"][0] = value
            else:
                d["fingers"][0]["material"][where] = value
            with pytest.raises(grasp.SceneError) as e:
                grasp.Scene(d)
            text = str(e.value) + json.dumps(e.value.problems)
            assert longest_digit_run(text) <= 20, text


def test_extreme_schedule_numbers_are_quoted_in_exponent_form():
    scene = grasp.Scene(EXAMPLES / "plate_transfer.json")
    schedule = json.loads((EXAMPLES / "plate_transfer.schedule.json").read_text())
    schedule["time"] = {"start": 1e308, "end": -1e308, "step": 1e308}
    with pytest.raises(grasp.ScheduleError) as e:
        grasp.transfer(scene, schedule)
    text = str(e.value)
    assert "1e308" in text and longest_digit_run(text) <= 20, text


def mug_folder(tmp_path, scene_change=None, vertex=None):
    """The mug scene copied into tmp_path with its mesh, optionally changed."""
    (tmp_path / "meshes").mkdir()
    obj = (EXAMPLES / "meshes" / "mug.obj").read_text().splitlines()
    if vertex is not None:
        first = next(i for i, line in enumerate(obj) if line.startswith("v "))
        obj[first] = vertex
    (tmp_path / "meshes" / "mug.obj").write_text("\n".join(obj) + "\n")
    scene = json.loads((EXAMPLES / "mug_power_grasp.json").read_text())
    if scene_change:
        scene_change(scene)
    path = tmp_path / "mug.json"
    path.write_text(json.dumps(scene))
    return path


def test_an_unknown_mesh_unit_is_named_by_its_path(tmp_path):
    def furlong(s):
        s["object"]["shape"]["mesh"]["unit"] = "furlong"

    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(mug_folder(tmp_path, scene_change=furlong))
    (problem,) = e.value.problems
    assert problem["path"] == "object.shape.mesh.unit", problem
    assert problem["message"].startswith("unknown variant `furlong`"), problem


@pytest.mark.parametrize("vertex", ["v nan 0 0", "v 0 inf 0", "v 0 0 1e30"])
def test_a_mesh_vertex_that_is_not_finite_or_too_far_is_refused_at_the_file(tmp_path, vertex):
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(mug_folder(tmp_path, vertex=vertex))
    (problem,) = e.value.problems
    assert problem["path"] == "object.shape.mesh.file", problem
    assert "vertex 0 of the mesh" in problem["message"], problem
    assert "ray" not in problem["fix"], problem


def test_a_bad_external_load_column_is_one_problem(tmp_path):
    scene = grasp.Scene(EXAMPLES / "plate_handoff_coulomb.json")
    shutil.copy(EXAMPLES / "plate_bump.csv", tmp_path / "bump.csv")
    schedule = json.loads((EXAMPLES / "plate_bump.schedule.json").read_text())
    schedule["external"]["csv"]["path"] = str(tmp_path / "bump.csv")
    schedule["external"]["csv"]["force_columns"] = [None, None, "no_such_column"]
    with pytest.raises(grasp.ScheduleError) as e:
        grasp.transfer(scene, schedule)
    (problem,) = e.value.problems
    assert problem["path"] == "external.csv.columns", problem
    assert "`no_such_column`" in problem["message"], problem


@pytest.mark.parametrize("value, shown", [(0, "0"), (-1, "-1"), (-(2**70), str(-(2**70))),
                                          (2**64, "more than 18446744073709551615")])
def test_max_memory_outside_its_range_names_the_keyword_and_the_range(value, shown):
    scene = grasp.Scene(EXAMPLES / "plate_transfer.json")
    with pytest.raises(ValueError) as e:
        grasp.transfer(scene, EXAMPLES / "plate_transfer.schedule.json", max_memory=value)
    message = str(e.value)
    assert message.startswith(f"`max_memory=` is {shown};"), message
    assert "[1, 18446744073709551615]" in message and "e.g. 2**30" in message, message
    with pytest.raises(TypeError, match="`max_memory=` is '1GiB'; give a number of bytes"):
        grasp.transfer(scene, EXAMPLES / "plate_transfer.schedule.json", max_memory="1GiB")
    assert len(grasp.transfer(scene, EXAMPLES / "plate_transfer.schedule.json", max_memory=2**64 - 1)) == 200
