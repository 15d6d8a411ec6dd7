"""The grasped object's body: found by name or id, and refused where MuJoCo's contacts on it
are not what holds it (the world; a body fixed or welded to another, on joints other than a
free one, or moved by the program) or where it has no weight to hold (no mass). Such a body's
contacts carry its support's reaction, which the scene would take for a grasp's load."""

import numpy as np

from ._errors import ModelLoadError, UnknownBodyError
from ._urdf import OBJECT_FIX, is_urdf


def urdf_hint(model, fix):
    """``fix``, and for a model compiled from a URDF how a URDF makes the object."""
    return f"{fix}; {OBJECT_FIX}" if is_urdf(model) else fix


def body_name(model, b):
    return model.body(b).name or f"body{b}"


def joint_types(mujoco, model, b):
    """The types of body ``b``'s own joints ("free", "ball", "slide", "hinge")."""
    return [mujoco.mjtJoint(int(model.jnt_type[j])).name.removeprefix("mjJNT_").lower()
            for j in range(model.njnt) if model.jnt_bodyid[j] == b]


def why_not_object(mujoco, model, b):
    """Why body ``b`` cannot be the grasped object, or None."""
    if b == 0:
        return "it is the world body"
    if model.body_mocapid[b] >= 0:
        return "it is a mocap body, moved by the program, not by its contacts"
    types = joint_types(mujoco, model, b)
    if types and "free" not in types:
        return f"it moves on {' and '.join(f'a {t}' for t in types)} joint only, not a free joint"
    if not types:
        weld = int(model.body_weldid[b])
        to = "the world" if weld == 0 else f"body '{body_name(model, weld)}'"
        return f"it has no joint: it is fixed to {to}, which holds it"
    if not model.body_mass[b] > 0:
        return f"it has no mass ({model.body_mass[b]:g} kg), so no weight for a grasp to hold"
    return None


def graspable_bodies(mujoco, model):
    """The named bodies that can be the grasped object."""
    return [model.body(b).name for b in range(1, model.nbody)
            if model.body(b).name and why_not_object(mujoco, model, b) is None]


def body_id(mujoco, model, body):
    """The id of a body given by name (or id); UnknownBodyError otherwise."""
    if isinstance(body, (int, np.integer)) and not isinstance(body, bool):
        if 0 <= int(body) < model.nbody:
            return int(body)
        raise UnknownBodyError(f"body id {body} is out of range (the model has {model.nbody} bodies)",
                               "give a body name or an id in range")
    b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, str(body))
    if b < 0:
        names = [model.body(i).name for i in range(1, model.nbody) if model.body(i).name]
        raise UnknownBodyError(f"the model has no body '{body}'",
                               urdf_hint(model, f"give one of its bodies: {', '.join(names) or '(none named)'}"))
    return b


def check_gravity(model):
    """The model's gravity (which makes the object's weight) is finite; ModelLoadError otherwise."""
    g = np.array(model.opt.gravity, dtype=float)
    if not np.all(np.isfinite(g)):
        raise ModelLoadError(f"the model's gravity (<option gravity>) is {g.tolist()}",
                             "give finite numbers, m/s^2 (MuJoCo's default is 0 0 -9.81)")


def object_body_id(mujoco, model, body):
    """The id of the grasped object's body (a name or an id): UnknownBodyError when the model
    has no such body, or when it cannot be the object (the same words for a name or an id)."""
    check_gravity(model)
    b = body_id(mujoco, model, body)
    why = why_not_object(mujoco, model, b)
    if why is not None:
        names = graspable_bodies(mujoco, model)
        raise UnknownBodyError(f"body '{body_name(model, b)}' (id {b}) cannot be the grasped object: {why}",
                               urdf_hint(model, "give the grasped object's body, one with a free joint (<freejoint/>) "
                                                f"and a mass: {', '.join(names) or '(this model has none)'}"))
    return b
