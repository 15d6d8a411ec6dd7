"""grasp.mujoco with ``control="mujoco-servo"``: a MuJoCo gripper's squeeze from its own actuator
gains (examples/mujoco/servo_pinch.xml: two jaws on slide joints, position actuators of kp 2000
N/m commanded 2 mm past first touch, rubber sphere tips of radius 10 mm on a wooden box).

The closed form: each jaw is a spring of MuJoCo's ``kp`` in series with a Hertz contact, so its
normal force solves ``P = kp (x - delta(P))``, ``delta(P) = (9 P^2 / (16 R E*^2))^(1/3)``
(Johnson 4.2 and eq. 4.23), with ``x`` the commanded position past first touch read from
MuJoCo alone: its overlap at the contact plus its actuator's force over ``kp``. MuJoCo's own
contact settles at its soft contact's overlap instead of Hertz's approach, so its normal force
(the actuator's, at equilibrium) differs from ours by ``kp (overlap - delta(P))``: the whole
difference, computed and checked here.

Tolerances, and why:
- 0.5 % on the normal force against the scalar root: the Hertz discretisation error the mounts'
  closed-form tests allow (Johnson's Hertz on this patch), plus the tangential load's coupling
  through Dundurs' beta (0.09 here), second order in the friction's 0.44 N;
- 1e-12 where the bridge copies MuJoCo's numbers (``kp``, the overlap, the actuator's force);
- 1e-3 of the force for MuJoCo's contact force against its actuator's force (its state is 1 s
  into a damped settle, the box creeping at 0.7 mm/s).
"""

import re

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, checker

mujoco = checker("mujoco", reason="MuJoCo is not installed (scripts/install-checkers.sh installs mujoco==4.0.0)")
import grasp.mujoco as gm  # noqa: E402

MJ = EXAMPLES / "mujoco"
SERVO = MJ / "servo_pinch.xml"
MATERIALS = MJ / "servo_pinch.materials.json"
TIP_RADIUS_M = 0.01


def e_star():
    """``E*`` of the rubber tip on the wooden box, Pa (Johnson eq. 4.22), from the material map."""
    rubber, wood = (2e6, 0.45), (1.1e10, 0.3)
    return 1.0 / sum((1 - nu * nu) / e for e, nu in (rubber, wood))


def hertz_approach(p):
    return (9 * p * p / (16 * TIP_RADIUS_M * e_star() ** 2)) ** (1 / 3)


def series_root(kp, x):
    """The root of ``P = kp (x - delta(P))`` by bisection (``P`` in ``[0, kp x]``)."""
    lo, hi = 0.0, kp * x
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid < kp * (x - hertz_approach(mid)) else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.fixture(scope="module")
def servo():
    model = gm.load_model(SERVO)
    data = gm.load_state(model, keyframe="grasped")
    return model, data, gm.scene_from(model, data, "box", materials=MATERIALS, control="mujoco-servo")


def mujoco_side(model, data, finger):
    """``kp``, MuJoCo's overlap (m) and its actuator's force (N) for ``finger`` (the actuator of
    the same name as the jaw, read straight from MuJoCo)."""
    a = model.actuator(finger.removeprefix("jaw_")).id
    kp = float(model.actuator_gainprm[a, 0])
    geom = model.geom(f"tip_{finger.removeprefix('jaw_')}").id
    overlaps = [-data.contact[i].dist for i in range(data.ncon) if geom in (data.contact[i].geom1, data.contact[i].geom2)]
    assert len(overlaps) == 1
    return kp, overlaps[0], float(data.actuator_force[a])


def test_mujoco_servo_jaws_are_mounts_of_the_actuators_kp_commanded_where_mujoco_puts_them(servo):
    model, data, g = servo
    for spec in g.scene_dict["fingers"]:
        kp, overlap, force = mujoco_side(model, data, spec["name"])
        assert kp == 2000.0
        assert spec["mount"] == {"normal_n_per_m": pytest.approx(kp, rel=1e-12)}
        assert spec["control"]["approach_m"] == pytest.approx(overlap + force / kp, rel=1e-12)
        # The commanded 2 mm past first touch, as the keyframe's ctrl says.
        assert spec["control"]["approach_m"] == pytest.approx(0.002, rel=1e-9)


