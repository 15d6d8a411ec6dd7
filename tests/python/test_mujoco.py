"""grasp.mujoco: a grasp and a hand-off from MuJoCo, checked against MuJoCo's own
numbers.

Tolerances, and why:
- 1e-12 (relative) where this module copies MuJoCo's numbers (the weight ``body_mass |g|``,
  the centre of mass ``xipos``, a contact normal, ``mj_contactForce``'s normal force): only
  round-off separates them;
- 1e-8 of the weight for MuJoCo's unbalanced contact force against ``m a`` from MuJoCo's own
  accelerations (the sign and frame conventions of ``mj_contactForce``; they agree to MuJoCo's
  constraint solver tolerance, 1e-8: 1.5e-9 of the weight on the resting box);
- 1 % for the pinch's normal forces against the motor's commanded squeeze: MuJoCo's soft
  contact settles with the box tilted by a tenth of a degree and creeping, so its normal forces
  are 9.997 and 10.003 N for 10 N commanded (the issue's tolerance);
- float32 (1e-6 relative) for arrows read back from a Rerun recording.
"""

import csv
import io
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, ROOT, checker, numbers_close, rerun_cli

mujoco = checker("mujoco", reason="MuJoCo is not installed (scripts/install-checkers.sh installs mujoco==4.0.0)")
import grasp.mujoco as gm  # noqa: E402

MJ = EXAMPLES / "mujoco"
PINCH = MJ / "pinch.xml"
HANDOFF = MJ / "handoff.xml"
CONTROLLER = f"{MJ / 'handoff_controller.py'}:control"
ENV = {"CI": "1", "PATH": "/usr/bin:/bin"}


def python_m(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "grasp.mujoco", *map(str, args)], capture_output=True, text=True, cwd=cwd)


def rerun(*args):
    return subprocess.run([rerun_cli(), *map(str, args)], capture_output=True, text=True, env=ENV)


needs_rerun = pytest.mark.skipif(rerun_cli() is None, reason="the rerun CLI (scripts/install-checkers.sh) is not installed")


@pytest.fixture(scope="module")
def pinch():
    model = gm.load_model(PINCH)
    data = gm.load_state(model, keyframe="grasped")
    return model, data, gm.scene_from(model, data, "box", materials=MJ / "pinch.materials.json")


@pytest.fixture(scope="module")
def rollout():
    model = gm.load_model(HANDOFF)
    return model, gm.simulate(model, gm.load_state(model), CONTROLLER, steps=1600, every=10)


@pytest.fixture(scope="module")
def handoff(rollout):
    model, r = rollout
    return gm.schedule_from_rollout(model, r, "cylinder", materials=MJ / "handoff.materials.json")


