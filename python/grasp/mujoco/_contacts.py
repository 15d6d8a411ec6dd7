"""MuJoCo's contacts on the object, read at a state after ``mj_forward``, grouped into fingers.

Conventions read from MuJoCo (and checked in the tests against a resting box, whose contact
forces sum to its weight): ``contact.frame`` holds the normal first, pointing from ``geom1`` to
``geom2``, then the two tangents; ``mj_contactForce`` gives the force (and, for condim > 3, the
torque) that ``geom1`` exerts on ``geom2``, in that frame, normal first; ``contact.pos`` is the
midpoint between the two surfaces, ``contact.dist`` their signed distance (negative when they
overlap), so the object's surface point is ``pos +- dist/2 n``.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from ._errors import StateError
from ._limits import MAX_FORCE_N


@dataclass
class Contact:
    """One active MuJoCo contact of the object, in world coordinates, forces on the object."""

    index: int
    object_geom: int
    other_geom: int
    other_body: int
    point_m: np.ndarray  # on the object's surface
    applied_at_m: np.ndarray  # where MuJoCo applies the force (its Jacobians): contact.pos, the midpoint
    normal: np.ndarray  # unit, into the object
    tangent: np.ndarray  # MuJoCo's first tangent of the frame
    force_n: np.ndarray  # MuJoCo's contact force on the object, world
    torque_nm: np.ndarray  # torsional/rolling torque on the object (condim > 3), world
    normal_force_n: float
    mu: float  # MuJoCo's combined sliding friction of the pair (0 for condim 1)
    condim: int
    dist_m: float


@dataclass
class FingerLoad:
    """The contacts of one (object geom, other body) pair: one finger."""

    object_geom: int
    other_body: int
    contacts: list = field(default_factory=list)

    @property
    def key(self):
        return (self.object_geom, self.other_body)

    @property
    def force_n(self):
        """MuJoCo's total contact force on the object, world, N."""
        return np.sum([c.force_n for c in self.contacts], axis=0)

    @property
    def normal_weights(self):
        w = np.array([max(c.normal_force_n, 0.0) for c in self.contacts])
        return w if w.sum() > 0 else np.ones(len(self.contacts))

    @property
    def normal(self):
        """The common contact normal into the object: the direction of the summed normal
        forces (the plain mean where MuJoCo's normal forces are all zero)."""
        w = self.normal_weights
        n = np.sum([wi * c.normal for wi, c in zip(w, self.contacts)], axis=0)
        return n / np.linalg.norm(n)

    @property
    def center_of_pressure_m(self):
        """The contact points weighted by MuJoCo's normal forces."""
        w = self.normal_weights
        return np.sum([wi * c.point_m for wi, c in zip(w, self.contacts)], axis=0) / w.sum()

    @property
    def normal_force_n(self):
        """MuJoCo's normal force: the total contact force along the common normal, N."""
        return float(self.force_n @ self.normal)

    @property
    def friction_force_n(self):
        """MuJoCo's friction force: the total contact force across the common normal, N."""
        f = self.force_n
        return f - (f @ self.normal) * self.normal

    @property
    def main_other_geom(self):
        """The finger geom carrying the most normal force (the first one on a tie)."""
        best = max(self.contacts, key=lambda c: c.normal_force_n)
        return best.other_geom