def test_mujoco_servo_squeeze_is_the_series_springs_root_and_mujocos_differs_by_its_overlap(servo):
    model, data, g = servo
    sol = grasp.solve(g.scene)
    assert sol.status == "solved"
    mj = {f.name: f.normal_force_n for f in g.fingers}
    for f in sol.fingers:
        kp, overlap, force = mujoco_side(model, data, f["name"])
        x = overlap + force / kp
        want = series_root(kp, x)
        ours = f["normal_force_n"]
        print(f"{f['name']}: grasp P {ours:.5f} N, series root {want:.5f} N, MuJoCo {mj[f['name']]:.5f} N "
              f"(actuator {force:.5f} N); overlap {overlap * 1e3:.4f} mm, Hertz approach "
              f"{hertz_approach(ours) * 1e3:.4f} mm")
        assert ours == pytest.approx(want, rel=5e-3)
        # MuJoCo's contact force is its actuator's at equilibrium.
        assert mj[f["name"]] == pytest.approx(force, rel=1e-3)
        # The two squeezes differ by the two contacts' compliance: kp (overlap - delta).
        explained = kp * (overlap - hertz_approach(ours))
        assert ours - force == pytest.approx(explained, rel=1e-2)
        assert explained > 0.5  # MuJoCo's soft contact sinks in further than Hertz's


def changed_model(old, new):
    """The servo pinch with ``old`` replaced by ``new`` in its XML, at its keyframe "grasped"."""
    text = SERVO.read_text()
    changed = text.replace(old, new)
    assert changed != text
    model = mujoco.MjModel.from_xml_string(changed)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("grasped").id)
    return model, data


LEFT = '<position name="left" joint="jaw_left" kp="2000" ctrlrange="-0.005 0.005"/>'


def test_mujoco_servo_stiffness_is_kp_gear_squared_and_its_approach_follows_the_actuators_force():
    # A geared actuator: force kp (ctrl - gear q) on the length gear q, so K_q = kp gear^2 and
    # the jaw's unloaded position is where gear q = ctrl (MuJoCo's own force at the state says
    # how far that is: tau / K_q = gear force / (kp gear^2)).
    model, data = changed_model(LEFT, LEFT.replace('kp="2000"', 'kp="2000" gear="2"'))
    g = gm.scene_from(model, data, "box", materials=MATERIALS, control="mujoco-servo")
    left = next(f for f in g.scene_dict["fingers"] if f["name"] == "jaw_left")
    assert left["mount"]["normal_n_per_m"] == pytest.approx(2000.0 * 4, rel=1e-12)
    force = float(data.actuator_force[model.actuator("left").id])
    overlap = -min(data.contact[i].dist for i in range(data.ncon)
                   if model.geom("tip_left").id in (data.contact[i].geom1, data.contact[i].geom2))
    assert left["control"]["approach_m"] == pytest.approx(overlap + 2 * force / 8000.0, rel=1e-12)
    q = float(data.qpos[model.joint("jaw_left").qposadr[0]])
    assert left["control"]["approach_m"] == pytest.approx(overlap + 0.002 / 2 - q, rel=1e-9)


def test_mujoco_servo_refuses_jaws_it_cannot_read_as_a_spring_along_the_normal():
    pinch = gm.load_model(MJ / "pinch.xml")
    data = gm.load_state(pinch, keyframe="grasped")
    with pytest.raises(gm.MujocoError) as e:
        gm.scene_from(pinch, data, "box", materials=MJ / "pinch.materials.json", control="mujoco-servo")
    # The pinch's left jaw is welded to the world; its right jaw is a bare force motor.
    assert "moves on 0 joints, not one" in str(e.value)
    for old, new, words in [
        (LEFT, '<motor name="left" joint="jaw_left" ctrlrange="0 5"/>', "has no stiffness"),
        # A slide across the normal cannot squeeze.
        ('type="slide" axis="0 -1 0"', 'type="slide" axis="1 0 0"', "it cannot squeeze"),
        # An asymmetric force range: the actuator saturates at its upper end, 1 N.
        (LEFT, LEFT.replace("/>", ' forcelimited="true" forcerange="-10 1"/>'), "at its force limit"),
        ('damping="20"/>\n      <geom name="tip_left"',
         'damping="20" actuatorfrclimited="true" actuatorfrcrange="-1 1"/>\n      <geom name="tip_left"',
         "at its actuator force limit"),
    ]:
        model, data = changed_model(old, new)
        with pytest.raises(gm.MujocoError) as e:
            gm.scene_from(model, data, "box", materials=MATERIALS, control="mujoco-servo")
        assert words in str(e.value), str(e.value)
        assert "control='mujoco-force'" in str(e.value)


