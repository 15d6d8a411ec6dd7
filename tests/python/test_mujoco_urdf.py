"""grasp.mujoco with URDF grippers: MuJoCo compiles the URDF, the bridge's URDF options go into a
copy of its text in memory, and the grasp equals the one of the same gripper written in MJCF.

Tolerance, and why: 1e-9 relative (1e-12 absolute, in m and N, for numbers near zero, such as a
coordinate that is 0 in one and 1e-18 in the other) between the URDF gripper and its MJCF twin
(examples/mujoco/urdf_pinch.urdf and urdf_pinch.xml): both compile to the same MuJoCo model up to
URDF's conventions (the palm fused into the world instead of a body without a joint, so the
fingers' positions are summed at compile time instead of by the kinematics; full sizes halved),
so what may differ is round-off, and 1e-9 is far above it and far below any difference in the
model (dropping the URDF's <mujoco><option> alone changes the grasp by more than 1e-3).
"""

import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, ROOT, checker, numbers_close

mujoco = checker("mujoco", reason="MuJoCo is not installed (scripts/install-checkers.sh installs mujoco==4.0.0)")
import grasp.mujoco as gm  # noqa: E402

MJ = EXAMPLES / "mujoco"
URDF = MJ / "urdf_pinch.urdf"
MJCF = MJ / "urdf_pinch.xml"
STATE = MJ / "urdf_pinch.state.json"
MATERIALS = MJ / "urdf_pinch.materials.json"
REL, ABS = 1e-9, 1e-12
# A tetrahedron (OBJ) for the mesh folder's tests.
TET = "v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nv 0 0 0.01\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def python_m(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "grasp.mujoco", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=120)


def grasp_of(path, text=None):
    """The pinch's grasp from the model file (or from ``text``, an MJCF, in memory)."""
    model = gm.load_model(path) if text is None else mujoco.MjModel.from_xml_string(text)
    return gm.scene_from(model, gm.load_state(model, qpos=STATE), "box", materials=MATERIALS)


def without_description(scene):
    return {k: v for k, v in scene.items() if k != "description"}


@pytest.fixture(scope="module")
def both():
    return grasp_of(URDF), grasp_of(MJCF)


def test_mujoco_urdf_gripper_compiles_with_its_links_and_collisions_named(both):
    urdf, _ = both
    model = gm.load_model(URDF)
    bodies = [model.body(i).name for i in range(model.nbody)]
    # The palm, on a fixed joint, is fused into the world (MuJoCo's default for URDF); the box's
    # floating joint is a free joint; the collisions' names are the geoms'.
    assert bodies == ["world", "finger_left", "finger_right", "box"]
    assert model.jnt_type[model.joint("box").id] == mujoco.mjtJoint.mjJNT_FREE
    assert {"palm", "pad_left", "stem_left", "pad_right", "stem_right", "box"} <= {
        model.geom(i).name for i in range(model.ngeom)}
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC and model.opt.impratio == 10
    assert urdf.finger_names == ["finger_left", "finger_right"]
    assert [f.geoms for f in urdf.fingers] == [["pad_left"], ["pad_right"]]
    assert [f.contact_count for f in urdf.fingers] == [4, 4]
    # The figures docs/guide/mujoco.md quotes (to their last digit).
    for f in urdf.fingers:
        assert f.normal_force_n == pytest.approx(0.5063, abs=5e-5)
        assert np.linalg.norm(f.friction_force_n) == pytest.approx(0.2450, abs=5e-5)


def test_mujoco_urdf_gripper_grasp_equals_the_mjcf_twins(both):
    urdf, mjcf = both
    # Not trivially equal: each pad squeezes half a newton and its friction carries half the weight.
    assert all(f.normal_force_n > 0.4 for f in urdf.fingers)
    numbers_close(without_description(urdf.scene_dict), without_description(mjcf.scene_dict))
    for a, b in zip(urdf.fingers, mjcf.fingers, strict=True):
        assert a.name == b.name and a.geoms == b.geoms
        numbers_close([a.normal_force_n, *a.friction_force_n, *a.center_of_pressure_m],
                      [b.normal_force_n, *b.friction_force_n, *b.center_of_pressure_m])
    ours, theirs = grasp.solve(urdf.scene), grasp.solve(mjcf.scene)
    assert ours.status == theirs.status == "solved"
    for field in ("finger_normal_forces_n", "normal_forces_n", "tangential_forces_n"):
        a, b = np.asarray(getattr(ours, field)), np.asarray(getattr(theirs, field))
        assert a.shape == b.shape and np.allclose(a, b, rtol=REL, atol=ABS), field
    assert min(ours.finger_normal_forces_n) > 0.4


