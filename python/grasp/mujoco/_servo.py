"""A finger's servo as MuJoCo models it, turned into the scene's ``mount`` and commanded position.

A jaw on one slide or hinge joint, moved by position actuators (``<position kp=...>``: force
``kp (ctrl - gear q)``, any affine actuator) and held by the joint's own ``stiffness``, is a
spring between the jaw and where its servo would put it unloaded, of stiffness ``K_q`` (the sum
of the actuators' ``-bias_1 gear^2`` and the joint's stiffness; N/m or N m/rad). Seen at the
contact, ``J = (dp/dq, dtheta/dq)`` in the contact frame (``t1, t2, n``; MuJoCo's Jacobian at the
contact point), it is the mount ``K = J^-T K_q J^-1``:

- a slide along the normal (the jaw moving along ``n``, not turning, to ``ALONG_NORMAL_TOLERANCE``)
  is the mount's normal stiffness ``k = K_q / J_n^2`` (``J_n = n . dp/dq``), commanded past first
  touch by MuJoCo's overlap at the contact plus how far the spring's force at the state would
  move the jaw, ``J_n tau / K_q`` (``tau``: the actuators' and the joint spring's generalised
  force at the state, MuJoCo's own, so a motor's constant push counts too);
- any other (a hinge, whose contact swings on an arc and whose pad turns; a slide tilted off the
  normal) is the compliant form, the singular ``compliance`` ``J J' / K_q``: the core moves only
  as the joint moves it, rigid in every other direction. It is commanded at MuJoCo's overlap and
  preloaded with the spring's force along the normal at the state, ``tau / J_n``: that preload
  puts the core where the spring would carry it unloaded, ``J tau / K_q``, along the joint's own
  motion (an approach would move it along the normal only).

Jaws whose joints one fixed tendon drives (affine actuators on the tendon, stiffness ``K_L``
on its length ``L = sum c_i q_i``) and a joint equality ties together (``q_1 = q_2``: a Franka
hand, as MuJoCo Menagerie models it) are one servo, the scene's ``servos`` entry: the jaws move
as one coordinate ``q`` with ``L = (sum c_i) q``, so the servo's stiffness on the sum of the
jaws' normal forces is ``(sum c_i)^2 K_L / J_n^2`` (each jaw's ``J_n`` alike, to
``ALONG_NORMAL_TOLERANCE``), and each jaw is commanded at its overlap plus ``J_n F_a / ((sum
c_i) K_L)``, with ``F_a`` the tendon actuators' force at the state. A tendon over one jaw's
joint alone is that jaw's spring: its normal mount, ``c^2 K_L / J_n^2``.

Not taken (each refused naming the finger and the fix): a jaw on several joints or on a ball or
free joint, a joint that does not move the contact point along the normal (``J_n`` 0: it cannot
squeeze), a hinge whose spring pulls the jaw off the object at the state (no preload to give), a
joint with no stiffness (a bare motor: use ``control="mujoco-force"``), an actuator at its force
limit or a joint at its actuator force limit (no longer a spring there), a joint driven through a transmission other than joint
actuators or one fixed tendon; for tied jaws also: a tendon over jaws no equality ties one to
one (a differential), coefficients summing to 0, a tendon with a spring of its own, jaws with
springs of their own, tied jaws that move the same way (the servo would pull one off), jaws
that turn or move across the normal, or unlike levers.
"""

from dataclasses import dataclass

import numpy as np

from ._body import body_name
from ._errors import MujocoError

# How far a jaw's joint may tilt its motion off the normal (rad: the distance across the normal
# per distance along it), or turn the pad (the turn times the patch's half-side, per distance
# along the normal), and still count as moving along it: the mount's stiffness along the normal
# is then right to about half its square (5e-7), below the contact's discretisation.
ALONG_NORMAL_TOLERANCE = 1e-3

# Relative agreement asked between MuJoCo's generalised actuator force on the jaw's joint and the
# sum of its joint actuators' forces: below it, no tendon, joint-level force limit or other
# transmission stands between them.
ACTUATOR_SUM_TOLERANCE = 1e-9