def test_mujoco_contact_conventions_on_a_box_resting_on_the_floor():
    xml = """<mujoco><option cone="elliptic"/><worldbody><geom name="floor" type="plane" size="1 1 .1"/>
      <body name="box" pos="0 0 .05"><freejoint/><geom name="box" type="box" size=".05 .04 .05" density="500"/></body>
      </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for _ in range(500):
        mujoco.mj_step(model, data)
    g = gm.scene_from(model, data, "box", materials={"floor": "rigid", "box": {"youngs_modulus": 3e9, "poisson_ratio": 0.35}})
    assert g.finger_names == ["world"] and g.fingers[0].contact_count == 4
    f = g.scene_dict["fingers"][0]
    assert np.allclose(f["normal"], [0, 0, 1], atol=1e-12)  # from the floor into the box
    # MuJoCo's contact forces and weight leave exactly the box's m a unbalanced.
    assert np.abs(g.unbalanced_force_n - g.inertial_force_n).max() < 1e-8 * g.weight_n
    assert g.fingers[0].normal_force_n == pytest.approx(g.weight_n, rel=1e-6)
    # The contact point lies on the box's bottom face; the patch is the face (the four corners).
    bottom = data.geom_xpos[1][2] - 0.05
    assert f["contact_point"][2] == pytest.approx(bottom, abs=1e-9)
    assert sorted(f["patch"]["size"]) == pytest.approx([0.08, 0.1], abs=1e-12)
    assert "tip" not in f  # the floor is a plane: flat, no pad drawn
    assert grasp.solve(g.scene).status == "solved"


def test_mujoco_pinch_scene_has_two_fingers_at_the_pads_with_the_models_weight(pinch):
    model, data, g = pinch
    assert g.finger_names == ["jaw_left", "jaw_right"]
    assert [f.contact_count for f in g.fingers] == [4, 4]
    box = model.body("box").id
    obj = g.scene_dict["object"]
    assert obj["weight"] == pytest.approx(model.body_mass[box] * np.linalg.norm(model.opt.gravity), rel=1e-12)
    assert np.allclose(obj["center_of_mass"], data.xipos[box], rtol=0, atol=1e-12)
    assert obj["gravity"] == [0.0, 0.0, -1.0]
    assert obj["shape"]["box"]["size"] == pytest.approx((2 * model.geom("box").size).tolist(), rel=1e-15)
    for f, side in zip(g.scene_dict["fingers"], (1, -1)):
        pad = model.geom(f"pad_{f['name'].split('_')[1]}").id
        # The normal is MuJoCo's contact normal, turned into the object (the box is geom1).
        c = [data.contact[i] for i in range(data.ncon) if pad in (data.contact[i].geom1, data.contact[i].geom2)][0]
        frame_n = np.array(c.frame[:3]) * (-1 if c.geom1 == model.geom("box").id else 1)
        assert np.allclose(f["normal"], frame_n, rtol=0, atol=1e-12)
        # ... the pads' face normal (-y for the left pad, +y for the right) but for the box's tilt.
        tilt = math.degrees(math.acos(np.dot(f["normal"], [0, -side, 0])))
        assert tilt < 1.0
        # The contact point is the pad's face centre on the box's surface.
        rel = np.array(f["contact_point"]) - data.geom_xpos[pad]
        rot = data.geom_xmat[pad].reshape(3, 3)
        local = rot.T @ rel
        assert abs(local[0]) < 1e-9 and abs(local[2]) < 1e-4
        # ... inside the pad's face by at most MuJoCo's overlap (soft contacts overlap: 0.5 mm at
        # the fixed jaw, 1.3 mm at the light moving one, whose constraint is softer).
        overlap = max(-data.contact[i].dist for i in range(data.ncon) if pad in (data.contact[i].geom1, data.contact[i].geom2))
        assert 0 <= model.geom_size[pad][1] - abs(local[1]) <= overlap + 1e-12
        assert f["patch"]["size"] == pytest.approx([0.01, 0.01], abs=1e-5)
        assert f["tip"]["shape"]["box"]["size"] == pytest.approx([0.01, 0.005, 0.01], abs=1e-12)
        assert f["material"] == {"youngs_modulus": 2e6, "poisson_ratio": 0.45}
        assert f["friction"] == {"mu": 0.8}
    assert g.warnings == []


def test_mujoco_pinch_force_controlled_normals_equal_the_commanded_squeeze_and_both_hold(pinch):
    model, data, g = pinch
    squeeze = float(data.actuator_force[0])
    assert squeeze == 10.0
    report = gm.compare(g, margins=False)
    sol = report.solution
    assert sol.status == "solved" and report.grasp_holds and report.mujoco_holds
    mj = np.array([f.normal_force_n for f in g.fingers])
    assert np.allclose(sol.finger_normal_forces_n, mj, rtol=1e-12)
    assert np.all(np.abs(sol.finger_normal_forces_n / squeeze - 1) < 0.01)
    # Both carry the same load along the same normals: the friction totals agree.
    ours = np.sum([f["tangential_force_n"] for f in sol.fingers], axis=0)
    theirs = np.sum([f.friction_force_n for f in g.fingers], axis=0)
    assert np.abs(ours - theirs).max() < 1e-8
    assert report.mujoco_slip_speed_m_per_s < 1e-3  # MuJoCo creeps (0.2 mm/s at impratio 10)
    # Position-held, the energy model squeezes less than MuJoCo's motor: still a grasp.
    held = gm.compare(gm.scene_from(model, data, "box", materials=MJ / "pinch.materials.json", control="held"),
                      margins=False)
    assert held.solution.status == "solved"
    assert np.all(held.solution.finger_normal_forces_n < 0.5 * squeeze)
    assert held.grasp.scene_dict["fingers"][0]["control"] == "held"


def test_mujoco_pinch_report_matches_the_committed_one(pinch):
    _, _, g = pinch
    report = gm.compare(g)
    d = report.to_dict()
    committed = json.loads((MJ / "pinch.report.json").read_text())
    assert d["smallest_margin_n"] > 1.0
    for ours, theirs in zip(d["fingers"], committed["fingers"]):
        for side in ("mujoco", "grasp"):
            for k in ("normal_force_n", "friction_magnitude_n", "tangential_magnitude_n", "stick_count"):
                if k in theirs[side]:
                    assert ours[side][k] == pytest.approx(theirs[side][k], rel=1e-6, abs=1e-12), (side, k)
    assert d["smallest_margin_n"] == pytest.approx(committed["smallest_margin_n"], rel=1e-6)
    table = report.table()
    assert "jaw_left" in table and "jaw_right" in table and "MuJoCo holds" in table
    assert report.table(markdown=True).startswith("| finger |")


@needs_rerun
def test_mujoco_report_recording_shows_both_force_sets_as_arrows(pinch, tmp_path):
    _, _, g = pinch
    rrd, js = tmp_path / "pinch.rrd", tmp_path / "pinch.json"
    gm.compare(g, margins=False).write(json_path=js, rrd=rrd)
    assert rerun("rrd", "verify", rrd).returncode == 0
    out = rerun("rrd", "print", "-vvv", rrd).stdout
    # One recording (MuJoCo's layer took the project's recording id, grasp-transfer's
    # rerun_log.rs), opened on the project's layout.
    assert re.findall(r"StoreId\(\s*Recording,\s*\"grasp\",\s*\"([^\"]+)\"", out) == ["grasp-transfer"]
    assert "BlueprintActivationCommand" in out
    for name in g.finger_names:
        for part in ("normal", "friction"):
            assert f"/world/forces/{name}/{part} " in out  # this project's
            assert f"/world/mujoco/forces/{name}/{part} " in out  # MuJoCo's
    # MuJoCo's normal arrow: its normal force along its normal, at the project's scale.
    scale = gm._rerun.arrow_scale_m_per_n(g.scene)
    block = out[out.index("/world/mujoco/forces/jaw_left/normal -"):]
    vec = [float(x) for x in re.search(r"\[\[([-0-9.e, ]+)\]\]\s*│\s*│", block).group(1).split(",")]
    f = g.fingers[0]
    assert np.allclose(vec, f.normal * f.normal_force_n * scale, rtol=1e-6, atol=1e-9)
    assert json.loads(js.read_text())["holds"]["mujoco"] is True


def mujoco_normal_forces(model, r, body="cylinder"):
    """Per step and finger body, the sum of mj_contactForce's normal components (N), computed
    here independently of grasp.mujoco."""
    data = mujoco.MjData(model)
    b = model.body(body).id
    out = []
    f6 = np.zeros(6)
    for i in range(len(r)):
        r.apply(data, i)
        mujoco.mj_forward(model, data)
        row = {}
        for k in range(data.ncon):
            c = data.contact[k]
            if c.efc_address < 0:
                continue
            b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
            if b not in (b1, b2):
                continue
            other = model.body(b2 if b1 == b else b1).name
            mujoco.mj_contactForce(model, data, k, f6)
            row[other] = row.get(other, 0.0) + f6[0]
        out.append(row)
    return out


def read_profile(text):
    rows = list(csv.DictReader(io.StringIO(text)))
    return np.array([float(r["t_s"]) for r in rows]), rows


def test_mujoco_handoff_schedule_rows_equal_mujocos_normal_forces(rollout, handoff):
    model, r = rollout
    times, rows = read_profile(handoff.profile_csv)
    forces = mujoco_normal_forces(model, r)
    assert sum(1 for f in forces if any(v > 0 for v in f.values())) == len(rows)  # unloaded first state left out
    first = next(i for i, f in enumerate(forces) if any(v > 0 for v in f.values()))
    assert handoff.finger_names == ["a1", "a2", "b1", "b2"]
    # One state left out is named in the singular ("states 0 left out" read as none).
    if first == 1:
        assert any(w.startswith("state 0 left out: ") for w in handoff.warnings), handoff.warnings
    for j, row in enumerate(rows):
        assert float(row["t_s"]) == r.time[first + j]
        for name in handoff.finger_names:
            want = max(forces[first + j].get(name, 0.0), 0.0)
            assert float(row[f"{name}_n"]) == pytest.approx(want, rel=1e-12, abs=1e-12), (j, name)
    loads = handoff.normal_forces_n
    assert loads[0, 2:].max() == 0.0 and loads[0, :2].min() > 10  # A holds, B open
    assert loads[-1, :2].max() == 0.0 and loads[-1, 2:].min() > 14  # B holds, A open
    sched = handoff.schedule_dict
    assert sched["time"]["times"] == [float(t) for t in times]
    assert set(sched["fingers"]) == set(handoff.finger_names)


@needs_rerun
def test_mujoco_handoff_replays_end_to_end_and_its_files_pass_the_rerun_checks(handoff, tmp_path):
    files = {k: tmp_path / f"replay.{k}" for k in ("mcap", "rrd", "csv")}
    replay = handoff.replay(**files)
    run = replay.run
    assert len(run) == len(handoff.times_s)
    assert set(run.statuses) == {"solved"} and replay.flagged_steps == []
    # The replay commands exactly MuJoCo's normal forces (NaN: never; 0: released).
    commanded = np.nan_to_num(run.commanded_loads_n, nan=-1.0)
    assert np.allclose(commanded, handoff.normal_forces_n, rtol=1e-12, atol=1e-12)
    assert run.summary["receiving"] == ["b1", "b2"] and run.summary["releasing"] == ["a1", "a2"]
    assert rerun("rrd", "verify", files["rrd"]).returncode == 0
    proc = rerun("mcap", "check", files["mcap"])
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "/world/mujoco/forces/b1/normal" in rerun("rrd", "print", files["rrd"]).stdout
    text = replay.summary_text()
    assert "no step where MuJoCo held but the elastic model found no equilibrium" in text


def test_mujoco_rollout_file_gives_the_same_schedule(rollout, handoff, tmp_path):
    model, r = rollout
    path = tmp_path / "rollout.npz"
    r.save(path)
    again = gm.schedule_from_rollout(model, path, "cylinder", materials=MJ / "handoff.materials.json")
    assert again.profile_csv == handoff.profile_csv
    assert again.scene_dict == handoff.scene_dict


@needs_rerun
def test_mujoco_commands_write_what_grasp_solve_and_grasp_transfer_run(run_cli, rollout, tmp_path):
    proc = python_m("scene", PINCH, "--object", "box", "--keyframe", "grasped", "--materials", MJ / "pinch.materials.json",
                    "--out", tmp_path / "pinch.json", "--report", tmp_path / "pinch.report.json", "--no-margin")
    assert proc.returncode == 0, proc.stderr
    assert "jaw_left" in proc.stdout and "MuJoCo holds" in proc.stdout
    assert run_cli("solve", tmp_path / "pinch.json").returncode == 0
    model, r = rollout
    r.save(tmp_path / "rollout.npz")
    proc = python_m("handoff", HANDOFF, "--object", "cylinder", "--rollout", tmp_path / "rollout.npz",
                    "--materials", MJ / "handoff.materials.json", "--out", tmp_path / "h", "--no-replay")
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "h.csv", "h.json", "h.schedule.json", "pinch.json", "pinch.report.json", "rollout.npz"]
    mcap, rrd = tmp_path / "h.mcap", tmp_path / "h.rrd"
    proc = run_cli("transfer", tmp_path / "h.json", "--schedule", tmp_path / "h.schedule.json", "--mcap", mcap, "--rrd", rrd)
    assert proc.returncode == 0, proc.stderr
    assert rerun("rrd", "verify", rrd).returncode == 0 and rerun("mcap", "check", mcap).returncode == 0


def test_mujoco_committed_examples_are_what_the_commands_make(pinch, handoff):
    _, _, g = pinch
    committed = json.loads((MJ / "pinch.json").read_text())
    ours = dict(g.scene_dict, description=committed["description"])
    numbers_close(ours, committed)
    committed = json.loads((MJ / "handoff.json").read_text())
    numbers_close(handoff.scene_dict, committed)
    model = gm.load_model(MJ / "servo_pinch.xml")
    servo = gm.scene_from(model, gm.load_state(model, keyframe="grasped"), "box",
                          materials=MJ / "servo_pinch.materials.json", control="mujoco-servo")
    committed = json.loads((MJ / "servo_pinch.json").read_text())
    numbers_close(dict(servo.scene_dict, description=committed["description"]), committed)
    model = gm.load_model(MJ / "hinge_pinch.xml")
    hinge = gm.scene_from(model, gm.load_state(model, keyframe="grasped"), "box",
                          materials=MJ / "hinge_pinch.materials.json", control="mujoco-servo")
    committed = json.loads((MJ / "hinge_pinch.json").read_text())
    numbers_close(dict(hinge.scene_dict, description=committed["description"]), committed)
    model = gm.load_model(MJ / "coupled_pinch.xml")
    coupled = gm.scene_from(model, gm.load_state(model, keyframe="grasped"), "box",
                            materials=MJ / "coupled_pinch.materials.json", control="mujoco-servo")
    committed = json.loads((MJ / "coupled_pinch.json").read_text())
    numbers_close(dict(coupled.scene_dict, description=committed["description"]), committed)
    outs = handoff.outputs(str(MJ / "handoff"))
    numbers_close(json.loads(outs[str(MJ / "handoff.schedule.json")]),
                  json.loads((MJ / "handoff.schedule.json").read_text()))
    _, ours_rows = read_profile(handoff.profile_csv)
    _, their_rows = read_profile((MJ / "handoff.csv").read_text())
    numbers_close([{k: float(v) for k, v in r.items()} for r in ours_rows],
                  [{k: float(v) for k, v in r.items()} for r in their_rows])


def test_mujoco_gallery_pictures_are_regenerated_identically(run_cli, tmp_path):
    gallery = (EXAMPLES / "README.md").read_text()
    for name in ("pinch", "handoff"):
        assert f"docs/gallery/mujoco/{name}.svg" in gallery
        out = tmp_path / f"{name}.svg"
        proc = run_cli("plot", MJ / f"{name}.json", "--out", out)
        assert proc.returncode == 0 and ": solved;" in proc.stdout, proc.stderr
        assert out.read_bytes() == (ROOT / "docs" / "gallery" / "mujoco" / f"{name}.svg").read_bytes(), (
            f"{name}: the picture changed; run scripts/make-mujoco-examples.py and review it")


def test_mujoco_unnamed_geoms_get_the_default_material_with_a_warning(pinch):
    model, data, _ = pinch
    g = gm.scene_from(model, data, "box", materials={"box": "rigid"})
    assert g.warnings[0].startswith("no material in the map for 'pad_left', 'pad_right': using the default")
    assert g.scene_dict["fingers"][0]["material"] == gm.DEFAULT_MATERIAL
    assert g.scene_dict["object"]["material"] == "rigid"


def test_mujoco_material_map_may_give_pads_a_layer(pinch):
    """A material of the map may carry layer_thickness_m: the pad's scene material
    keeps it and the scene solves with the layered kernels; anything else stays refused."""
    model, data, _ = pinch
    pad = {"youngs_modulus": 1e6, "poisson_ratio": 0.45, "layer_thickness_m": 0.002}
    g = gm.scene_from(model, data, "box", materials={"box": "rigid", "pad_left": pad, "pad_right": pad})
    assert [f["material"] for f in g.scene_dict["fingers"]] == [pad, pad]
    assert grasp.solve(g.scene).status == "solved"
    with pytest.raises(gm.MaterialMapError):
        gm.scene_from(model, data, "box", materials={"box": "rigid", "pad_left": dict(pad, thickness=1)})


def test_mujoco_a_sphere_tip_on_a_cylinder_gets_hertz_patch_and_radii(rollout):
    model, r = rollout
    data = mujoco.MjData(model)
    r.apply(data, 20)
    g = gm.scene_from(model, data, "cylinder", materials=MJ / "handoff.materials.json", control="held")
    f = g.scene_dict["fingers"][0]
    p = g.fingers[0].normal_force_n
    assert f["name"] == "a1" and f["tip"] == {"sphere": {"radius": 0.015}}
    assert f["object_radius"] == [0.025, None]  # across the axis, straight along it (t2)
    assert abs(np.dot(f["tangent"], [0, 0, 1])) < 1e-9  # t1 around the cylinder, t2 along its axis
    # 2.4 semi-axes of the Hertz ellipse (Johnson 4.2, equivalent radius) at MuJoCo's force.
    e_star = 1 / ((1 - 0.45**2) / 2e6 + (1 - 0.35**2) / 3e9)
    r1, r2 = 1 / (1 / 0.015 + 1 / 0.025), 0.015
    c = (3 * p * math.sqrt(r1 * r2) / (4 * e_star)) ** (1 / 3)
    assert f["patch"]["size"] == pytest.approx([2.4 * c * (r1 / r2) ** (1 / 3), 2.4 * c * (r2 / r1) ** (1 / 3)], rel=1e-12)
    assert grasp.solve(g.scene).status == "solved"


def test_mujoco_a_mesh_object_is_written_beside_the_scene(tmp_path):
    verts = " ".join(f"{x} {y} {z}" for x in (-0.03, 0.03) for y in (-0.02, 0.02) for z in (-0.05, 0.05))
    xml = f"""<mujoco><option cone="elliptic"/><asset><mesh name="m" vertex="{verts}"/></asset><worldbody>
      <geom name="floor" type="plane" size="1 1 .1"/>
      <body name="block" pos="0 0 .05"><freejoint/><geom name="block" type="mesh" mesh="m" density="700"/></body>
      </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for _ in range(300):
        mujoco.mj_step(model, data)
    g = gm.scene_from(model, data, "block", materials={"floor": "rigid"}, mesh_name="block.obj")
    assert g.scene_dict["object"]["shape"]["mesh"] == {"file": "block.obj"}
    written = g.write(tmp_path / "block.json")
    assert sorted(os.path.basename(p) for p in written) == ["block.json", "block.obj"]
    scene = grasp.Scene(tmp_path / "block.json")
    assert scene.shape_report["volume_m3"] == pytest.approx(0.06 * 0.04 * 0.1, rel=1e-6)  # MuJoCo keeps float32 vertices
    assert any("mesh" in w for w in g.warnings)



