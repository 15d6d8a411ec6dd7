"""grasp.mujoco: a grasp state, or a whole hand-off rollout, from MuJoCo into this project.

MuJoCo's soft contacts give each grasp plausible total forces, but no pressure distribution,
no stick zone, and a held object creeps. This module takes MuJoCo's contacts on an object and
asks the elastic contact model what it says about them (``mujoco`` is an optional extra:
``pip install 'mujoco==4.0.0'``; importing this module works without it, every call that
needs it raises :class:`MujocoNotInstalled` with that command):

>>> import mujoco, grasp.mujoco as gm
>>> model = mujoco.MjModel.from_xml_path("examples/mujoco/pinch.xml")
>>> data = mujoco.MjData(model)
>>> mujoco.mj_resetDataKeyframe(model, data, model.key("grasped").id)
>>> g = gm.scene_from(model, data, "box", materials="examples/mujoco/pinch.materials.json")
>>> g.scene                      # a grasp.Scene; g.fingers: MuJoCo's side, per finger
>>> report = gm.compare(g)       # grasp.solve beside MuJoCo's forces, with the margin
>>> print(report.table())
>>> report.write(json_path="out/pinch.report.json", rrd="out/pinch.rrd")

and for a hand-off, from a controller or a recorded rollout (.npz of time, qpos, qvel, ...):

>>> rollout = gm.simulate(model, data, "examples/mujoco/handoff_controller.py:control", steps=1600, every=10)
>>> h = gm.schedule_from_rollout(model, rollout, "cylinder", materials=...)
>>> h.write("out/handoff")       # out/handoff.json, .schedule.json, .csv: `grasp transfer` runs them
>>> replay = h.replay(mcap="out/handoff.mcap", rrd="out/handoff.rrd")
>>> print(replay.summary_text())

A URDF gripper loads the same way (MuJoCo compiles it; the grasped object is a link on a
floating joint, the state a qpos file since a URDF has no keyframes):

>>> model = gm.load_model("examples/mujoco/urdf_pinch.urdf", mesh_dir=None, fuse_static=None)
>>> data = gm.load_state(model, qpos="examples/mujoco/urdf_pinch.state.json")

The same from the shell: ``python -m grasp.mujoco scene ...`` and ``python -m grasp.mujoco
handoff ...`` (``--help``).
"""

from ._errors import (
    ContactGeometryError,
    ControllerError,
    MaterialMapError,
    ModelLoadError,
    MujocoError,
    MujocoNotInstalled,
    NoContactError,
    StateError,
    UnknownBodyError,
)
from ._controller import load_controller, simulate
from ._handoff import Handoff, HandoffReplay, schedule_from_rollout
from ._materials import DEFAULT_MATERIAL
from ._report import HOLD_SPEED_M_PER_S, Report, compare
from ._scene import MujocoFinger, MujocoGrasp, scene_from
from ._state import Rollout, load_model, load_state

__all__ = [
    "DEFAULT_MATERIAL",
    "HOLD_SPEED_M_PER_S",
    "ContactGeometryError",
    "ControllerError",
    "Handoff",
    "HandoffReplay",
    "MaterialMapError",
    "ModelLoadError",
    "MujocoError",
    "MujocoFinger",
    "MujocoGrasp",
    "MujocoNotInstalled",
    "NoContactError",
    "Report",
    "Rollout",
    "StateError",
    "UnknownBodyError",
    "compare",
    "load_controller",
    "load_model",
    "load_state",
    "schedule_from_rollout",
    "scene_from",
    "simulate",
]