@dataclass
class Servo:
    """A finger's servo at the contact (N/m, m, N).

    Attributes
    ----------
    joint : str
        MuJoCo's joint that moves the jaw.
    stiffness_n_per_m : float
        The stiffness along the normal, ``K_q / J_n^2``.
    approach_m : float
        The commanded position past first touch: MuJoCo's overlap plus ``J_n tau / K_q`` (a
        slide along the normal), or the overlap alone (the compliant form, preloaded).
    spring_force_n : float
        MuJoCo's actuators' and joint spring's force along the normal at the state, ``tau / J_n``.
    overlap_m : float
        MuJoCo's overlap at the contact (its soft contact's penetration).
    """

    joint: str
    stiffness_n_per_m: float
    approach_m: float
    spring_force_n: float
    overlap_m: float
    compliance: list = None
    tendon: str = None
    tendon_jaws: int = 0

    def tendon_mark(self):
        """What the scene's ``servos`` needs of a tendon-coupled jaw (``None`` otherwise)."""
        if self.tendon is None:
            return None
        return {"tendon": self.tendon, "jaws": self.tendon_jaws, "stiffness_n_per_m": self.stiffness_n_per_m}

    def mount(self):
        """The scene's ``mount``: the normal stiffness of a slide along the normal, else the
        compliance ``J J' / K_q`` preloaded with the spring's force along the normal; ``None``
        for a jaw of a tendon-coupled servo (the scene's ``servos`` carries its spring)."""
        if self.tendon is not None:
            return None
        if self.compliance is None:
            return {"normal_n_per_m": self.stiffness_n_per_m}
        return {"compliance": self.compliance, "preload_n": self.spring_force_n}


@dataclass
class Coupling:
    """Jaw joints one fixed tendon drives and a joint equality ties (see the module)."""

    tendon: str
    joints: list
    coef_sum: float
    stiffness: float
    force: float


def tendon_coupling(mujoco, model, data, j, name):
    """The :class:`Coupling` of joint ``j``, or ``None`` when no tendon actuator drives it."""
    by_tendon = int(mujoco.mjtTrn.mjTRN_TENDON)
    tendons = {int(model.actuator_trnid[a, 0]) for a in range(model.nu)
               if int(model.actuator_trntype[a]) == by_tendon}
    for t in sorted(tendons):
        wraps = range(int(model.tendon_adr[t]), int(model.tendon_adr[t] + model.tendon_num[t]))
        joints = [int(model.wrap_objid[w]) for w in wraps]
        if int(model.wrap_type[wraps[0]]) != int(mujoco.mjtWrap.mjWRAP_JOINT) or j not in joints:
            continue
        tendon = model.tendon(t).name or f"tendon{t}"
        k, force = tendon_spring(mujoco, model, data, t, name)
        for other in joints:
            if other != j and not tied(mujoco, model, data, j, other):
                refuse(name, f"tendon '{tendon}' drives joints '{model.joint(j).name}' and "
                             f"'{model.joint(other).name}', but no active joint equality ties them one to one "
                             "(q1 = q2; a differential shares the force, not the motion)",
                       "tie the jaws' joints with a joint equality of polycoef '0 1 0 0 0', or control='mujoco-force'")
        coef_sum = float(sum(model.wrap_prm[w] for w in wraps))
        if not abs(coef_sum) > 0:
            refuse(name, f"tendon '{tendon}''s coefficients sum to 0: its length does not change as the tied jaws move",
                   "give the tendon coefficients of one sign, or control='mujoco-force'")
        dofs = [int(model.jnt_dofadr[i]) for i in joints]
        applied = float(sum(data.qfrc_actuator[d] for d in dofs))
        if abs(applied - coef_sum * force) > ACTUATOR_SUM_TOLERANCE * max(abs(applied), abs(coef_sum * force), 1e-300):
            refuse(name, f"the jaws of tendon '{tendon}' take {applied:g} from their actuators, not the tendon's "
                         f"{coef_sum * force:g} (another actuator, or a force limit on a joint or the tendon)",
                   "drive the coupled jaws by the one tendon within its force limits, or control='mujoco-force'")
        return Coupling(tendon=tendon, joints=joints, coef_sum=coef_sum, stiffness=k, force=force)
    return None


