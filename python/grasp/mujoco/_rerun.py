"""MuJoCo's forces added to a recording this project wrote: the project's Rerun file (object,
fingertips, pressure and stick/slip maps, its force arrows and plots, the layout) is merged with
a second recording of the same id holding MuJoCo's force arrows, contact points and force
plots (``rerun rrd merge``), so the viewer shows both force sets at every step.

Entities added: ``world/mujoco/forces/<finger>/normal`` and ``.../friction`` (arrows at
MuJoCo's centre of pressure, the project's scale; MuJoCo's normal in purple, friction in green,
beside the project's red and blue), ``world/mujoco/contacts/<finger>`` (MuJoCo's contact
points), ``plots/normal_force/mujoco/<finger>`` and ``plots/friction/mujoco/<finger>``.
"""

import os
import subprocess
import sys

import numpy as np

from ._errors import MujocoError

RERUN_VERSION = "0.36.3"
APPLICATION_ID = "grasp"  # the project's recordings (grasp-transfer's rerun_layout.rs)
RECORDING_ID = "grasp-transfer"
MUJOCO_NORMAL_RGB = [150, 40, 160]
MUJOCO_FRICTION_RGB = [40, 160, 80]


def require_rerun():
    try:
        import rerun  # noqa: PLC0415
    except ImportError:
        raise MujocoError(
            "a Rerun recording with MuJoCo's forces needs the Python package rerun-sdk, which is not installed",
            f"pip install 'rerun-sdk=={RERUN_VERSION}' (or pip install '.[mujoco]'), or leave out the .rrd output") from None
    return rerun


def arrow_scale_m_per_n(scene):
    """The project's arrow scale of ``scene`` (a ``grasp.Scene``), m per N: the one its
    recordings draw with (grasp-transfer sinks::drawing_scale, reached through
    ``grasp._native``)."""
    from .. import _native

    return _native._arrow_scale_m_per_n(scene)


def write_mujoco_layer(path, steps, m_per_n):
    """A recording (id ``grasp-transfer``) of MuJoCo's finger forces per step. ``steps``: list
    of (index, time_s, [(name, normal_force_n, normal, friction_force_n, cop, points)])."""
    rr = require_rerun()
    rec = rr.RecordingStream(APPLICATION_ID, recording_id=RECORDING_ID, make_default=False, make_thread_default=False)
    rec.set_log_time_enabled(False)  # the step and schedule time only, as the project's recordings
    rec.set_log_tick_enabled(False)
    rec.save(path)
    for index, time_s, fingers in steps:
        rec.set_time("step", sequence=int(index))
        rec.set_time("schedule_time", duration=float(time_s))
        for name, p, n, q, cop, points in fingers:
            pn = np.asarray(n) * p * m_per_n
            qv = np.asarray(q) * m_per_n
            rec.log(f"world/mujoco/forces/{name}/normal",
                    rr.Arrows3D(vectors=[pn], origins=[np.asarray(cop) - pn], colors=[MUJOCO_NORMAL_RGB],
                                labels=[f"MuJoCo {name} P {p:.3g} N"]))
            rec.log(f"world/mujoco/forces/{name}/friction",
                    rr.Arrows3D(vectors=[qv], origins=[cop], colors=[MUJOCO_FRICTION_RGB]))
            rec.log(f"world/mujoco/contacts/{name}",
                    rr.Points3D(np.asarray(points).reshape(-1, 3), colors=[MUJOCO_NORMAL_RGB], radii=[0.0005]))
            rec.log(f"plots/normal_force/mujoco/{name}", rr.Scalars([p]))
            rec.log(f"plots/friction/mujoco/{name}", rr.Scalars([float(np.linalg.norm(q))]))
    rec.flush()
    rec.disconnect()


def rerun_command():
    """The rerun CLI shipped with rerun-sdk: ``python -m rerun_cli``."""
    require_rerun()
    return [sys.executable, "-m", "rerun_cli"]


def merge(inputs, output):
    """``rerun rrd merge INPUTS -o OUTPUT``."""
    env = dict(os.environ, CI="1")
    proc = subprocess.run([*rerun_command(), "rrd", "merge", *map(os.fspath, inputs), "-o", os.fspath(output)],
                          capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        raise MujocoError(f"rerun rrd merge failed: {proc.stderr.strip()[-500:]}",
                          f"check the rerun-sdk installation (rerun-sdk=={RERUN_VERSION})")