# Box, cylinder and capsule fingertips as the solids MuJoCo poses.

RUBBER = {"youngs_modulus": 2e6, "poisson_ratio": 0.45}


def settled(xml, steps=300):
    """The model of ``xml`` and its state after ``steps`` steps of 2 ms."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    return model, data


def ball_on(tip_geom, ball_at):
    """A steel ball (radius 10 mm, 8000 kg/m^3) resting on the fixed fingertip geom ``tip_geom``
    (named "tip", in body "tip"), dropped from ``ball_at`` and settled for 0.3 s."""
    return settled(f"""<mujoco><option cone="elliptic" impratio="10"/><worldbody>
      <body name="tip">{tip_geom}</body>
      <body name="ball" pos="{ball_at}"><freejoint/><geom name="ball" type="sphere" size=".01" density="8000"/></body>
      </worldbody></mujoco>""")


def pose_matrix(shape):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.array(shape["quaternion"], dtype=float))
    return m.reshape(3, 3)


def mujoco_overlaps(model, data, geom):
    """MuJoCo's overlaps (-contact.dist, m) at the contacts of ``geom``."""
    return [-data.contact[i].dist for i in range(data.ncon) if geom in (data.contact[i].geom1, data.contact[i].geom2)]


def test_mujoco_a_box_pad_is_the_posed_box_and_carries_nothing_past_its_edge():
    """A box fingertip is the scene's ``tip.shape``: the box as MuJoCo poses it, moved out of
    the object along the normal by MuJoCo's overlap (it was a flat pad of the box's size centred
    on MuJoCo's point, with no edge where the real one is). A steel ball rests on a 10 x 10 mm
    rubber pad (turned 30 degrees about its normal) 0.5 mm in from the pad's edge: its Hertz
    patch (2.4 semi-axes, 2.4 mm) reaches 0.7 mm past the edge. The elements past the edge are
    off the surface, exactly those whose centres lie outside the pad's footprint (from MuJoCo's
    pose of the pad, not from the scene), and the solved contact lies within the footprint."""
    turn = math.radians(30)
    rot_z = np.array([[math.cos(turn), -math.sin(turn), 0], [math.sin(turn), math.cos(turn), 0], [0, 0, 1]])
    centre = np.array([0.01, 0.02, 0.0])
    ball = centre + rot_z @ [0.0045, 0.0, 0.0] + [0, 0, 0.0125]
    model, data = ball_on(f'<geom name="tip" type="box" size=".005 .005 .0025" pos="{" ".join(map(str, centre))}" '
                          'euler="0 0 30"/>', " ".join(map(str, ball)))
    pad = model.geom("tip").id
    g = gm.scene_from(model, data, "ball", materials={"ball": "rigid", "tip": RUBBER})
    assert g.warnings == []
    f = g.scene_dict["fingers"][0]
    n = np.array(f["normal"])
    assert np.allclose(n, [0, 0, 1], atol=1e-9)
    # The tip: the box, its size and orientation MuJoCo's, moved by MuJoCo's overlap along n.
    shape = f["tip"]["shape"]
    assert set(f["tip"]) == {"shape"} and set(shape) == {"box", "position", "quaternion"}
    assert shape["box"]["size"] == pytest.approx((2 * model.geom_size[pad]).tolist(), rel=1e-15)
    assert np.allclose(pose_matrix(shape), data.geom_xmat[pad].reshape(3, 3), rtol=0, atol=1e-12)
    [overlap] = mujoco_overlaps(model, data, pad)
    assert 1e-4 < overlap < 1e-3
    assert np.allclose(shape["position"], data.geom_xpos[pad] - overlap * n, rtol=0, atol=1e-12)
    # Solved: the elements past the pad's real edge carry nothing.
    sol = grasp.solve(g.scene)
    assert sol.status == "solved"
    assert sol.finger_normal_forces_n[0] == pytest.approx(g.fingers[0].normal_force_n, rel=1e-9)
    rot = data.geom_xmat[pad].reshape(3, 3)
    local = (sol.positions_m - data.geom_xpos[pad]) @ rot  # element centres in the pad's frame
    half = model.geom_size[pad][:2]
    outside = np.any(np.abs(local[:, :2]) > half, axis=1)
    assert outside.sum() >= 9  # at least a column of the 9 x 9 patch
    assert np.array_equal(sol.states == "off_surface", outside)
    # The contact reaches the edge and stops there.
    loaded = sol.normal_forces_n > 0
    element = f["patch"]["size"][0] / 9
    assert np.all(np.abs(local[loaded, :2]) <= half)
    assert local[loaded, 0].max() > half[0] - element