def tendon_spring(mujoco, model, data, t, name):
    """``K_L`` (N/m of tendon length) of tendon ``t``'s affine actuators and their force at the
    state, N; refuses one at its force limit or a tendon without stiffness."""
    k, force = actuator_springs(mujoco, model, data, (int(mujoco.mjtTrn.mjTRN_TENDON),), t, name)
    if float(model.tendon_stiffness[t]) != 0.0:
        refuse(name, f"tendon '{model.tendon(t).name}' has a spring of its own (stiffness "
                     f"{float(model.tendon_stiffness[t]):g})",
               "give the tendon's stiffness to its position actuator, or control='mujoco-force'")
    if not k > 0:
        refuse(name, f"tendon '{model.tendon(t).name}' has no stiffness (no position actuator on it)",
               "give it a position actuator, or control='mujoco-force'")
    return k, force


def tied(mujoco, model, data, a, b):
    """True when a joint equality active at the state ties joints ``a`` and ``b`` one to one
    (``q_a = q_b`` about their reference positions)."""
    for e in range(model.neq):
        if int(model.eq_type[e]) != int(mujoco.mjtEq.mjEQ_JOINT) or not data.eq_active[e]:
            continue
        pair = {int(model.eq_obj1id[e]), int(model.eq_obj2id[e])}
        if pair == {a, b} and np.allclose(model.eq_data[e, :5], [0, 1, 0, 0, 0]):
            return True
    return False


def refuse(name, what, fix):
    """Raises :class:`MujocoError` for finger ``name``: ``what`` is wrong, ``fix`` says what to do."""
    raise MujocoError(f"finger {name}: {what}", fix)


def jaw_joint(mujoco, model, body, name):
    """The one slide or hinge joint between ``body`` and the world (through its parents)."""
    joints = []
    b = body
    while b > 0:
        joints += [j for j in range(model.njnt) if model.jnt_bodyid[j] == b]
        b = int(model.body_parentid[b])
    if len(joints) != 1:
        refuse(name, f"body '{body_name(model, body)}' moves on {len(joints)} joints, not one",
               "give each jaw one slide joint along the contact normal, or control='mujoco-force' or 'held'")
    j = joints[0]
    kind = mujoco.mjtJoint(int(model.jnt_type[j])).name.removeprefix("mjJNT_").lower()
    if kind not in ("slide", "hinge"):
        refuse(name, f"joint '{model.joint(j).name}' is a {kind} joint", "give the jaw a slide or hinge joint")
    return j


def at_limit(force, low_high):
    """True when ``force`` sits at either end of the range ``low_high`` (to 1e-9)."""
    return any(np.isclose(force, end, rtol=1e-9, atol=0.0) for end in low_high)


def actuator_springs(mujoco, model, data, transmissions, target, name):
    """The stiffness of the actuators driving ``target`` through one of ``transmissions``
    (``-bias_1 gear^2`` of each affine one: N/m or N m/rad of the joint or tendon) and their
    force on it at the state (``gear`` times each actuator's force); refuses one at its force
    limit (no longer a spring there)."""
    k, force = 0.0, 0.0
    for a in range(model.nu):
        if int(model.actuator_trntype[a]) not in transmissions or int(model.actuator_trnid[a, 0]) != target:
            continue
        gear = float(model.actuator_gear[a, 0])
        if int(model.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_AFFINE):
            k += -float(model.actuator_biasprm[a, 1]) * gear * gear
        f = float(data.actuator_force[a])
        if model.actuator_forcelimited[a] and at_limit(f, model.actuator_forcerange[a]):
            refuse(name, f"actuator '{model.actuator(a).name}' is at its force limit ({f:g} N)",
                   "give a state within the actuator's force range, or control='mujoco-force'")
        force += gear * f
    return k, force


