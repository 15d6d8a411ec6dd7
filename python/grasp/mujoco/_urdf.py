"""URDF models, compiled by MuJoCo's URDF import: links become bodies, collisions geoms (named
by their ``name``), a ``floating`` joint a free joint, a link on a fixed joint is fused into its
parent. The bridge's URDF options go into the ``<mujoco><compiler>`` element of a copy of the
URDF text in memory (the user's file is never changed), compiled with the URDF's folder as the
model's folder, so relative names resolve as if MuJoCo had opened the file itself.
"""

import os
import warnings
import weakref
import xml.etree.ElementTree as ET

from ._errors import ModelLoadError

# The models compiled from a URDF here, so that errors about the object can say how a URDF
# makes one (a weak set: nothing is kept alive by it).
URDF_MODELS = weakref.WeakSet()

# The URDF options, as messages name them (the API's keyword, the command's option).
OPTION_NAMES = {"mesh_dir": "--mesh-dir (mesh_dir=)", "fuse_static": "--fuse-static/--no-fuse-static (fuse_static=)",
                "balance_inertia": "--balance-inertia (balance_inertia=)"}

OBJECT_FIX = ('in a URDF the grasped object is a link on a floating joint whose parent is the world link, '
              '<joint name="box" type="floating"><parent link="world"/><child link="box"/></joint>, '
              'with an <inertial> of nonzero mass; a link on a fixed joint is fused into its parent '
              '(MuJoCo\'s fusestatic; --no-fuse-static keeps it as a body)')


def is_urdf(model):
    """True for a model :func:`load_urdf` compiled."""
    return model in URDF_MODELS


def given_options(mesh_dir=None, fuse_static=None, balance_inertia=False):
    """The names of the URDF options that are set."""
    given = {"mesh_dir": mesh_dir is not None, "fuse_static": fuse_static is not None,
             "balance_inertia": bool(balance_inertia)}
    return [OPTION_NAMES[k] for k, v in given.items() if v]


def mesh_folder(mesh_dir):
    """``mesh_dir`` as an absolute folder (relative to the working folder); ModelLoadError when
    it is not a folder."""
    d = os.path.abspath(os.fspath(mesh_dir))
    if not os.path.isdir(d):
        what = "is not a folder" if os.path.exists(d) else "does not exist"
        raise ModelLoadError(f"the mesh folder {os.fspath(mesh_dir)} given as {OPTION_NAMES['mesh_dir']} {what}",
                             "give the folder that holds the URDF's mesh files (each is looked up there by its "
                             "bare file name), relative to the working folder or absolute")
    return d


def compiler_of(root):
    """The URDF's ``<mujoco><compiler>`` element, added when missing."""
    mj = root.find("mujoco")
    if mj is None:
        mj = ET.SubElement(root, "mujoco")
    compiler = mj.find("compiler")
    return compiler if compiler is not None else ET.SubElement(mj, "compiler")


def unname_duplicates(root):
    """Drops a collision name that several collisions share (MuJoCo keeps it on one of them,
    whichever it reaches first, and says so on standard output); warns naming their links."""
    named = {}
    for link in root.iter("link"):
        for col in link.iter("collision"):
            if col.get("name"):
                named.setdefault(col.get("name"), []).append((link.get("name"), col))
    for name, uses in named.items():
        if len(uses) > 1:
            for _, col in uses:
                del col.attrib["name"]
            links = ", ".join(sorted({str(link) for link, _ in uses}))
            warnings.warn(f"URDF collision name '{name}' is given to {len(uses)} collisions (links {links}): none of "
                          "their geoms is named; the material map names them by their links", stacklevel=4)


def urdf_text(root, mesh_dir, fuse_static, balance_inertia):
    """The URDF text with the options set in its ``<mujoco><compiler>`` element."""
    compiler = compiler_of(root)
    if mesh_dir is not None:
        compiler.set("meshdir", mesh_folder(mesh_dir))
        compiler.set("strippath", "true")
    if fuse_static is not None:
        compiler.set("fusestatic", "true" if fuse_static else "false")
    if balance_inertia:
        compiler.set("balanceinertia", "true")
    unname_duplicates(root)
    return ET.tostring(root, encoding="unicode")


def compile_fix(message, mesh_dir):
    """The fix for MuJoCo's compiler message on a URDF."""
    m = message.lower()
    if "free joint can only be used on top level" in m:
        return ("give the object's floating joint the world link as its parent (<parent link=\"world\"/>), or a link "
                "fixed to it with static links fused (leave out --no-fuse-static)")
    if "opening file" in m or "resource not found" in m:
        where = (f"put the mesh in {mesh_dir}, or give the folder that holds it as --mesh-dir" if mesh_dir is not None
                 else "give --mesh-dir DIR, the folder that holds the URDF's meshes (each looked up there by its bare "
                      "file name: package:// and folders stripped)")
        return where
    if "triangle inequality" in m or "balanceinertia" in m:
        return "fix the link's <inertia>, or add --balance-inertia (balance_inertia=True) to let MuJoCo balance it"
    if "mass and inertia" in m:
        return "give every moving link an <inertial> with a positive mass and inertia"
    return "fix the URDF"


def load_urdf(mujoco, path, root, mesh_dir=None, fuse_static=None, balance_inertia=False):
    """The MuJoCo model of the URDF at ``path`` (its XML tree ``root``, which is changed)."""
    text = urdf_text(root, mesh_dir, fuse_static, balance_inertia)
    try:
        spec = mujoco.MjSpec.from_string(text)
        spec.modelfiledir = os.path.dirname(os.path.abspath(path)) + os.sep
        model = spec.compile()
    except Exception as e:  # MuJoCo raises ValueError with the compiler's message
        message = str(e).strip()
        raise ModelLoadError(f"MuJoCo cannot compile the URDF {path}: {message}",
                             compile_fix(message, mesh_dir)) from None
    URDF_MODELS.add(model)
    return model