def test_mujoco_box_pads_are_moved_out_of_mujocos_overlap_which_changes_no_gap(pinch):
    """MuJoCo's soft contacts let the pinch's pads overlap the box by 0.48 mm (fixed jaw) and
    1.30 mm (the moving jaw) at the contact point: more than the 5 % of the patch's half diagonal
    (0.35 mm) by which a ``tip.shape`` may miss it. The pads are moved back along the normal by
    their overlap: the pads as MuJoCo poses them are refused, the moved ones touch the box at the
    contact point, and moving them further along the normal changes no gap (the tip's heights
    are measured from its height at the contact point): the same solution to round-off."""
    import copy

    model, data, g = pinch
    moved = []
    for f in g.scene_dict["fingers"]:
        pad = model.geom(f"pad_{f['name'].split('_')[1]}").id
        shape, n = f["tip"]["shape"], np.array(f["normal"])
        assert shape["box"]["size"] == pytest.approx((2 * model.geom_size[pad]).tolist(), rel=1e-15)
        assert np.allclose(pose_matrix(shape), data.geom_xmat[pad].reshape(3, 3), rtol=0, atol=1e-12)
        d = data.geom_xpos[pad] - np.array(shape["position"])
        assert np.allclose(d, (d @ n) * n, rtol=0, atol=1e-15)  # along the normal, into the object
        overlaps = mujoco_overlaps(model, data, pad)
        assert min(overlaps) - 1e-12 <= d @ n <= max(overlaps) + 1e-12
        moved.append(float(d @ n))
        # The moved pad's face (its side facing the box) passes through the contact point.
        local = pose_matrix(shape).T @ (np.array(f["contact_point"]) - shape["position"])
        assert abs(abs(local[1]) - model.geom_size[pad][1]) < 1e-12
    assert moved == pytest.approx([4.82e-4, 1.298e-3], rel=2e-3)
    half_diagonal = 0.5 * math.hypot(*g.scene_dict["fingers"][0]["patch"]["size"])
    assert min(moved) > 0.05 * half_diagonal
    as_posed = copy.deepcopy(g.scene_dict)
    further = copy.deepcopy(g.scene_dict)
    for a, b, f in zip(as_posed["fingers"], further["fingers"], g.scene_dict["fingers"]):
        pad = model.geom(f"pad_{f['name'].split('_')[1]}").id
        a["tip"]["shape"]["position"] = data.geom_xpos[pad].tolist()
        b["tip"]["shape"]["position"] = (np.array(f["tip"]["shape"]["position"])
                                         - 0.02 * half_diagonal * np.array(f["normal"])).tolist()
    with pytest.raises(ValueError, match=r"fingers\[1\]\.tip\.shape: lies 1\.29\de-3 m from the contact point"):
        grasp.Scene(as_posed)
    ours, theirs = grasp.solve(g.scene), grasp.solve(grasp.Scene(further))
    assert ours.status == theirs.status == "solved"
    assert np.allclose(theirs.normal_forces_n, ours.normal_forces_n, rtol=1e-9, atol=1e-12)
    assert np.allclose(theirs.tangential_forces_n, ours.tangential_forces_n, rtol=1e-9, atol=1e-12)


def test_mujoco_without_the_objects_shape_a_box_pad_stays_a_flat_pad(pinch):
    """Without exact gaps (an object of two geoms has no shape, so its gaps are quadratic) a
    ``tip.shape`` would be refused: the box pad stays ``tip.flat``, the box's size."""
    text = PINCH.read_text().replace(
        '<geom name="box" type="box" size="0.03 0.02 0.05"',
        '<geom name="box_low" type="box" pos="0 0 -0.03" size="0.03 0.02 0.02" density="700"/>'
        '<geom name="box" type="box" pos="0 0 0.02" size="0.03 0.02 0.03"')
    model = mujoco.MjModel.from_xml_string(text)
    data = gm.load_state(model, keyframe="grasped")
    g = gm.scene_from(model, data, "box", materials=MJ / "pinch.materials.json")
    assert "shape" not in g.scene_dict["object"]
    assert any("2 collision geoms" in w for w in g.warnings)
    for f in g.scene_dict["fingers"]:
        assert f["tip"] == {"flat": {"size": pytest.approx([0.01, 0.01], rel=2e-3)}}
    assert grasp.solve(g.scene).status == "solved"


def test_mujoco_cylinder_and_capsule_tips_are_posed_solids():
    """A cylinder and a capsule fingertip are ``tip.shape`` too: a ball on a cylinder's flat
    end 0.5 mm in from its rim (it had no tip: an unbounded flat) carries nothing past the rim;
    a ball on a capsule's side, next to its round end (it was an infinite cylinder), solves on
    the capsule as MuJoCo poses it."""
    model, data = ball_on('<geom name="tip" type="cylinder" size=".005 .01" pos="0 0 -.01"/>', ".0045 0 .0101")
    tip = model.geom("tip").id
    g = gm.scene_from(model, data, "ball", materials={"ball": "rigid", "tip": RUBBER})
    f = g.scene_dict["fingers"][0]
    shape = f["tip"]["shape"]
    assert shape["cylinder"] == {"radius": 0.005, "length": 0.02}
    assert np.allclose(pose_matrix(shape), data.geom_xmat[tip].reshape(3, 3), rtol=0, atol=1e-12)
    [overlap] = mujoco_overlaps(model, data, tip)
    assert np.allclose(shape["position"], data.geom_xpos[tip] - overlap * np.array(f["normal"]), rtol=0, atol=1e-12)
    sol = grasp.solve(g.scene)
    assert sol.status == "solved"
    radial = np.linalg.norm((sol.positions_m - data.geom_xpos[tip])[:, :2], axis=1)
    assert np.array_equal(sol.states == "off_surface", radial > 0.005)
    assert 9 <= np.sum(radial > 0.005) and np.all(radial[sol.normal_forces_n > 0] <= 0.005)
    # A capsule (radius 5 mm, 20 mm between its end centres) along x; the ball on its side
    # 1 mm before the round end begins.
    model, data = ball_on('<geom name="tip" type="capsule" size=".005 .01" euler="0 90 0"/>', ".009 0 .0151")
    tip = model.geom("tip").id
    g = gm.scene_from(model, data, "ball", materials={"ball": "rigid", "tip": RUBBER})
    f = g.scene_dict["fingers"][0]
    shape = f["tip"]["shape"]
    assert shape["capsule"] == {"radius": 0.005, "length": 0.02}
    assert np.allclose(pose_matrix(shape), data.geom_xmat[tip].reshape(3, 3), rtol=0, atol=1e-12)
    [overlap] = mujoco_overlaps(model, data, tip)
    assert np.allclose(shape["position"], data.geom_xpos[tip] - overlap * np.array(f["normal"]), rtol=0, atol=1e-12)
    assert grasp.solve(g.scene).status == "solved"


def test_mujoco_handoff_box_pads_are_posed_in_the_scenes_frame():
    """In a hand-off each finger is placed where it carried its largest load, moved with the
    object to its first pose: its ``tip.shape`` moves with it, so the pad sits on the object as
    MuJoCo had it at that step (the pinch's box drops and turns while MuJoCo's contact settles)."""
    model = gm.load_model(PINCH)

    def squeeze(model, data):
        data.ctrl[0] = 10.0

    r = gm.simulate(model, gm.load_state(model, keyframe="start"), squeeze, steps=400, every=20)
    h = gm.schedule_from_rollout(model, r, "box", materials=MJ / "pinch.materials.json")
    obj = h.scene_dict["object"]["shape"]
    obj_rot = pose_matrix(obj)
    data = mujoco.MjData(model)
    box = model.geom("box").id
    turned = 0.0
    for j, f in enumerate(h.scene_dict["fingers"]):
        i = int(np.argmax(h.normal_forces_n[:, j]))
        r.apply(data, int(np.flatnonzero(r.time == h.times_s[i])[0]))
        mujoco.mj_forward(model, data)
        pad = model.geom(f"pad_{f['name'].split('_')[1]}").id
        box_rot = data.geom_xmat[box].reshape(3, 3)
        shape = f["tip"]["shape"]
        # The pad's orientation and place relative to the box: MuJoCo's at that step (its place
        # but for the move out of the overlap, along the normal).
        assert np.allclose(obj_rot.T @ pose_matrix(shape), box_rot.T @ data.geom_xmat[pad].reshape(3, 3), atol=1e-12)
        ours = obj_rot.T @ (np.array(shape["position"]) - obj["position"])
        theirs = box_rot.T @ (data.geom_xpos[pad] - data.geom_xpos[box])
        n_box = obj_rot.T @ np.array(f["normal"])
        d = theirs - ours
        assert np.allclose(d, (d @ n_box) * n_box, rtol=0, atol=1e-12) and 0 < d @ n_box < 2e-3
        turned = max(turned, float(np.abs(box_rot - obj_rot).max()))
    assert turned > 1e-4  # the box did turn between the first state and the fingers' steps
    assert h.scene.finger_names == ["jaw_left", "jaw_right"]