def test_mujoco_urdf_twin_comparison_sees_a_changed_option():
    # The comparison can fail: the MJCF twin without the URDF's <mujoco><option> (pyramidal
    # cones, impratio 1) gives another grasp, by far more than the tolerance.
    text = MJCF.read_text()
    assert '<option cone="elliptic" impratio="10"/>' in text
    plain = grasp_of(None, text.replace('<option cone="elliptic" impratio="10"/>', ""))
    urdf = grasp_of(URDF)
    a = np.array([f.friction_force_n for f in urdf.fingers])
    b = np.array([f.friction_force_n for f in plain.fingers])
    assert np.max(np.abs(a - b)) > 1e-3 * np.max(np.abs(a))


def test_mujoco_urdf_gripper_scene_through_the_command_equals_the_mjcf_twins(tmp_path):
    outs = {}
    for name, model in (("urdf", URDF), ("mjcf", MJCF)):
        proc = python_m("scene", model, "--object", "box", "--qpos", STATE, "--materials", MATERIALS,
                        "--out", tmp_path / f"{name}.json", "--report", tmp_path / f"{name}.report.json")
        assert proc.returncode == 0, proc.stderr
        assert "finger_left" in proc.stdout and "grasp: solved" in proc.stdout, proc.stdout
        outs[name] = [json.loads((tmp_path / f"{name}{s}.json").read_text()) for s in ("", ".report")]
    assert "urdf_pinch.urdf" in outs["urdf"][0]["description"]
    numbers_close(without_description(outs["urdf"][0]), without_description(outs["mjcf"][0]))
    numbers_close(outs["urdf"][1], outs["mjcf"][1])  # the report: MuJoCo's forces and the solved ones
    # The command's scene is the API's.
    numbers_close(without_description(outs["urdf"][0]), without_description(grasp_of(URDF).scene_dict))


def mesh_urdf(mesh="package://pinch_meshes/meshes/tet.obj", compiler=""):
    """A URDF with a mesh collision named by a ROS package URI, and a box on a floating joint."""
    return f"""<robot name="m">{compiler}<link name="world"/>
      <link name="base"><inertial><mass value="0.1"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/>
        </inertial><collision name="tet"><geometry><mesh filename="{mesh}"/></geometry></collision></link>
      <joint name="base" type="fixed"><parent link="world"/><child link="base"/></joint>
      <link name="box"><inertial><mass value="0.1"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/>
        </inertial><collision name="box"><geometry><box size="0.01 0.01 0.01"/></geometry></collision></link>
      <joint name="box" type="floating"><parent link="world"/><child link="box"/></joint>
    </robot>"""


def test_mujoco_urdf_options_go_into_a_copy_and_the_users_file_is_unchanged(tmp_path):
    folder = tmp_path / "robot"
    (folder / "urdf").mkdir(parents=True)
    (folder / "meshes").mkdir()
    (folder / "meshes" / "tet.obj").write_text(TET)
    robot = folder / "urdf" / "m.urdf"
    robot.write_text(mesh_urdf(compiler='<mujoco><compiler fusestatic="false"/></mujoco>'))
    before = robot.read_bytes()
    # The file's own compiler keeps the base a body; the option overrides it, the mesh folder
    # finds the mesh by its bare name (package:// and folders stripped).
    with pytest.raises(gm.ModelLoadError, match="--mesh-dir"):
        gm.load_model(robot)
    kept = gm.load_model(robot, mesh_dir=folder / "meshes")
    assert kept.nmesh == 1 and mujoco.mj_name2id(kept, mujoco.mjtObj.mjOBJ_BODY, "base") > 0
    fused = gm.load_model(robot, mesh_dir=folder / "meshes", fuse_static=True, balance_inertia=True)
    assert mujoco.mj_name2id(fused, mujoco.mjtObj.mjOBJ_BODY, "base") < 0
    # The command: a mesh folder relative to the working folder, every URDF option.
    out = tmp_path / "out"
    out.mkdir()
    proc = python_m("handoff", robot, "--object", "box", "--rollout", tmp_path / "none.npz", "--mesh-dir", "meshes",
                    "--fuse-static", "--balance-inertia", "--out", out / "h", cwd=folder)
    assert proc.returncode == 1 and "none.npz" in proc.stderr, proc.stderr  # loaded; the rollout is missing
    assert robot.read_bytes() == before
    assert sorted(p.name for p in folder.rglob("*")) == ["m.urdf", "meshes", "tet.obj", "urdf"]
    assert list(out.iterdir()) == []


def test_mujoco_urdf_example_file_is_unchanged_by_a_run(tmp_path):
    before = URDF.read_bytes()
    proc = python_m("scene", URDF, "--object", "box", "--qpos", STATE, "--materials", MATERIALS, "--no-fuse-static",
                    "--balance-inertia", "--mesh-dir", MJ, "--out", tmp_path / "s.json", "--no-margin")
    assert proc.returncode == 0, proc.stderr
    assert URDF.read_bytes() == before
    # Kept as a body, the palm is the fingers' parent; the grasp is the same.
    numbers_close(without_description(json.loads((tmp_path / "s.json").read_text())),
                  without_description(grasp_of(MJCF).scene_dict))