def joint_stiffness(mujoco, model, data, j, name):
    """``K_q`` (N/m or N m/rad) of joint ``j`` and the generalised force ``tau`` its springs
    (actuators, the joint's stiffness) put on it at the state: MuJoCo's ``qfrc_actuator`` (after
    its joint-level force limit) plus the joint spring's."""
    dof = int(model.jnt_dofadr[j])
    k = float(model.jnt_stiffness[j])
    qpos = float(data.qpos[model.jnt_qposadr[j]])
    spring = -k * (qpos - float(model.qpos_spring[model.jnt_qposadr[j]]))
    by_joint = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    k_actuators, summed = actuator_springs(mujoco, model, data, by_joint, j, name)
    k += k_actuators
    applied = float(data.qfrc_actuator[dof])
    if model.jnt_actfrclimited[j] and at_limit(applied, model.jnt_actfrcrange[j]):
        refuse(name, f"joint '{model.joint(j).name}' is at its actuator force limit ({applied:g})",
               "give a state within the joint's actfrcrange, or control='mujoco-force'")
    if abs(applied - summed) > ACTUATOR_SUM_TOLERANCE * max(abs(applied), abs(summed), 1e-300):
        refuse(name, f"joint '{model.joint(j).name}' is driven through a tendon or another transmission "
                     f"({applied:g} applied, {summed:g} from its joint actuators)",
               "drive the jaw's joint by joint actuators, or control='mujoco-force'")
    if not k > 0:
        refuse(name, f"joint '{model.joint(j).name}' has no stiffness (no position actuator, no joint stiffness)",
               "give it a position actuator (a URDF has none: an MJCF that attaches the URDF and adds "
               "one, docs/guide/mujoco.md \"URDF grippers\") or a joint stiffness, or control='mujoco-force'")
    return k, applied + spring


def finger_servo(mujoco, model, data, body, point, n, overlap_m, name, half_side_m, t1=None):
    """The :class:`Servo` of the jaw ``body`` touching at ``point`` (m, world) with the normal
    ``n`` into the object, where MuJoCo's surfaces overlap by ``overlap_m``; ``half_side_m``:
    the patch's half-side, over which a turn of the jaw would move the pad; ``t1``: the scene's
    first tangent (the contact frame of a compliance; ``None``: only the stiffness is asked)."""
    j = jaw_joint(mujoco, model, body, name)
    coupling = tendon_coupling(mujoco, model, data, j, name)
    if coupling is not None:
        return coupled_servo(mujoco, model, data, (body, j, coupling), point, n, overlap_m, name, half_side_m)
    k_q, tau = joint_stiffness(mujoco, model, data, j, name)
    jacp = np.zeros((3, model.nv))
    jacr = np.zeros((3, model.nv))
    mujoco.mj_jac(model, data, jacp, jacr, np.asarray(point, dtype=float), body)
    dof = int(model.jnt_dofadr[j])
    moved, turned = jacp[:, dof], jacr[:, dof]
    j_n = float(moved @ n)
    across = float(np.linalg.norm(moved - j_n * n))
    turn = float(np.linalg.norm(turned))
    if not abs(j_n) > ALONG_NORMAL_TOLERANCE * max(float(np.linalg.norm(moved)), turn * half_side_m):
        refuse(name, f"joint '{model.joint(j).name}' moves the contact point {abs(j_n):.3g} m along the normal "
                     f"for every {across:.3g} m across it and {turn:.3g} rad of turn: it cannot squeeze",
               "give the jaw a joint that moves its pad toward the object, or control='mujoco-force' or 'held'")
    along = across <= ALONG_NORMAL_TOLERANCE * abs(j_n) and turn * half_side_m <= ALONG_NORMAL_TOLERANCE * abs(j_n)
    servo = Servo(joint=model.joint(j).name, stiffness_n_per_m=k_q / (j_n * j_n),
                  approach_m=float(overlap_m + j_n * tau / k_q), spring_force_n=tau / j_n,
                  overlap_m=float(overlap_m))
    if along or t1 is None:
        return servo
    if not servo.spring_force_n > 0:
        refuse(name, f"joint '{model.joint(j).name}''s spring pulls the jaw off the object at the state "
                     f"({servo.spring_force_n:.3g} N along the normal)",
               "give a state where the servo presses the jaw on the object, or control='mujoco-force'")
    t1 = np.asarray(t1, dtype=float)
    frame = np.array([t1, np.cross(n, t1), n])
    jac = np.concatenate([frame @ moved, frame @ turned])
    servo.compliance = (np.outer(jac, jac) / k_q).tolist()
    servo.approach_m = float(overlap_m)
    return servo


