"""grasp.solve: element arrays consistent with the resultants and with equilibrium (computed
here in NumPy, independently of the library's residuals), options, and solver outcomes."""

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES


def solved_cube_a():
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    return scene, grasp.solve(scene)


def test_element_arrays_have_one_row_per_element_and_sum_to_the_resultants():
    scene, sol = solved_cube_a()
    assert sol.status == "solved" and sol.has_forces and sol.reason is None
    n = 3 * 25
    assert sol.positions_m.shape == (n, 3)
    assert sol.normal_forces_n.shape == (n,)
    assert sol.tangential_forces_n.shape == (n, 3)
    assert sol.tangential_forces_local_n.shape == (n, 2)
    assert sol.slips_m.shape == (n, 2)
    assert sol.pressures_pa.shape == sol.gaps_m.shape == sol.finger.shape == (n,)
    assert set(sol.states) <= {"stick", "slip", "separated"}
    assert sol.finger_names == scene.finger_names
    # Sums over each finger's elements against the library's resultants: the same numbers
    # added in another order, so agreement to round-off (1e-12 of the load) is required.
    for i, f in enumerate(sol.fingers):
        mine = sol.finger == i
        assert abs(sol.normal_forces_n[mine].sum() - f["normal_force_n"]) <= 1e-12 * sol.load_scale_n
        q = sol.tangential_forces_n[mine].sum(axis=0)
        assert np.abs(q - np.array(f["tangential_force_n"])).max() <= 1e-12 * sol.load_scale_n
    assert np.allclose(sol.finger_normal_forces_n, [f["normal_force_n"] for f in sol.fingers], rtol=0, atol=0)
    assert (sol.normal_forces_n >= 0).all()


def test_element_forces_hold_the_object_in_equilibrium():
    scene, sol = solved_cube_a()
    d = scene.to_dict()
    normals = np.array([f["normal"] for f in d["fingers"]])[sol.finger]
    forces = sol.normal_forces_n[:, None] * normals + sol.tangential_forces_n
    weight = d["object"]["weight"] * np.array(d["object"]["gravity"])
    com = np.array(d["object"]["center_of_mass"])
    total_force = forces.sum(axis=0) + weight
    total_moment = np.cross(sol.positions_m - com, forces).sum(axis=0)
    # The solver's tolerance is 1e-10 of the load scale; 1e-8 leaves room for the sums.
    assert np.linalg.norm(total_force) <= 1e-8 * sol.load_scale_n
    length_m = np.linalg.norm(sol.positions_m - com, axis=1).max()
    assert np.linalg.norm(total_moment) <= 1e-8 * sol.load_scale_n * length_m
    # The friction force lies in the tangent plane, within the cone mu F (mu = 0.4).
    assert np.abs((sol.tangential_forces_n * normals).sum(axis=1)).max() <= 1e-12 * sol.load_scale_n
    g = np.linalg.norm(sol.tangential_forces_n, axis=1)
    assert (g <= 0.4 * sol.normal_forces_n + 1e-9 * sol.load_scale_n).all()


def test_native_and_clarabel_agree_to_1e_8_of_the_load():
    # As in tests/solver_equivalence.rs: Clarabel, the reference, at 1e-12 (at its default
    # 1e-10 its element friction forces are good to about 1e-8 of the load only).
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    a = grasp.solve(scene, solver="native")
    b = grasp.solve(scene, solver="clarabel", tolerance=1e-12)
    assert a.solver["solver"] == "native" and b.solver["solver"] == "clarabel"
    assert np.abs(a.normal_forces_n - b.normal_forces_n).max() <= 1e-8 * a.load_scale_n
    assert np.abs(a.tangential_forces_n - b.tangential_forces_n).max() <= 1e-8 * a.load_scale_n


def test_dense_and_fft_compliance_agree_and_say_which_ran():
    # The FFT operator discretises the same operator as the dense matrix (products
    # equal to 1e-12), so the native solver's answers agree to its tolerance; 1e-8 of the load,
    # as in tests/solver_equivalence.rs.
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    dense = grasp.solve(scene, solver="native", compliance="dense")
    fft = grasp.solve(scene, solver="native", compliance="fft")
    assert dense.solver["compliance"] == "dense" and fft.solver["compliance"] == "fft"
    assert dense.solver["inner_iterations"] == 0 < fft.solver["inner_iterations"]
    assert np.abs(dense.normal_forces_n - fft.normal_forces_n).max() <= 1e-8 * dense.load_scale_n
    with pytest.raises(ValueError, match="compliance="):
        grasp.solve(scene, compliance="sparse")


