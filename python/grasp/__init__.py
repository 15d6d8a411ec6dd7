"""grasp: elastic grasp contact forces and object hand-offs, from Python.

The same library as the ``grasp`` command (Sinha's 1989 contact-stress grasp model as
corrected in ``docs/model.md``), called in-process:

>>> import grasp
>>> scene = grasp.Scene("examples/cube_a.json")          # a path, a dict or JSON text
>>> sol = grasp.solve(scene)                  # model=, solver=, tolerance=, compliance=
>>> sol.status, sol.finger_normal_forces_n               # N, one per finger
>>> sol.normal_forces_n, sol.tangential_forces_n         # per element: (N,), (N, 3)
>>> run = grasp.transfer(scene_b, "examples/plate_transfer.schedule.json", mcap="out.mcap")
>>> run.times_s, run.normal_forces_n                     # (T,), (T, F)
>>> plan = grasp.plan(scene_c, releasing=["f1", "f2"], receiving=["f3", "f4"], max_rate=1.5)
>>> plan["met"], plan["duration_s"]; grasp.transfer(scene_c, plan["schedule"])

Units are SI and every name carries its unit (``_n`` newtons, ``_m`` metres, ``_pa``
pascals, ``_s`` seconds). Bad scenes and schedules raise :class:`SceneError` /
:class:`ScheduleError` with ``problems`` (JSON path, message, fix); a grasp that cannot
hold is a solution whose ``status`` is ``"no_equilibrium"``, not an exception. The GIL is
released while the library computes, so threads solve in parallel.
"""

from ._native import (
    GraspError,
    Scene,
    SceneError,
    ScheduleError,
    Solution,
    Transfer,
    __version__,
    plan,
    solve,
    transfer,
)

__all__ = [
    "GraspError",
    "Scene",
    "SceneError",
    "ScheduleError",
    "Solution",
    "Transfer",
    "__version__",
    "plan",
    "solve",
    "transfer",
]
