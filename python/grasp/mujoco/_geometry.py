"""Geometry of MuJoCo geoms in this project's terms: the object's shape, the curvature of each
surface at a contact (sphere, cylinder, flat), the finger frame (t1, t2), the fingertip (a box,
cylinder or capsule as the posed solid, moved out of MuJoCo's overlap), and the candidate patch
(the points' spread for a flat pair, a Hertz estimate for a curved one).
"""

import math

import numpy as np

from ._errors import ContactGeometryError

# A patch side at most this fraction of twice the radius along it (the scene requires radius
# >= half the patch side).
RADIUS_SIDE_LIMIT = 0.999
# A spread below this (m) is no spread: one point, or points on a line.
MIN_SPREAD_M = 1e-6
# Patch sides per Hertz semi-axis (the project's suggestion: the contact and a ring of free
# elements around it, as `grasp solve --explain-frames` suggests).
HERTZ_SIDE_PER_SEMI_AXIS = 2.4
# A normal within this angle of a cylinder's axis is on its flat end.
CAP_ANGLE_DEG = 45.0
# Fingertip geoms written as the scene's `tip.shape` (the solid, posed) under exact gaps. A
# sphere keeps `tip.sphere`, already its exact profile; a mesh stays flat (MuJoCo collides its
# convex hull, not the mesh the scene would cast rays to).
TIP_SHAPE_TYPES = ("box", "cylinder", "capsule")
# The largest angle between a `tip.shape`'s outward normal at the contact and the contact's
# normal: the scene's limit (atan 0.3, the half-space's small slopes), degrees.
MAX_TIP_FACING_DEG = math.degrees(0.2915)
# A ray onto a fingertip that slips through an edge is cast again this fraction of its length aside.
RAY_NUDGE = 1e-9


def geom_type_name(mujoco, gtype):
    return mujoco.mjtGeom(int(gtype)).name.removeprefix("mjGEOM_").lower()


def geom_pose(data, g):
    """(position, 3x3 rotation with the geom's axes as columns) in the world."""
    return np.array(data.geom_xpos[g], dtype=float), np.array(data.geom_xmat[g], dtype=float).reshape(3, 3)


def quaternion_of(mujoco, rot):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rot).reshape(9))
    return q / np.linalg.norm(q)