# Bad input: a named error, nothing written.


def no_files(folder):
    return sorted(p.name for p in folder.iterdir()) == []


def test_mujoco_an_object_with_no_contacts_is_a_named_error(tmp_path):
    xml = """<mujoco><worldbody><geom type="plane" size="1 1 .1"/>
      <body name="ball" pos="0 0 1"><freejoint/><geom type="sphere" size=".1"/></body></worldbody></mujoco>"""
    (tmp_path / "m.xml").write_text(xml)
    model = gm.load_model(tmp_path / "m.xml")
    with pytest.raises(gm.NoContactError, match="body 'ball' has no active contact"):
        gm.scene_from(model, gm.load_state(model), "ball")
    out = tmp_path / "out"
    out.mkdir()
    proc = python_m("scene", tmp_path / "m.xml", "--object", "ball", "--out", out / "s.json", "--report", out / "r.json")
    assert proc.returncode == 1 and "has no active contact" in proc.stderr and no_files(out)
    (tmp_path / "idle.py").write_text("def idle(model, data):\n    pass\n")
    proc = python_m("handoff", tmp_path / "m.xml", "--object", "ball", "--controller", f"{tmp_path / 'idle.py'}:idle",
                    "--steps", "3", "--out", out / "h")
    assert proc.returncode == 1 and "held by no contact" in proc.stderr and no_files(out), proc.stderr


def test_mujoco_a_box_pad_touching_by_its_edge_is_a_contact_geometry_error(tmp_path):
    """A box fingertip whose edge touches the object (a pad turned 45 degrees under a block)
    has no face towards the object at MuJoCo's contact: the elastic model's small slopes do not
    hold there, and the scene would refuse the posed tip. A ContactGeometryError says so (it was
    a flat pad, face to face), exit 1 and nothing written."""
    xml = """<mujoco><worldbody>
      <body name="tip"><geom name="tip" type="box" size=".005 .005 .005" euler="0 45 0"/></body>
      <body name="block" pos="0 0 .01697"><freejoint/><geom name="block" type="box" size=".01 .01 .01" density="700"/></body>
      </worldbody></mujoco>"""
    (tmp_path / "m.xml").write_text(xml)
    model = gm.load_model(tmp_path / "m.xml")
    words = ("finger tip: the fingertip box tip faces 45.0 degrees away from MuJoCo's contact normal where it meets "
             "the object (at most 16.7: its edge or corner touches the object")
    with pytest.raises(gm.ContactGeometryError, match=re.escape(words)):
        gm.scene_from(model, gm.load_state(model), "block", materials={"block": "rigid"})
    out = tmp_path / "out"
    out.mkdir()
    proc = python_m("scene", tmp_path / "m.xml", "--object", "block", "--out", out / "s.json")
    assert proc.returncode == 1 and f"error: {words}" in proc.stderr and no_files(out), proc.stderr

def test_mujoco_unknown_body_and_unknown_names_in_the_material_map_are_named_errors(pinch, tmp_path):
    model, data, _ = pinch
    with pytest.raises(gm.UnknownBodyError, match="no body 'bx'.*box, jaw_left, jaw_right"):
        gm.scene_from(model, data, "bx")
    with pytest.raises(gm.MaterialMapError, match="'pad_lft' \\(did you mean 'pad_left'\\?\\)"):
        gm.scene_from(model, data, "box", materials={"pad_lft": "rigid"})
    with pytest.raises(gm.MaterialMapError, match="material of 'box'"):
        gm.scene_from(model, data, "box", materials={"box": {"youngs_modulus": "hard"}})
    (tmp_path / "map.json").write_text('{"pad_lft": "rigid"}')
    proc = python_m("scene", PINCH, "--object", "box", "--keyframe", "grasped", "--materials", tmp_path / "map.json",
                    "--out", tmp_path / "s.json")
    assert proc.returncode == 1 and "did you mean 'pad_left'" in proc.stderr
    proc = python_m("scene", PINCH, "--object", "bx", "--keyframe", "grasped", "--out", tmp_path / "s.json")
    assert proc.returncode == 1 and "no body 'bx'" in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.json"]


def test_mujoco_material_maps_with_duplicates_non_finite_or_huge_numbers_are_named_errors(pinch, tmp_path):
    # Duplicate keys were accepted (the last won), "layer_thickness_m": null refused,
    # and a 5,000-digit integer leaked Python's own 4,300-digit error.
    model, data, _ = pinch
    cases = [
        ('{"box": "rigid", "box": {"youngs_modulus": 1e9, "poisson_ratio": 0.3}}', "gives 'box' twice"),
        ('{"box": {"youngs_modulus": NaN, "poisson_ratio": 0.3}}', "has NaN"),
        ('{"box": {"youngs_modulus": 1e400, "poisson_ratio": 0.3}}', "material of 'box'"),
        ('{"box": {"youngs_modulus": 1' + "0" * 5000 + ', "poisson_ratio": 0.3}}', "integer of 5001 digits"),
    ]
    for text, words in cases:
        path = tmp_path / "map.json"
        path.write_text(text)
        with pytest.raises(gm.MaterialMapError, match=words) as e:
            gm.scene_from(model, data, "box", materials=path)
        assert len(str(e.value)) < 600, str(e.value)[:300]
    with pytest.raises(gm.MaterialMapError, match="material of 'box'"):
        gm.scene_from(model, data, "box", materials={"box": {"youngs_modulus": float("inf"), "poisson_ratio": 0.3}})
    layered = {"youngs_modulus": 2e6, "poisson_ratio": 0.45, "layer_thickness_m": None}
    g = gm.scene_from(model, data, "box", materials={"box": "rigid", "pad_left": layered, "pad_right": layered})
    assert [f["material"] for f in g.scene_dict["fingers"]] == [{"youngs_modulus": 2e6, "poisson_ratio": 0.45}] * 2


def test_mujoco_states_that_do_not_load_are_named_errors(rollout, tmp_path):
    model = gm.load_model(PINCH)
    with pytest.raises(gm.StateError, match="no keyframe 'nope'.*start, grasped"):
        gm.load_state(model, keyframe="nope")
    (tmp_path / "q.txt").write_text("0 0 0.05 1 0 0 0")
    with pytest.raises(gm.StateError, match="qpos has 7 numbers, the model needs 8"):
        gm.load_state(model, qpos=tmp_path / "q.txt")
    (tmp_path / "q.txt").write_text("0 0 nan 1 0 0 0 0")
    with pytest.raises(gm.StateError, match="NaN"):
        gm.load_state(model, qpos=tmp_path / "q.txt")
    (tmp_path / "bad.xml").write_text("<mujoco><worldbody><body><geom type='box'/></body></worldbody></mujoco>")
    with pytest.raises(gm.ModelLoadError, match="MuJoCo cannot load"):
        gm.load_model(tmp_path / "bad.xml")
    hmodel, r = rollout
    with pytest.raises(gm.StateError, match="'qpos' has shape"):
        gm.schedule_from_rollout(hmodel, {"time": r.time, "qpos": r.qpos[:, :5], "qvel": r.qvel}, "cylinder")
    with pytest.raises(gm.StateError, match="strictly increasing"):
        gm.schedule_from_rollout(hmodel, {"time": r.time[::-1], "qpos": r.qpos, "qvel": r.qvel}, "cylinder")
    with pytest.raises(gm.ControllerError, match="cannot import"):
        gm.simulate(hmodel, gm.load_state(hmodel), str(tmp_path / "nope.py") + ":control", steps=2)
    out = tmp_path / "out"
    out.mkdir()
    for args in (["--keyframe", "nope"], ["--qpos", tmp_path / "q.txt"]):
        proc = python_m("scene", PINCH, "--object", "box", *args, "--out", out / "s.json")
        assert proc.returncode == 1 and proc.stderr.startswith("error: "), proc.stderr
    proc = python_m("scene", tmp_path / "bad.xml", "--object", "box", "--out", out / "s.json")
    assert proc.returncode == 1 and "MuJoCo cannot load" in proc.stderr
    assert no_files(out)


def test_mujoco_existing_outputs_are_kept_without_force(tmp_path):
    target = tmp_path / "s.json"
    target.write_text("mine\n")
    args = ["scene", PINCH, "--object", "box", "--keyframe", "grasped", "--out", target, "--no-margin"]
    proc = python_m(*args)
    assert proc.returncode == 1 and "--force" in proc.stderr and target.read_text() == "mine\n"
    assert python_m(*args, "--force").returncode == 0
    assert json.loads(target.read_text())["fingers"][0]["name"] == "jaw_left"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.json"]  # no temporary left
    proc = python_m("scene", PINCH, "--object", "box", "--out", tmp_path / "t.json", "--colour", "red")
    assert proc.returncode == 1 and "unrecognized arguments: --colour red" in proc.stderr  # usage errors exit 1