HINGE = MJ / "hinge_pinch.xml"


def test_mujoco_hinge_jaws_are_their_joints_compliance_and_squeeze_as_the_closed_form_says():
    """examples/mujoco/hinge_pinch.xml: each finger hangs 50 mm below a hinge along x, servoed at
    kp 5 N m/rad. Its contact point moves ``J = dp/dq`` per radian (MuJoCo's Jacobian at the
    contact): ``J_n`` along the normal, and ``J_z`` up, because the contact lies 10 mm off the
    line below the hinge (the tip's radius). So the box's weight, carried as friction ``W / 2``
    by each pad, turns the hinge too. The servo's balance ``K_q (q_c - q) = J_n P + J_z W / 2``
    and Hertz's approach ``delta(P)`` close the jaw: ``delta(P) = overlap + J_n (tau - J_n P -
    J_z W / 2) / K_q``, with ``tau`` MuJoCo's actuator torque at the state and ``overlap`` its
    contact's. The scene's mount is the compliance ``J J' / K_q`` in the contact frame (to
    1e-12: the bridge's arithmetic), preloaded by ``tau / J_n``; its squeeze must be that root
    within 0.5 % (the Hertz grid's error, as for the slide jaws). MuJoCo's own squeeze differs
    by ``K_q / J_n^2 (overlap - delta(P))`` (its softer contact) plus what its state, 1 s into
    a damped settle, leaves unbalanced on the joint, ``(tau - J_n P_mj - J_z F_mj) / J_n``
    (computed); what remains is the grid's error, within the same 0.5 % of the squeeze. A
    normal-only mount of ``K_q / J_n^2`` would miss ``J_z W / (2 J_n)``, 3 % of the squeeze:
    the test needs the coupling to pass."""
    model = gm.load_model(HINGE)
    data = gm.load_state(model, keyframe="grasped")
    g = gm.scene_from(model, data, "box", materials=MJ / "hinge_pinch.materials.json", control="mujoco-servo")
    sol = grasp.solve(g.scene)
    assert sol.status == "solved"
    weight = float(model.body("box").mass[0]) * 9.81
    mj = {f.name: (f.normal_force_n, float(f.friction_force_n[2])) for f in g.fingers}
    for spec, f in zip(g.scene_dict["fingers"], sol.fingers):
        side = spec["name"].removeprefix("jaw_")
        a, joint = model.actuator(side).id, model.joint(spec["name"])
        k_q = float(model.actuator_gainprm[a, 0])
        tau = float(data.actuator_force[a])
        geom = model.geom(f"tip_{side}").id
        (c,) = [data.contact[i] for i in range(data.ncon) if geom in (data.contact[i].geom1, data.contact[i].geom2)]
        overlap = -float(c.dist)
        point, n = np.asarray(spec["contact_point"]), np.asarray(spec["normal"])
        jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        mujoco.mj_jac(model, data, jacp, jacr, point, model.body(spec["name"]).id)
        dof = int(joint.dofadr[0])
        j_n, j_z = float(jacp[:, dof] @ n), float(jacp[2, dof])
        t1 = np.asarray(spec["tangent"])
        frame = np.array([t1, np.cross(n, t1), n])
        jac = np.concatenate([frame @ jacp[:, dof], frame @ jacr[:, dof]])
        assert np.allclose(spec["mount"]["compliance"], np.outer(jac, jac) / k_q, rtol=1e-12, atol=1e-18)
        assert spec["mount"]["preload_n"] == pytest.approx(tau / j_n, rel=1e-12)
        assert spec["control"]["approach_m"] == pytest.approx(overlap, rel=1e-12)
        lo, hi = 0.0, 10.0
        for _ in range(200):
            p = 0.5 * (lo + hi)
            gap = overlap + j_n * (tau - j_n * p - j_z * weight / 2) / k_q - hertz_approach(p)
            lo, hi = (p, hi) if gap > 0 else (lo, p)
        want, ours = 0.5 * (lo + hi), f["normal_force_n"]
        k_eff = k_q / j_n**2
        p_mj, f_mj = mj[spec["name"]]
        unbalanced = (tau - j_n * p_mj - j_z * f_mj) / j_n
        explained = k_eff * (overlap - hertz_approach(ours)) + unbalanced
        print(f"{spec['name']}: grasp P {ours:.5f} N, closed form {want:.5f} N, MuJoCo {p_mj:.5f} N "
              f"(unbalanced {unbalanced:.5f} N); J_n {j_n * 1e3:.3f} mm, J_z {j_z * 1e3:.3f} mm per rad; "
              f"difference {ours - p_mj:.5f} N, explained {explained:.5f} N")
        assert ours == pytest.approx(want, rel=5e-3)
        assert abs(j_z * weight / 2 / j_n) > 0.02 * ours  # the coupling the closed form counts
        assert abs((ours - p_mj) - explained) <= 5e-3 * ours
        # MuJoCo's own balance of the hinge: its actuator's torque is its contact's, J_n P + J_z
        # F, to 2e-3 of the squeeze (its state 1 s into a damped settle, the box creeping at
        # 0.39 mm/s; measured 1.5e-3).
        assert abs(unbalanced) <= 2e-3 * p_mj