def mesh_obj_text(model, g):
    """The geom's mesh as OBJ text, in the geom's frame (MuJoCo stores mesh vertices there)."""
    mid = int(model.geom_dataid[g])
    v0, nv = int(model.mesh_vertadr[mid]), int(model.mesh_vertnum[mid])
    f0, nf = int(model.mesh_faceadr[mid]), int(model.mesh_facenum[mid])
    verts = np.array(model.mesh_vert[v0:v0 + nv], dtype=float)
    faces = np.array(model.mesh_face[f0:f0 + nf], dtype=int)
    lines = [f"# MuJoCo mesh of geom {model.geom(g).name or g}, geom frame, m"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in verts.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    return "\n".join(lines) + "\n"


def object_shape(mujoco, model, data, g):
    """The scene's ``object.shape`` for geom ``g``, and the OBJ text of a mesh (or None), or
    (None, None, reason) for a type the scene format has no shape for."""
    t = geom_type_name(mujoco, model.geom_type[g])
    size = np.array(model.geom_size[g], dtype=float)
    pos, rot = geom_pose(data, g)
    pose = {"position": pos.tolist(), "quaternion": quaternion_of(mujoco, rot).tolist()}
    if t == "box":
        return {"box": {"size": (2 * size).tolist()}, **pose}, None, None
    if t == "sphere":
        return {"sphere": {"radius": float(size[0])}, **pose}, None, None
    if t in ("cylinder", "capsule"):
        return {t: {"radius": float(size[0]), "length": float(2 * size[1])}, **pose}, None, None
    if t == "mesh":
        return {"mesh": {"file": None}, **pose}, mesh_obj_text(model, g), None
    return None, None, f"a {t} has no shape in the scene format"


def tip_shape(mujoco, model, data, g, point, n, who):
    """The scene's ``tip.shape`` for fingertip geom ``g`` (box, cylinder or capsule) at the
    contact ``point`` (on the object's surface) with the normal ``n`` (into the object), and the
    distance (m) it was moved; None for another type.

    The tip is the geom as MuJoCo poses it, moved back along ``n`` out of the object by its
    overlap there (MuJoCo's soft contacts overlap, by a millimetre say; the scene's tip touches
    the object at the contact point undeformed, and the elastic model finds its own approach).
    The move is along the rays the scene casts to the tip (along the normal, its heights measured
    from its height at the contact point), so it changes no gap. ContactGeometryError where the
    line through the point along ``n`` misses the geom, or meets it where its surface does not
    face the object (MuJoCo's contact on the pad's edge or corner)."""
    t = geom_type_name(mujoco, model.geom_type[g])
    if t not in TIP_SHAPE_TYPES:
        return None
    shape, _, _ = object_shape(mujoco, model, data, g)
    pos, rot = geom_pose(data, g)
    # A ray from outside the geom, on the object's side, back along the normal; one through an
    # edge may slip past both faces in floating point: it is cast again a hair aside.
    reach = 2 * float(model.geom_rbound[g]) + float(np.linalg.norm(point - pos)) + 1e-3
    u = tangent_plane(np.eye(3)[int(np.argmin(np.abs(n)))], n)
    aside = [np.zeros(3)] + [RAY_NUDGE * reach * d for d in (u, -u, np.cross(n, u), -np.cross(n, u))]
    name = model.geom(g).name or f"geom {g}"
    for a in aside:
        normal = np.zeros(3)
        hit = mujoco.mju_rayGeom(pos, np.ascontiguousarray(rot).reshape(9), np.array(model.geom_size[g], dtype=float),
                                 point + a + reach * n, -n, int(model.geom_type[g]), normal)
        if hit >= 0:
            break
    else:
        raise ContactGeometryError(
            f"{who}: the line through MuJoCo's contact point along its normal misses the fingertip {t} "
            f"{name}", "give a state where the fingertip's surface faces the object at the contact")
    angle = math.degrees(math.acos(float(np.clip(normal @ n, -1.0, 1.0))))
    if angle > MAX_TIP_FACING_DEG:
        raise ContactGeometryError(
            f"{who}: the fingertip {t} {name} faces {angle:.1f} degrees away from MuJoCo's contact normal where "
            f"it meets the object (at most {MAX_TIP_FACING_DEG:.1f}: its edge or corner touches the object, "
            "which the elastic model's small slopes do not allow)",
            "give a state where the fingertip's face meets the object")
    moved = reach - float(hit)  # > 0: the tip's surface lies inside the object
    shape["position"] = (pos - moved * n).tolist()
    return shape, moved


def moved_shape(mujoco, shape, p_map, rot):
    """A posed shape moved rigidly: its position by ``p_map``, its orientation turned by ``rot``."""
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.array(shape["quaternion"], dtype=float))
    out = dict(shape)
    out["position"] = p_map(shape["position"]).tolist()
    out["quaternion"] = quaternion_of(mujoco, rot @ m.reshape(3, 3)).tolist()
    return out


class Surface:
    """A geom's surface at a contact point: ``kind`` "flat", "sphere" or "cylinder" (radius
    ``radius_m``, axis ``axis`` in the world), with a note where it is an approximation."""

    def __init__(self, kind, radius_m=None, axis=None, note=None, box=None):
        self.kind, self.radius_m, self.axis, self.note, self.box = kind, radius_m, axis, note, box


def surface_at(mujoco, model, data, g, point, normal_out):
    """The surface of geom ``g`` at a world ``point`` whose outward normal is ``normal_out``."""
    t = geom_type_name(mujoco, model.geom_type[g])
    size = np.array(model.geom_size[g], dtype=float)
    pos, rot = geom_pose(data, g)
    axis = rot[:, 2]
    name = model.geom(g).name or f"geom {g}"
    if t == "sphere":
        return Surface("sphere", float(size[0]))
    if t == "capsule":
        z = float((point - pos) @ axis)
        if abs(z) <= size[1]:
            return Surface("cylinder", float(size[0]), axis)
        return Surface("sphere", float(size[0]))
    if t == "cylinder":
        if abs(normal_out @ axis) > math.cos(math.radians(CAP_ANGLE_DEG)):
            return Surface("flat")
        return Surface("cylinder", float(size[0]), axis)
    if t == "box":
        return Surface("flat", box=(rot, size))
    if t in ("plane", "hfield"):
        return Surface("flat")
    if t == "mesh":
        return Surface("flat", note=f"{name} is a mesh: its curvature at the contact is not derived (taken flat)")
    return Surface("flat", note=f"{name} is a{'n' if t[0] in 'aeiou' else ''} {t}: taken flat at the contact")