def test_model_override_runs_the_coulomb_fixed_point():
    scene = grasp.Scene(EXAMPLES / "plate_handoff_coulomb.json")
    coulomb = grasp.solve(scene)
    assert scene.model == "coulomb" and coulomb.sequential is not None
    energy = grasp.solve(scene, model="energy")
    assert energy.sequential is None
    assert energy.status == "solved"


def test_a_grasp_that_cannot_hold_is_a_status_not_an_exception(cube_a_dict):
    for f in cube_a_dict["fingers"]:
        f["friction"] = {"mu": 0.01}
    sol = grasp.solve(grasp.Scene(cube_a_dict))
    assert sol.status == "no_equilibrium" and not sol.has_forces
    assert sol.reason
    assert sol.normal_forces_n.shape == (0,)
    assert sol.residuals is None


def test_bad_options_name_the_argument():
    scene = grasp.Scene(EXAMPLES / "cube_a.json")
    with pytest.raises(ValueError, match="solver="):
        grasp.solve(scene, solver="fast")
    with pytest.raises(ValueError, match="model="):
        grasp.solve(scene, model="tresca")
    with pytest.raises(ValueError, match="tolerance="):
        grasp.solve(scene, tolerance=0.5)
    with pytest.raises(TypeError):
        grasp.solve(scene, "energy")  # options are keyword-only


def test_timings_and_repr():
    _, sol = solved_cube_a()
    assert 0 < sol.solve_time_s < 10 and 0 < sol.build_time_s < 10
    assert sol.solver["iterations"] > 0 and sol.solver["unknowns"] > 0
    assert repr(sol).startswith("Solution(solved: f1 ")


def test_a_scene_too_large_for_the_address_space_is_a_memory_error_not_an_abort():
    """In a 300 MiB address space (`ulimit -v`; a 512 x 512 patch needs about 600 MiB to
    solve, measured) the fine scene raises MemoryError naming what did not fit and the fix, and
    the same process goes on to solve the small scene: the refused allocation is reported,
    not an abort of the interpreter (exit 134)."""
    import subprocess
    import sys
    script = f"""
import json, grasp
scene = json.loads(open({str(EXAMPLES / "hertz_sphere_on_flat.json")!r}).read())
fine = json.loads(json.dumps(scene))
fine["fingers"][0]["patch"]["grid"] = [512, 512]
try:
    grasp.solve(grasp.Scene(fine))
    print("fine solved")
except MemoryError as e:
    print("MemoryError:", e)
print("small", grasp.solve(grasp.Scene(scene)).status)
"""
    proc = subprocess.run(["sh", "-c", 'ulimit -v 300000 && exec "$0" -c "$1"', sys.executable,
                           script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith("MemoryError: ") and "not enough memory for" in lines[0], lines
    assert "coarser grid" in lines[0], lines
    assert lines[1] == "small solved", lines


def test_a_dense_compliance_too_large_gives_the_command_lines_estimate(run_cli):
    """Forcing the dense compliance on a fine grid is refused in Python with the same estimate
    of a whole solve's memory as the command line's memory check gives for the same scene."""
    import re

    scene = EXAMPLES / "plate_transfer_fine.json"
    done = run_cli("solve", scene, "--compliance", "dense")
    cli = re.search(r"needs an estimated ([0-9.]+ GiB) of memory", done.stderr)
    assert done.returncode != 0 and cli, done.stderr
    with pytest.raises(grasp.SceneError) as err:
        grasp.solve(grasp.Scene(scene), compliance="dense")
    assert f"needs an estimated {cli.group(1)} of memory" in str(err.value)
    assert "`compliance=`" in str(err.value)


def test_the_default_tolerance_is_the_librarys():
    # `solve`'s signature writes its default tolerance as a number; the library's own default
    # (grasp_model::DEFAULT_TOLERANCE, the CLI's --tolerance default too) is the one source.
    import inspect

    default = inspect.signature(grasp.solve).parameters["tolerance"].default
    assert default == grasp._native.DEFAULT_TOLERANCE