COUPLED = MJ / "coupled_pinch.xml"


def tendon_spring_of(model, data, joints):
    """MuJoCo's own stiffness of tied jaws and their actuators' push, from its forces alone:
    ``K_q = -d(sum qfrc_actuator)/dq`` with every tied joint moved by ``dq`` (a difference of an
    affine force: exact to round-off), and ``tau = sum qfrc_actuator`` at the state."""
    dofs = [int(model.joint(j).dofadr[0]) for j in joints]
    mujoco.mj_forward(model, data)
    tau = float(sum(data.qfrc_actuator[d] for d in dofs))
    moved = mujoco.MjData(model)
    moved.qpos[:], moved.ctrl[:], moved.act[:] = data.qpos, data.ctrl, data.act
    dq = 1e-6
    for j in joints:
        moved.qpos[model.joint(j).qposadr[0]] += dq
    mujoco.mj_forward(model, moved)
    return -(float(sum(moved.qfrc_actuator[d] for d in dofs)) - tau) / dq, tau


def test_mujoco_coupled_jaws_are_one_servo_and_squeeze_as_the_closed_form_says():
    """examples/mujoco/coupled_pinch.xml, the Franka hand's drive as MuJoCo Menagerie models it:
    the two slide jaws tied by a joint equality and driven through a fixed tendon (half of each
    joint) by one actuator of kp 2000 N/m on the tendon's length. The jaws move as one
    coordinate, so the scene has one servo (``servos``) on the sum of the jaws' forces, of
    stiffness ``K_q / J_n^2`` with ``K_q`` MuJoCo's own ``-d(sum qfrc)/dq`` over the tied jaws,
    each jaw commanded at its overlap plus ``J_n tau / K_q`` (``tau``: the actuators' push on
    the jaws at the state), to 1e-9 (the difference quotient's round-off), here and for a
    geared drive with unequal coefficients (1.5 and 0.5, gear 2: 8000 N/m), and no mounts.
    The closed form: two alike jaws share the spring, ``2 P = k (x - delta(P))``, with ``x``
    from MuJoCo alone; the model within 0.5 % (the Hertz grid's error, as above). MuJoCo's
    jaws balance its tendon, ``P = tau / (2 J_n)``, to 1e-3 (its settle), and ours exceeds its
    squeeze by ``k / 2 (overlap - delta(P))`` (its softer contact) within the same 0.5 %.
    Refused: a tendon with no equality (a differential), and tied jaws that move the same way."""
    model = gm.load_model(COUPLED)
    data = gm.load_state(model, keyframe="grasped")
    g = gm.scene_from(model, data, "box", materials=MJ / "coupled_pinch.materials.json", control="mujoco-servo")
    (servo,) = g.scene_dict["servos"]
    assert servo["name"] == "split" and servo["fingers"] == ["jaw_left", "jaw_right"]
    k_q, tau = tendon_spring_of(model, data, ["jaw_left", "jaw_right"])
    assert servo["stiffness_n_per_m"] == pytest.approx(k_q, rel=1e-9)  # J_n = 1
    k = servo["stiffness_n_per_m"]
    sol = grasp.solve(g.scene)
    assert sol.status == "solved"
    mj = {f.name: f.normal_force_n for f in g.fingers}
    for spec, f in zip(g.scene_dict["fingers"], sol.fingers):
        assert "mount" not in spec
        geom = model.geom(f"tip_{spec['name'].removeprefix('jaw_')}").id
        (c,) = [data.contact[i] for i in range(data.ncon) if geom in (data.contact[i].geom1, data.contact[i].geom2)]
        overlap = -float(c.dist)
        x = overlap + tau / k_q
        assert spec["control"]["approach_m"] == pytest.approx(x, rel=1e-9)
        want = series_root(k / 2, x)
        ours = f["normal_force_n"]
        explained = k / 2 * (overlap - hertz_approach(ours))
        print(f"{spec['name']}: grasp P {ours:.5f} N, closed form {want:.5f} N, MuJoCo {mj[spec['name']]:.5f} N "
              f"(tau / 2 = {tau / 2:.5f} N); difference {ours - mj[spec['name']]:.5f} N, explained {explained:.5f} N")
        assert ours == pytest.approx(want, rel=5e-3)
        assert mj[spec["name"]] == pytest.approx(tau / 2, rel=1e-3)
        assert abs((ours - mj[spec["name"]]) - explained) <= 5e-3 * ours
    text = COUPLED.read_text()
    geared = text.replace('coef="0.5"/>\n      <joint joint="jaw_right" coef="0.5"',
                          'coef="1.5"/>\n      <joint joint="jaw_right" coef="0.5"')
    geared = geared.replace('tendon="split" biastype', 'tendon="split" gear="2" biastype')
    assert geared.count('coef="1.5"') == 1 and 'gear="2"' in geared
    model = mujoco.MjModel.from_xml_string(geared)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("grasped").id)
    data.ctrl[:] = 0.006  # past the geared length at this state (3.2 mm), so the servo presses
    g = gm.scene_from(model, data, "box", materials=MJ / "coupled_pinch.materials.json", control="mujoco-servo")
    k_q, tau = tendon_spring_of(model, data, ["jaw_left", "jaw_right"])
    assert g.scene_dict["servos"][0]["stiffness_n_per_m"] == pytest.approx(k_q, rel=1e-9)
    assert k_q == pytest.approx(2000.0 * 2.0**2 * 2.0**2, rel=1e-9)  # (sum c)^2 gear^2 kp
    for spec in g.scene_dict["fingers"]:
        geom = model.geom(f"tip_{spec['name'].removeprefix('jaw_')}").id
        overlap = -min(data.contact[i].dist for i in range(data.ncon)
                       if geom in (data.contact[i].geom1, data.contact[i].geom2))
        assert spec["control"]["approach_m"] == pytest.approx(overlap + tau / k_q, rel=1e-9)
    # Tied jaws that move the same way: the right jaw's slide reversed, its state mirrored so
    # that it still touches (the tie is MuJoCo's to keep; the bridge reads the motion).
    same_way = re.sub(r'(<key name="grasped"[^>]* qpos="[^"]* )(\S+)(")',
                      lambda m: m.group(1) + repr(-float(m.group(2))) + m.group(3),
                      text.replace('type="slide" axis="0 1 0"', 'type="slide" axis="0 -1 0"'))
    for xml, words in [
        (text.replace('<joint name="together" joint1="jaw_left" joint2="jaw_right"/>', ""),
         "no active joint equality ties them"),
        (same_way, "pulls this jaw off the object"),
    ]:
        model = mujoco.MjModel.from_xml_string(xml)
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, model.key("grasped").id)
        with pytest.raises(gm.MujocoError) as e:
            gm.scene_from(model, data, "box", materials=MJ / "coupled_pinch.materials.json", control="mujoco-servo")
        assert words in str(e.value) and "control='mujoco-force'" in str(e.value), str(e.value)