def test_mujoco_a_state_file_gives_the_keyframes_scene(pinch, tmp_path):
    model, data, g = pinch
    np.savez(tmp_path / "state.npz", qpos=data.qpos, qvel=data.qvel, ctrl=data.ctrl, time=[data.time])
    again = gm.scene_from(model, gm.load_state(model, qpos=tmp_path / "state.npz"), "box",
                          materials=MJ / "pinch.materials.json")
    assert again.scene_dict == g.scene_dict
    proc = python_m("scene", PINCH, "--object", "box", "--qpos", tmp_path / "state.npz", "--materials",
                    MJ / "pinch.materials.json", "--out", tmp_path / "s.json", "--no-margin")
    assert proc.returncode == 0, proc.stderr
    assert json.loads((tmp_path / "s.json").read_text())["fingers"] == g.scene_dict["fingers"]


def test_mujoco_guide_chapter_shows_the_commands_and_the_pinch_table(pinch):
    section = (ROOT / "docs" / "guide" / "mujoco.md").read_text()
    assert "python -m grasp.mujoco scene examples/mujoco/pinch.xml" in section
    assert "python -m grasp.mujoco handoff examples/mujoco/handoff.xml" in section
    _, _, g = pinch
    table = [line for line in gm.compare(g, margins=False).table(markdown=True).splitlines() if line.startswith("|")]
    shown = [line for line in section.splitlines() if line.startswith("| finger |")]
    assert shown, "the section has no side-by-side table"
    start = section.splitlines().index(shown[0])
    assert section.splitlines()[start:start + len(table)] == table


def test_mujoco_handoff_flags_held_steps_the_elastic_model_cannot_hold(handoff):
    # The flagging rule on a made-up replay of the real hand-off: every step MuJoCo held is
    # flagged where the elastic model found no equilibrium or a margin below the threshold, and
    # no step MuJoCo did not hold is (the full replay with margins takes over a minute: the
    # guide's run (docs/guide/mujoco.md) flags t = 1.4-1.6 s; here the rule itself is what is checked).
    from types import SimpleNamespace

    n = len(handoff.times_s)
    held = [i for i in range(n) if handoff.mujoco_held[i]]
    dropped = [i for i in range(n) if not handoff.mujoco_held[i]]
    assert len(held) >= 3
    statuses = ["solved"] * n
    margins = [5.0] * n
    statuses[held[0]] = "infeasible"
    margins[held[1]] = 0.5
    margins[held[2]] = float("nan")  # no margin computed at that step: never flagged
    for i in dropped:
        statuses[i], margins[i] = "infeasible", 0.0
    run = SimpleNamespace(statuses=statuses, smallest_margins_n=margins)
    flagged = gm.HandoffReplay(handoff, run, threshold_n=1.0).flagged_steps
    assert [(i, why) for i, _, why in flagged] == [(held[0], "infeasible"), (held[1], "margin 0.5 N")]
    assert flagged[0][1] == float(handoff.times_s[held[0]])
    # Without a threshold only the step with no equilibrium is flagged.
    unthresholded = gm.HandoffReplay(handoff, run, threshold_n=None).flagged_steps
    assert [i for i, _, _ in unthresholded] == [held[0]]


def test_mujoco_a_controller_that_exits_or_raises_is_a_controller_error(tmp_path):
    """Item 2 of the hostile review: a controller's sys.exit (at a step, or when its module is
    imported) is a ControllerError naming the controller, exit 1 and nothing written, as any
    exception of the controller; Ctrl-C (KeyboardInterrupt) still interrupts."""
    cases = [  # (module text, words of the error after the controller's name)
        ("import sys\ndef control(model, data):\n    sys.exit(0)\n", "called sys.exit(0) at step 0 (t = 0 s)"),
        ("import sys\ndef control(model, data):\n    if data.time > 0.0015:\n        sys.exit('done')\n",
         "called sys.exit('done') at step 2 (t = 0.002 s)"),
        ("def control(model, data):\n    raise SystemExit\n", "called sys.exit(None) at step 0"),
        ("class Stop(BaseException):\n    pass\ndef control(model, data):\n    raise Stop('odd')\n",
         "failed at step 0 (t = 0 s): Stop('odd')"),
        ("def control(model, data):\n    raise RuntimeError('boom')\n", "failed at step 0 (t = 0 s): RuntimeError('boom')"),
        ("import sys\nsys.exit(3)\ndef control(model, data):\n    pass\n", "called sys.exit(3) while its module was imported"),
    ]
    model = gm.load_model(HANDOFF)
    out = tmp_path / "out"
    out.mkdir()
    for i, (text, words) in enumerate(cases):
        path = tmp_path / f"c{i}.py"
        path.write_text(text)
        spec = f"{path}:control"
        with pytest.raises(gm.ControllerError, match=re.escape(f"the controller {spec} {words}")):
            gm.simulate(model, gm.load_state(model), spec, steps=5)
        proc = python_m("handoff", HANDOFF, "--object", "cylinder", "--controller", spec, "--steps", "5",
                        "--out", out / "h", "--save-rollout", out / "r.npz")
        assert proc.returncode == 1, (spec, proc.returncode, proc.stderr)
        assert f"error: the controller {spec} {words}" in proc.stderr and "; fix: " in proc.stderr, proc.stderr
        assert list(out.iterdir()) == []

    def interrupt(model, data):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        gm.simulate(model, gm.load_state(model), interrupt, steps=5)


def test_mujoco_count_arguments_are_range_checked_before_the_run(rollout, tmp_path):
    """Item 3 of the hostile review: steps, every, the patch grid, the margin threshold and a
    rollout's states are range-checked, naming the argument (and its option) and the range,
    before MuJoCo or the replay runs (--steps had no bound; a rollout grew 0.5 MB/s)."""
    model, r = rollout
    idle = lambda model, data: None  # noqa: E731
    api = [
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=0), "steps (--steps) is 0, not a whole number "
         "from 1 to 1000000; fix: give a whole number from 1 to 1000000"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=10**10), "steps (--steps) is 10000000000"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=2.5), "steps (--steps) is 2.5"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=True), "steps (--steps) is True"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=10, every=0), "every (--every) is 0"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=10, every=10**7), "every (--every) is 10000000"),
        (lambda: gm.simulate(model, gm.load_state(model), idle, steps=10**6), "give 1000001 states of this model "
         "(275 MiB), more than a rollout may have (1000000 states, 1024 MiB); fix: record fewer states"),
        (lambda: gm.schedule_from_rollout(model, r, "cylinder", patch={"grid": [3000, 3000]}),
         "patch grid (--grid) is 3000 x 3000: 9000000 elements per finger, more than the 4194304 (2048 x 2048)"),
        (lambda: gm.schedule_from_rollout(model, r, "cylinder", patch={"grid": [0, 9]}), "patch grid[0] (--grid) is 0"),
        (lambda: gm.schedule_from_rollout(model, {"time": np.arange(1_000_001.0),
                                                  "qpos": np.broadcast_to(r.qpos[0], (1_000_001, model.nq)),
                                                  "qvel": np.broadcast_to(r.qvel[0], (1_000_001, model.nv))}, "cylinder"),
         "rollout: 1000001 states, more than the 1000000 a schedule may have"),
        (lambda: gm.schedule_from_rollout(model, r, "cylinder").replay(threshold_n=float("nan")),
         "threshold_n (--threshold) is nan, not a finite number from 0 to 1e+07 N"),
    ]
    for call, words in api:
        with pytest.raises(gm.MujocoError, match=re.escape(words)):
            call()
    out = tmp_path / "out"
    out.mkdir()
    base = ["handoff", HANDOFF, "--object", "cylinder", "--controller", CONTROLLER, "--materials",
            MJ / "handoff.materials.json", "--out", out / "h"]
    cli = [(["--steps", "0"], "steps (--steps) is 0"), (["--steps", "10000000000"], "steps (--steps) is 10000000000"),
           (["--steps", "10", "--every", "0"], "every (--every) is 0"),
           (["--steps", "10", "--grid", "3000", "3000"], "patch grid (--grid) is 3000 x 3000"),
           (["--steps", "10", "--threshold", "-1"], "threshold_n (--threshold) is -1.0")]
    for args, words in cli:
        proc = subprocess.run([sys.executable, "-m", "grasp.mujoco", *map(str, base + args)], capture_output=True,
                              text=True, cwd=ROOT, timeout=60)
        assert proc.returncode == 1 and f"error: {words}" in proc.stderr, (args, proc.stderr)
        assert list(out.iterdir()) == []