def coupled_servo(mujoco, model, data, jaw, point, n, overlap_m, name, half_side_m):
    """The :class:`Servo` of a jaw of a tendon-coupled servo (see the module): ``jaw`` is
    ``(body, joint, coupling)``; its ``stiffness_n_per_m`` is the servo's, on the sum of the
    jaws' normal forces. A tendon over this jaw's joint alone is a spring of its own: the jaw's
    normal mount, as a joint actuator's."""
    body, j, c = jaw
    by_joint = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    if float(model.jnt_stiffness[j]) != 0.0 or any(
            int(model.actuator_trntype[a]) in by_joint and int(model.actuator_trnid[a, 0]) == j
            for a in range(model.nu)):
        refuse(name, f"joint '{model.joint(j).name}' has a spring of its own besides tendon '{c.tendon}'",
               "drive the coupled jaws by the tendon alone, or control='mujoco-force'")
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jac(model, data, jacp, jacr, np.asarray(point, dtype=float), body)
    dof = int(model.jnt_dofadr[j])
    moved, turn = jacp[:, dof], float(np.linalg.norm(jacr[:, dof]))
    j_n = float(moved @ n)
    across = float(np.linalg.norm(moved - j_n * n))
    if not abs(j_n) > 0 or max(across, turn * half_side_m) > ALONG_NORMAL_TOLERANCE * abs(j_n):
        refuse(name, f"joint '{model.joint(j).name}' of tendon '{c.tendon}' moves the contact point {across:.3g} m "
                     f"across the normal and turns the jaw {turn:.3g} rad for every {abs(j_n):.3g} m along it",
               "give the coupled jaws slide joints along the contact normal, or control='mujoco-force'")
    k_q, tau = c.coef_sum ** 2 * c.stiffness, c.coef_sum * c.force
    servo = Servo(joint=model.joint(j).name, stiffness_n_per_m=k_q / (j_n * j_n),
                  approach_m=float(overlap_m + j_n * tau / k_q), spring_force_n=tau / j_n,
                  overlap_m=float(overlap_m))
    if not servo.spring_force_n > 0:
        refuse(name, f"tendon '{c.tendon}' pulls this jaw off the object at the state ({servo.spring_force_n:.3g} N "
                     "along the normal: its tied jaws move the same way, or the servo opens)",
               "tie jaws that close on the object from opposite sides, or control='mujoco-force'")
    if len(c.joints) > 1:
        servo.tendon, servo.tendon_jaws = c.tendon, len(c.joints)
    return servo


def coupled_servos(specs):
    """The scene's ``servos`` from the fingers' specs, taking out each jaw's ``_tendon`` mark
    (:meth:`Servo.tendon_mark`): one servo per tendon, its jaws in scene order; refuses a
    tendon whose jaws do not all touch the object, or whose jaws see different stiffnesses
    (their ``J_n`` differ: the servo moves its jaws alike)."""
    servos = {}
    for spec in specs:
        mark = spec.pop("_tendon", None)
        if mark is not None:
            servos.setdefault(mark["tendon"], []).append((spec["name"], mark))
    out = []
    for tendon, jaws in servos.items():
        ks = [m["stiffness_n_per_m"] for _, m in jaws]
        if len(jaws) != jaws[0][1]["jaws"]:
            raise MujocoError(f"tendon '{tendon}' drives {jaws[0][1]['jaws']} jaws but {len(jaws)} touch the object",
                              "give a state where every coupled jaw touches it, or control='mujoco-force'")
        if max(ks) > min(ks) * (1 + ALONG_NORMAL_TOLERANCE):
            raise MujocoError(f"tendon '{tendon}' moves its jaws by different distances along their normals "
                              f"(servo stiffnesses {', '.join(f'{k:.6g}' for k in ks)} N/m)",
                              "give the coupled jaws alike levers, or control='mujoco-force'")
        out.append({"name": tendon, "fingers": [name for name, _ in jaws], "stiffness_n_per_m": ks[0]})
    return out