def object_contacts(mujoco, model, data, body):
    """Every active contact (in the constraint solver: ``efc_address >= 0``, not excluded)
    between a geom of ``body`` and a geom of another body, at the state of ``data``
    (``mj_forward`` must have run). Contacts with flexes are skipped."""
    out = []
    f6 = np.zeros(6)
    for i in range(data.ncon):
        c = data.contact[i]
        if c.exclude != 0 or c.efc_address < 0 or c.geom1 < 0 or c.geom2 < 0:
            continue
        b1, b2 = int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2])
        if (b1 == body) == (b2 == body):
            continue
        frame = np.array(c.frame, dtype=float).reshape(3, 3)
        mujoco.mj_contactForce(model, data, i, f6)
        # Force and torque of geom1 on geom2, world frame.
        on2 = frame.T @ f6[:3]
        tq2 = frame.T @ f6[3:] if c.dim > 3 else np.zeros(3)
        n12 = frame[0]
        if b2 == body:  # the object is geom2
            obj_geom, other, sign = int(c.geom2), int(c.geom1), 1.0
            point = np.array(c.pos) + 0.5 * c.dist * n12
        else:
            obj_geom, other, sign = int(c.geom1), int(c.geom2), -1.0
            point = np.array(c.pos) - 0.5 * c.dist * n12
        normal = sign * n12
        out.append(Contact(
            index=i, object_geom=obj_geom, other_geom=other, other_body=int(model.geom_bodyid[other]),
            point_m=point, applied_at_m=np.array(c.pos, dtype=float), normal=normal, tangent=frame[1].copy(), force_n=sign * on2,
            torque_nm=sign * tq2, normal_force_n=float(f6[0]),
            mu=float(c.friction[0]) if c.dim > 1 else 0.0, condim=int(c.dim), dist_m=float(c.dist)))
    return out


def group_fingers(contacts):
    """Contacts grouped per (object geom, other body), ordered by (other body, object geom)."""
    groups = {}
    for c in contacts:
        key = (c.object_geom, c.other_body)
        groups.setdefault(key, FingerLoad(*key)).contacts.append(c)
    return [groups[k] for k in sorted(groups, key=lambda k: (k[1], k[0]))]


def finger_names(model, keys):
    """A name per (object geom, other body): the body's name, with the object geom's where the
    body touches several of the object's geoms."""
    per_body = {}
    for g, b in keys:
        per_body.setdefault(b, []).append(g)
    names = {}
    for g, b in keys:
        base = model.body(b).name or f"body{b}"
        if len(per_body[b]) > 1:
            base = f"{base}:{model.geom(g).name or f'geom{g}'}"
        names[(g, b)] = base
    return names


def force_problem(fl):
    """What is wrong with MuJoCo's contact force on the finger ``fl`` for a grasp (not finite,
    beyond the project's largest force, a torque not finite), or None."""
    force = float(np.linalg.norm(fl.force_n))
    if not math.isfinite(force):
        return f"contact force is {force} N, not a force"
    if force > MAX_FORCE_N:
        return f"contact force is {force:.4g} N, beyond the {MAX_FORCE_N:g} N"
    if not all(np.isfinite(c.torque_nm).all() for c in fl.contacts):
        return "contact torque is not finite, not a torque"
    return None


def check_forces(groups, names, where=""):
    """StateError naming the first finger whose MuJoCo contact force is no grasp's: a state
    MuJoCo cannot simulate (bodies overlapping deeply, or moving at absurd speeds)."""
    for fl in groups:
        problem = force_problem(fl)
        if problem:
            raise StateError(f"finger {names[fl.key]}{where}: MuJoCo's {problem} a grasp may have",
                             "give a state MuJoCo can simulate (finite, physical qpos and qvel: no body moving at "
                             "absurd speed or overlapping another deeply)")


def contact_wrench(contacts, center_m):
    """MuJoCo's total contact force (N) and moment about ``center_m`` (N m) on the object, each
    force applied where MuJoCo's dynamics applies it (``contact.pos``, the midpoint between the
    surfaces: half the overlap off the object's surface, which moves the friction's moment)."""
    force = np.zeros(3)
    torque = np.zeros(3)
    for c in contacts:
        force += c.force_n
        torque += np.cross(c.applied_at_m - center_m, c.force_n) + c.torque_nm
    return force, torque


def slip_speeds_m_per_s(mujoco, model, data, contacts):
    """Per contact, the tangential speed of the object's surface point relative to the other
    body's (m/s), from the bodies' Jacobians at the contact point."""
    jp1, jp2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    speeds = []
    for c in contacts:
        obj_body = int(model.geom_bodyid[c.object_geom])
        mujoco.mj_jac(model, data, jp1, None, c.point_m, obj_body)
        mujoco.mj_jac(model, data, jp2, None, c.point_m, c.other_body)
        v = (jp1 - jp2) @ data.qvel
        speeds.append(float(np.linalg.norm(v - (v @ c.normal) * c.normal)))
    return speeds