def test_mujoco_an_object_body_that_is_not_free_or_has_no_mass_is_refused(pinch, rollout, tmp_path):
    """Items 4 and 7 of the hostile review: the world (by name or id: one wording), a body fixed
    or welded to another, on a slide joint, a mocap body, or a free body without mass is not
    taken as the grasped object (a fixed jaw's contacts carry the world's reaction, which was
    written as an external force); the error names the body and the bodies that can be."""
    model, data, _ = pinch
    xml = """<mujoco><worldbody><geom type="plane" size="1 1 .1"/>
      <body name="hand" mocap="true" pos="0 0 .5"><geom type="box" size=".01 .01 .01"/></body>
      <body name="frame" pos="0 0 .2"><freejoint/><body name="part"><geom type="box" size=".05 .05 .05" mass="1"/></body>
      </body><body name="ball" pos="0 .5 .1"><freejoint/><geom type="sphere" size=".1"/></body></worldbody></mujoco>"""
    other = mujoco.MjModel.from_xml_string(xml)
    hmodel, r = rollout
    pinch_fix = "fix: give the grasped object's body, one with a free joint (<freejoint/>) and a mass: box"
    cases = [
        (lambda: gm.scene_from(model, data, "world"), "body 'world' (id 0) cannot be the grasped object: it is the "
         f"world body; {pinch_fix}"),
        (lambda: gm.scene_from(model, data, 0), f"body 'world' (id 0) cannot be the grasped object: it is the world "
         f"body; {pinch_fix}"),
        (lambda: gm.scene_from(model, data, "jaw_left"), "body 'jaw_left' (id 2) cannot be the grasped object: it has no "
         f"joint: it is fixed to the world, which holds it; {pinch_fix}"),
        (lambda: gm.scene_from(model, data, "jaw_right"), "body 'jaw_right' (id 3) cannot be the grasped object: it "
         f"moves on a slide joint only, not a free joint; {pinch_fix}"),
        (lambda: gm.schedule_from_rollout(hmodel, r, "a1"), "body 'a1' (id 2) cannot be the grasped object: it moves "
         "on a slide joint only"),
        (lambda: gm.scene_from(other, mujoco.MjData(other), "hand"), "body 'hand' (id 1) cannot be the grasped object: "
         "it is a mocap body, moved by the program, not by its contacts; fix: give the grasped object's body, one "
         "with a free joint (<freejoint/>) and a mass: ball"),
        (lambda: gm.scene_from(other, mujoco.MjData(other), "part"), "body 'part' (id 3) cannot be the grasped object: "
         "it has no joint: it is fixed to body 'frame', which holds it"),
        (lambda: gm.scene_from(other, mujoco.MjData(other), "frame"), "body 'frame' (id 2) cannot be the grasped "
         "object: it has no mass (0 kg), so no weight for a grasp to hold"),
    ]
    for call, words in cases:
        with pytest.raises(gm.UnknownBodyError, match=re.escape(words)):
            call()
    for body, words in (("world", cases[0][1]), ("jaw_left", cases[2][1])):
        proc = python_m("scene", PINCH, "--object", body, "--keyframe", "grasped", "--out", tmp_path / "s.json")
        assert proc.returncode == 1 and f"error: {words}" in proc.stderr, proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_mujoco_patch_size_and_margin_are_range_checked_and_a_cut_is_warned(pinch, tmp_path):
    """Item 5 of the hostile review: patch sizes and margins outside the scene's ranges (finite;
    a side from 1e-9 to 10 m, a margin from 0 to 5 m) are refused, naming the field and its
    option; a patch side cut to a box pad's side is a warning (1e308 silently gave 10 mm)."""
    model, data, _ = pinch
    mats = MJ / "pinch.materials.json"
    side = "not a finite number from 1e-09 to 10 m; fix: give a number from 1e-09 to 10 m"
    margin = "not a finite number from 0 to 5 m; fix: give a number from 0 to 5 m"
    refused = [({"size": [1e308, 1e308]}, f"patch size[0] (--patch-size) is 1e+308, {side}"),
               ({"size": [0.01, float("inf")]}, f"patch size[1] (--patch-size) is inf, {side}"),
               ({"size": [float("nan"), 0.01]}, "patch size[0] (--patch-size) is nan"),
               ({"size": [0.0, 0.01]}, "patch size[0] (--patch-size) is 0.0"),
               ({"size": [1e-12, 0.01]}, "patch size[0] (--patch-size) is 1e-12"),
               ({"size": [20, 0.01]}, "patch size[0] (--patch-size) is 20"),
               ({"size": ["1", 0.01]}, "patch size[0] (--patch-size) is '1'"),
               ({"size": [0.01]}, "patch size (--patch-size) is [0.01]; fix: give [a, b]"),
               ({"margin_m": 1e308}, f"patch margin_m (--margin) is 1e+308, {margin}"),
               ({"margin_m": -0.001}, "patch margin_m (--margin) is -0.001"),
               ({"margin_m": float("nan")}, "patch margin_m (--margin) is nan"),
               ({"margin_m": 6}, "patch margin_m (--margin) is 6")]
    for patch, words in refused:
        with pytest.raises(gm.MujocoError, match=re.escape(words)):
            gm.scene_from(model, data, "box", materials=mats, patch=patch)
    cut = [({"size": [0.02, 0.005]}, [0.01, 0.005], "patch side along t1 (0.02 m, patch size (--patch-size)) cut to "
            "the pad's side 0.01 m"),
           ({"margin_m": 0.001}, [0.01, 0.01], "patch side along t1 (0.012 m, MuJoCo's points plus twice margin_m "
            "(--margin)) cut to the pad's side 0.01 m")]
    for patch, size, words in cut:
        g = gm.scene_from(model, data, "box", materials=mats, patch=patch)
        for f in g.scene_dict["fingers"]:
            assert f["patch"]["size"] == pytest.approx(size, abs=1e-4)
            assert f"finger {f['name']}: {words}" in g.warnings, g.warnings
    base = ["scene", PINCH, "--object", "box", "--keyframe", "grasped", "--materials", mats, "--no-margin",
            "--out", tmp_path / "s.json"]
    for args, words in ((["--patch-size", "1e308", "1e308"], refused[0][1]), (["--margin", "1e308"], refused[8][1])):
        proc = python_m(*base, *args)
        assert proc.returncode == 1 and f"error: {words}" in proc.stderr, proc.stderr
        assert list(tmp_path.iterdir()) == []
    proc = python_m(*base, "--margin", "0.001")
    assert proc.returncode == 0 and f"warning: finger jaw_left: {cut[1][2]}" in proc.stderr, proc.stderr


def test_mujoco_states_with_non_finite_numbers_or_absurd_forces_are_state_errors(pinch, rollout, tmp_path, monkeypatch):
    """Item 6 of the hostile review: a NaN or an infinity anywhere in the state mj_forward reads
    (data, a keyframe, a rollout) is a StateError naming the field (a NaN keyframe said "no
    active contact"); MuJoCo contact forces that are not finite or beyond the project's 1e7 N
    are refused naming the finger (qvel 1e150 gave normal_load nan, 1e10 gave 1.7e17 N)."""
    model, data, _ = pinch
    mats = MJ / "pinch.materials.json"
    hmodel, r = rollout

    def state(field, value, index=slice(None)):
        d = gm.load_state(model, keyframe="grasped")
        getattr(d, field)[index] = value
        return d

    monkeypatch.chdir(tmp_path)  # MuJoCo logs the NaN of the keyframe to MUJOCO_LOG.TXT here
    text = PINCH.read_text().replace('<key name="start"', '<key name="bad" qpos="0 0 nan 1 0 0 0 0"/><key name="start"')
    (tmp_path / "nan.xml").write_text(text)
    arrays = {k: getattr(r, k) for k in ("time", "qpos", "qvel", "ctrl", "act", "qacc_warmstart", "mocap_pos",
                                         "mocap_quat")}
    fast = dict(arrays, qvel=np.full_like(r.qvel, 1e10))
    nan_gravity = mujoco.MjModel.from_xml_string(PINCH.read_text().replace('gravity="0 0 -9.81"', 'gravity="0 nan -9.81"'))
    force = "MuJoCo's contact force is"
    cases = [
        (lambda: gm.scene_from(model, state("qvel", float("inf")), "box"), "data: qvel[0] is inf; fix: give finite "
         "numbers for qvel in data"),
        (lambda: gm.scene_from(model, state("qpos", float("nan"), 2), "box"), "data: qpos[2] is nan"),
        (lambda: gm.scene_from(model, state("ctrl", float("nan")), "box"), "data: ctrl[0] is nan"),
        (lambda: gm.simulate(model, state("qvel", float("nan"), 3), lambda m, d: None, steps=2), "data: qvel[3] is nan"),
        (lambda: gm.scene_from(model, state("xfrc_applied", float("inf"), (1, 2)), "box"),
         "data: xfrc_applied[1][2] is inf"),
        (lambda: gm.scene_from(model, state("qvel", 1e150), "box", materials=mats),
         f"finger jaw_left: {force} nan N, not a force a grasp may have; fix: give a state MuJoCo can simulate"),
        (lambda: gm.scene_from(model, state("qvel", 1e10), "box", materials=mats),
         f"finger jaw_left: {force} 2.227e+17 N, beyond the 1e+07 N a grasp may have"),
        (lambda: gm.load_state(gm.load_model(tmp_path / "nan.xml"), keyframe="bad"),
         "keyframe 'bad': qpos[2] is nan; fix: give finite numbers for qpos in keyframe 'bad'"),
        (lambda: gm.schedule_from_rollout(hmodel, fast, "cylinder"), "at state 1 (t = 0.01 s): MuJoCo's contact force is"),
        (lambda: gm.schedule_from_rollout(hmodel, gm.Rollout(**dict(arrays, qpos=r.qpos * np.nan)), "cylinder"),
         "rollout: 'qpos' has a NaN or an infinity"),
    ]
    for call, words in cases:
        with pytest.raises(gm.StateError, match=re.escape(words)):
            call()
    with pytest.raises(gm.ModelLoadError, match=re.escape("the model's gravity (<option gravity>) is [0.0, nan, -9.81]")):
        gm.scene_from(nan_gravity, mujoco.MjData(nan_gravity), "box")
    out = tmp_path / "out"
    out.mkdir()
    np.savez(tmp_path / "fast.npz", qpos=data.qpos, qvel=data.qvel * 0 + 1e10)
    by_keyframe = next(w for _, w in cases if w.startswith("keyframe 'bad'"))
    too_fast = next(w for _, w in cases if "2.227e+17 N" in w)
    for args, words in ((["--keyframe", "bad"], by_keyframe), (["--qpos", tmp_path / "fast.npz"], too_fast)):
        proc = python_m("scene", tmp_path / "nan.xml", "--object", "box", "--materials", mats, *args,
                        "--out", out / "s.json", cwd=tmp_path)
        assert proc.returncode == 1 and f"error: {words}" in proc.stderr, proc.stderr
        assert list(out.iterdir()) == []