def unit(v):
    return v / np.linalg.norm(v)


def tangent_plane(v, n):
    """``v`` projected on the plane normal to ``n``, unit; None when it is (nearly) along ``n``."""
    p = v - (v @ n) * n
    m = np.linalg.norm(p)
    return p / m if m > 1e-9 else None


def box_axis_across(rot, n):
    """The box axis most nearly perpendicular to ``n`` (the first on a tie), in the tangent plane."""
    dots = [abs(rot[:, k] @ n) for k in range(3)]
    k = int(np.argmin(dots))
    return tangent_plane(rot[:, k], n)


def frame_for(n, obj, tip, mujoco_tangent):
    """The finger's (t1, t2) with t1 x t2 = n: a cylinder's axis (the object's, else the tip's)
    along t2, else a box edge (the tip's, else the object's) along t1, else MuJoCo's tangent."""
    t2 = None
    for s in (obj, tip):
        if s.kind == "cylinder":
            t2 = tangent_plane(s.axis, n)
            if t2 is not None:
                return np.cross(t2, n), t2
    for s in (tip, obj):
        if s.box is not None:
            t1 = box_axis_across(s.box[0], n)
            if t1 is not None:
                return t1, np.cross(n, t1)
    t1 = tangent_plane(mujoco_tangent, n)
    if t1 is None:
        t1 = tangent_plane(np.eye(3)[int(np.argmin(np.abs(n)))], n)
    return t1, np.cross(n, t1)


def curvatures(s, t1, t2, who):
    """Curvature (1/m) of a surface along t1 and t2."""
    if s.kind == "sphere":
        return np.array([1.0, 1.0]) / s.radius_m
    if s.kind == "cylinder":
        a = unit(s.axis)
        if abs(a @ t2) > 1 - 1e-9:
            return np.array([1.0 / s.radius_m, 0.0])
        if abs(a @ t1) > 1 - 1e-9:
            return np.array([0.0, 1.0 / s.radius_m])
        raise ContactGeometryError(
            f"{who}: the cylinder's axis is at an angle to the other cylinder's (crossed cylinders "
            "at an angle have no principal frame in the scene format)",
            "cross the cylinders at a right angle or align them, or give the finger a spherical tip")
    return np.zeros(2)


def extent_along(box, d):
    """Full extent of a box (rot, half sizes) along the direction ``d``, m."""
    rot, size = box
    return float(2 * sum(abs(rot[:, k] @ d) * size[k] for k in range(3)))


def straight_length(s, d):
    """The length a surface offers along a direction in which it is straight (None: unbounded
    or unknown)."""
    if s.box is not None:
        return extent_along(s.box, d)
    return None


def hertz_semi_axes(load_n, k, e_star_pa, lengths):
    """Hertz semi-axes along t1, t2 (Johnson 4.2, the equivalent-radius ellipse, as the project's
    patch suggestion): None where the pair is straight (a line contact over ``lengths``)."""
    if k[0] > 0 and k[1] > 0:
        r1, r2 = 1 / k[0], 1 / k[1]
        c = (3 * load_n * math.sqrt(r1 * r2) / (4 * e_star_pa)) ** (1 / 3)
        return [c * (r1 / r2) ** (1 / 3), c * (r2 / r1) ** (1 / 3)]
    d = 0 if k[0] > 0 else 1
    length = lengths[1 - d]
    b = math.sqrt(4 * load_n * (1 / k[d]) / (math.pi * length * e_star_pa))
    return [b, None] if d == 0 else [None, b]
