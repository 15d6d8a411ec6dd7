"""A finger's servo as MuJoCo models it, turned into the scene's ``mount`` and commanded position.

A jaw on one slide joint, moved by position actuators (``<position kp=...>``: force ``kp (ctrl -
gear q)``, any affine actuator) and held by the joint's own ``stiffness``, is a spring between
the jaw and where its servo would put it unloaded. Seen at the contact it is the mount's normal
stiffness ``k = K_q / J_n^2`` (``K = J^-T K_q J^-1`` for one joint whose motion moves the contact
point along the normal: ``J_n = n . dp/dq``), with ``K_q`` the sum of the actuators' ``-bias_1
gear^2`` and the joint's stiffness. The commanded position past first touch is MuJoCo's overlap
at the contact plus how far the spring's force at the state would move the jaw, ``J_n tau /
K_q`` (``tau``: the actuators' and the joint spring's generalised force at the state, MuJoCo's
own, so a motor's constant push counts too).

Not taken (each refused naming the finger and the fix): a jaw on several joints or on a ball or
free joint, a joint whose motion turns the jaw or moves the contact point across the normal (a
hinge: the scene's mount would need their coupling), a joint with no stiffness (a bare motor: use
``control="mujoco-force"``), an actuator at its force limit or a joint at its actuator force
limit (no longer a spring there), a joint driven through a tendon or another transmission.
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
        The mount's normal stiffness, ``K_q / J_n^2``.
    approach_m : float
        The commanded position past first touch: MuJoCo's overlap plus ``J_n tau / K_q``.
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
        refuse(name, f"joint '{model.joint(j).name}' is a {kind} joint", "give the jaw a slide joint")
    return j


def at_limit(force, low_high):
    """True when ``force`` sits at either end of the range ``low_high`` (to 1e-9)."""
    return any(np.isclose(force, end, rtol=1e-9, atol=0.0) for end in low_high)


def joint_stiffness(mujoco, model, data, j, name):
    """``K_q`` (N/m or N m/rad) of joint ``j`` and the generalised force ``tau`` its springs
    (actuators, the joint's stiffness) put on it at the state: MuJoCo's ``qfrc_actuator`` (after
    its joint-level force limit) plus the joint spring's."""
    dof = int(model.jnt_dofadr[j])
    k = float(model.jnt_stiffness[j])
    qpos = float(data.qpos[model.jnt_qposadr[j]])
    spring = -k * (qpos - float(model.qpos_spring[model.jnt_qposadr[j]]))
    by_joint = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    summed = 0.0
    for a in range(model.nu):
        if int(model.actuator_trntype[a]) not in by_joint or int(model.actuator_trnid[a, 0]) != j:
            continue
        gear = float(model.actuator_gear[a, 0])
        if int(model.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_AFFINE):
            k += -float(model.actuator_biasprm[a, 1]) * gear * gear
        force = float(data.actuator_force[a])
        if model.actuator_forcelimited[a] and at_limit(force, model.actuator_forcerange[a]):
            refuse(name, f"actuator '{model.actuator(a).name}' is at its force limit ({force:g} N)",
                   "give a state within the actuator's force range, or control='mujoco-force'")
        summed += gear * force
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
               "give it a position actuator or a joint stiffness, or control='mujoco-force'")
    return k, applied + spring


def finger_servo(mujoco, model, data, body, point, n, overlap_m, name, half_side_m):
    """The :class:`Servo` of the jaw ``body`` touching at ``point`` (m, world) with the normal
    ``n`` into the object, where MuJoCo's surfaces overlap by ``overlap_m``; ``half_side_m``:
    the patch's half-side, over which a turn of the jaw would move the pad."""
    j = jaw_joint(mujoco, model, body, name)
    k_q, tau = joint_stiffness(mujoco, model, data, j, name)
    jacp = np.zeros((3, model.nv))
    jacr = np.zeros((3, model.nv))
    mujoco.mj_jac(model, data, jacp, jacr, np.asarray(point, dtype=float), body)
    dof = int(model.jnt_dofadr[j])
    moved, turned = jacp[:, dof], jacr[:, dof]
    j_n = float(moved @ n)
    across = float(np.linalg.norm(moved - j_n * n))
    turn = float(np.linalg.norm(turned))
    if not abs(j_n) > 0 or across > ALONG_NORMAL_TOLERANCE * abs(j_n) or \
            turn * half_side_m > ALONG_NORMAL_TOLERANCE * abs(j_n):
        refuse(name, f"joint '{model.joint(j).name}' moves the contact point {across:.3g} m across the normal "
                     f"and turns the jaw {turn:.3g} rad for every {abs(j_n):.3g} m along it",
               "give the jaw a slide joint along the contact normal, or control='mujoco-force' or 'held'")
    return Servo(joint=model.joint(j).name, stiffness_n_per_m=k_q / (j_n * j_n),
                 approach_m=float(overlap_m + j_n * tau / k_q), spring_force_n=tau / j_n,
                 overlap_m=float(overlap_m))