def npz_bomb(path, name, nbytes):
    """An .npz whose one array (zeros, deflated to a few kB) unpacks to ``nbytes``."""
    import zipfile

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (nbytes // 8,)})
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z, z.open(f"{name}.npy", "w", force_zip64=True) as f:
        f.write(header.getvalue())
        chunk = bytes(1 << 20)
        for _ in range(nbytes // len(chunk)):
            f.write(chunk)


def test_mujoco_a_patch_that_is_not_a_dict_and_corrupt_state_files_are_named_errors(pinch, rollout, tmp_path):
    """Item 7 of the hostile review: patch=[9, 9] raised a bare TypeError; a corrupt rollout
    ended in a BadZipFile traceback (and an empty one in EOFError, a JSON state nested too deep
    in RecursionError): each is a named error, the command exits 1 and writes nothing."""
    model, data, _ = pinch
    hmodel, r = rollout
    for patch in ([9, 9], "9 9", 9):
        with pytest.raises(gm.MujocoError, match=re.escape(f"patch is {patch!r} (a {type(patch).__name__}), not a "
                                                           "dict; fix: give None or a dict such as {'grid': [9, 9]")):
            gm.scene_from(model, data, "box", patch=patch)
    good = io.BytesIO()
    r.save(good)
    np.save(tmp_path / "one.npy", r.time)
    corrupt = {"zip.npz": b"PK\x03\x04" + bytes(64), "half.npz": good.getvalue()[:len(good.getvalue()) // 2],
               "text.npz": b"time qpos qvel\n", "empty.npz": b"", "one.npz": (tmp_path / "one.npy").read_bytes()}
    out = tmp_path / "out"
    out.mkdir()
    rollout_fix = "fix: give an .npz of time (T,), qpos (T, nq) and qvel (T, nv), as --save-rollout writes it"
    for name, raw in corrupt.items():
        path = tmp_path / name
        path.write_bytes(raw)
        words = f"{path} is not a rollout written by `python -m grasp.mujoco handoff --save-rollout` or Rollout.save ("
        with pytest.raises(gm.StateError, match=re.escape(words) + ".*" + re.escape(rollout_fix)):
            gm.schedule_from_rollout(hmodel, path, "cylinder")
        proc = python_m("handoff", HANDOFF, "--object", "cylinder", "--rollout", path, "--out", out / "h", "--no-replay")
        assert proc.returncode == 1 and f"error: {words}" in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
        with pytest.raises(gm.StateError, match=re.escape(f"state file {path} is not an .npz of qpos")):
            gm.load_state(model, qpos=path)
    assert list(out.iterdir()) == []
    (tmp_path / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    (tmp_path / "words.json").write_text('{"qpos": ["a", "b"]}')
    npz_bomb(tmp_path / "bomb.npz", "qpos", 65 << 20)
    states = [("deep.json", "cannot read the state file {}: RecursionError"),
              ("words.json", "{}: qpos is not a list of numbers (ValueError"),
              ("bomb.npz", "state file {} unpacks to 68157568 bytes, more than the 64 MiB its file may have")]
    for name, words in states:
        with pytest.raises(gm.StateError, match=re.escape(words.format(tmp_path / name))):
            gm.load_state(model, qpos=tmp_path / name)


def test_mujoco_long_runs_report_progress_on_a_terminal_only(tmp_path):
    # The simulation and the replay report their progress (a callable, or a line on
    # a terminal's standard error); nothing on a pipe or with --quiet.
    from grasp.mujoco._progress import terminal_bar

    model = gm.load_model(PINCH)
    seen = []
    gm.simulate(model, gm.load_state(model, keyframe="start"), lambda m, d: None, steps=7,
                progress=lambda done, total: seen.append((done, total)))
    assert seen == [(k, 7) for k in range(1, 8)]
    with pytest.raises(TypeError, match="progress= is not callable"):
        gm.simulate(model, gm.load_state(model, keyframe="start"), lambda m, d: None, steps=2, progress=3)

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    assert terminal_bar("steps", stream=io.StringIO()) is None
    assert terminal_bar("steps", quiet=True, stream=Terminal()) is None
    screen = Terminal()
    bar = terminal_bar("steps", stream=screen)
    for k in range(1, 4):
        bar(k, 3)
    assert "steps 3/3" in screen.getvalue() and "eta" in screen.getvalue()
    proc = python_m("scene", PINCH, "--object", "box", "--keyframe", "grasped", "--quiet", "--no-margin",
                    "--out", tmp_path / "s.json")
    assert proc.returncode == 0, proc.stderr
    assert "\r" not in proc.stderr


def test_mujoco_table_counts_a_frictionless_fingers_elements_apart():
    # As the CLI's table: elements of a frictionless finger (condim 1) neither stick nor slip.
    from grasp.mujoco._report import state_counts

    g = {"stick_count": 3, "slip_count": 5, "separated_count": 2}
    assert state_counts(g, 0.8) == "3/5/2"
    # The model counts them apart itself (state "frictionless"), not as stick or slip.
    frictionless = {"stick_count": 0, "slip_count": 0, "separated_count": 2, "frictionless_count": 8}
    assert state_counts(frictionless, 0.0) == "-/-/2 +8 frictionless"
    assert state_counts(None, 0.0) == "-"


def test_mujoco_a_sensor_in_every_pad_reads_each_fingers_load(pinch, tmp_path):
    # One surface taxel of 1 m, larger than any pad's patch, bins every element force of its
    # finger (docs/guide/tactile.md): it reads the finger's P to round-off (1e-12 relative).
    model, data, _ = pinch
    sensor = {"taxels": {"count": [1, 1], "pitch_m": 1.0, "size_m": 1.0, "depth_m": 0.0}}
    g = gm.scene_from(model, data, "box", materials=MJ / "pinch.materials.json", sensor=sensor)
    assert all(f["sensor"] == sensor for f in g.scene_dict["fingers"])
    sol = grasp.solve(g.scene)
    for name, p in zip(sol.finger_names, sol.finger_normal_forces_n):
        read = sol.sensor(name)["taxels"]["force_n"][0, 0, 0]
        assert abs(read - p) <= 1e-12 * p, (name, read, p)
    # The command writes the sensor into the scene; a bad one is named with the fix.
    out = tmp_path / "pinch.json"
    proc = python_m("scene", str(PINCH), "--object", "box", "--materials",
                    str(MJ / "pinch.materials.json"), "--keyframe", "grasped", "--out", str(out),
                    "--no-margin", "--sensor", json.dumps(sensor))
    assert proc.returncode == 0, proc.stderr
    assert json.loads(out.read_text())["fingers"][0]["sensor"] == sensor
    with pytest.raises(gm.MujocoError, match="give one or more of taxels, markers, gel"):
        gm.scene_from(model, data, "box", materials=MJ / "pinch.materials.json", sensor={"taxel": {}})
    proc = python_m("scene", str(PINCH), "--object", "box", "--keyframe", "grasped",
                    "--out", str(tmp_path / "bad.json"), "--no-margin", "--sensor", "{not json")
    assert proc.returncode == 1 and "--sensor is not JSON" in proc.stderr, proc.stderr