def refused(proc, *words):
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr.startswith("error: ") and "Traceback" not in proc.stderr, proc.stderr
    for w in words:
        assert w in proc.stderr, (w, proc.stderr)


def test_mujoco_urdf_bad_input_is_a_named_error(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    base = ["--qpos", STATE, "--materials", MATERIALS, "--out", out / "s.json"]
    # A mesh folder that does not exist, named with the option.
    with pytest.raises(gm.ModelLoadError, match="the mesh folder .*nowhere given as --mesh-dir .* does not exist"):
        gm.load_model(URDF, mesh_dir=tmp_path / "nowhere")
    refused(python_m("scene", URDF, "--object", "box", "--mesh-dir", tmp_path / "nowhere", *base),
            f"the mesh folder {tmp_path / 'nowhere'} given as --mesh-dir", "does not exist; fix: give the folder")
    # A mesh the URDF names by a package URI, without a mesh folder.
    (tmp_path / "m.urdf").write_text(mesh_urdf())
    refused(python_m("scene", tmp_path / "m.urdf", "--object", "box", "--out", out / "s.json"),
            "MuJoCo cannot compile the URDF", "tet.obj", "fix: give --mesh-dir DIR")
    # An unknown suffix, named.
    (tmp_path / "robot.sdf").write_bytes(URDF.read_bytes())
    with pytest.raises(gm.ModelLoadError, match="suffix '.sdf'.*give an MJCF .xml, a URDF .urdf or a binary .mjb"):
        gm.load_model(tmp_path / "robot.sdf")
    refused(python_m("scene", tmp_path / "robot.sdf", "--object", "box", *base), "suffix '.sdf'")
    # URDF options for an MJCF.
    with pytest.raises(gm.ModelLoadError, match="--mesh-dir .* applies to a URDF model only"):
        gm.load_model(MJCF, mesh_dir=MJ)
    refused(python_m("scene", MJCF, "--object", "box", "--no-fuse-static", *base), "--fuse-static/--no-fuse-static",
            "to a URDF model only")
    # A URDF without the object: the fix says how a URDF makes one.
    refused(python_m("scene", URDF, "--object", "cup", *base), "no body 'cup'", 'type="floating"',
            "<parent link=\"world\"/>")
    # The object on a fixed joint: fused into the world, or a body without a joint.
    fixed = URDF.read_text().replace('name="box" type="floating"', 'name="box" type="fixed"')
    (tmp_path / "fixed.urdf").write_text(fixed)
    initial = base[2:]  # the initial state (the state file is the floating joint's)
    refused(python_m("scene", tmp_path / "fixed.urdf", "--object", "box", *initial), "no body 'box'", "fusestatic")
    refused(python_m("scene", tmp_path / "fixed.urdf", "--object", "box", "--no-fuse-static", *initial),
            "cannot be the grasped object: it has no joint", 'type="floating"')
    # The object's floating joint under a finger: MuJoCo's message, and where the joint belongs.
    (tmp_path / "under.urdf").write_text(URDF.read_text().replace(
        '<parent link="world"/>\n    <child link="box"/>', '<parent link="finger_left"/>\n    <child link="box"/>'))
    refused(python_m("scene", tmp_path / "under.urdf", "--object", "box", *base),
            "free joint can only be used on top level", "the world link as its parent")
    # No keyframes in a URDF: the state is a qpos file, in the joints' order.
    refused(python_m("scene", URDF, "--object", "box", "--keyframe", "grasped", "--out", out / "s.json"),
            "no keyframes", "--qpos FILE", "finger_left (1), finger_right (1), box (7")
    assert list(out.iterdir()) == []


def test_mujoco_urdf_shared_collision_names_are_dropped_with_a_warning(tmp_path):
    text = URDF.read_text().replace('collision name="stem_right"', 'collision name="pad_left"')
    (tmp_path / "dup.urdf").write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = gm.load_model(tmp_path / "dup.urdf")
    said = [str(w.message) for w in caught]
    assert any("collision name 'pad_left' is given to 2 collisions (links finger_left, finger_right)" in s
               for s in said), said
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "pad_left") < 0
    # The material map names them by their links; the command prints the warning, not MuJoCo's.
    mats = {"box": {"youngs_modulus": 1.1e10, "poisson_ratio": 0.3}, "finger_left": "rigid", "finger_right": "rigid"}
    (tmp_path / "m.json").write_text(json.dumps(mats))
    proc = python_m("scene", tmp_path / "dup.urdf", "--object", "box", "--qpos", STATE, "--materials",
                    tmp_path / "m.json", "--out", tmp_path / "s.json", "--no-margin")
    assert proc.returncode == 0, proc.stderr
    assert "warning: URDF collision name 'pad_left'" in proc.stderr and "WARNING" not in proc.stdout
    assert os.path.exists(tmp_path / "s.json")
