"""A MuJoCo hand-off as a scene plus a load schedule that ``grasp transfer`` replays.

The fingers are fixed: the union over the rollout of the (object geom, other body) pairs in
contact, each placed where it carried its largest normal force (in the object's frame, moved
with the object to its pose at the first step, the scene's pose). Each finger's normal load per
step is MuJoCo's normal force (zero, released, when MuJoCo has no contact there), written as a
CSV profile. What MuJoCo's contacts carried beyond the scene's weight (the object's inertia, the
gravity turning with the object, the solver's residual) is the schedule's external wrench at
the centre of mass, so the elastic model carries exactly MuJoCo's contact load at every step.
"""

import csv
import io
import json
import math
import os
import re
import tempfile
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional, Union

import numpy as np

from ._body import object_body_id
from ._contacts import (
    check_forces,
    contact_wrench,
    finger_names,
    group_fingers,
    object_contacts,
    slip_speeds_m_per_s,
)
from ._controller import load_controller, simulate  # noqa: F401 (this module's names before the split)
from ._errors import NoContactError, require_mujoco
from ._files import check_targets, write_all
from ._geometry import moved_shape
from ._limits import MAX_FORCE_N, check_number
from ._materials import MaterialMap
from ._patch import patch_options, sensor_option
from ._report import HOLD_SPEED_M_PER_S
from ._scene import (
    MODELS,
    check_choice,
    check_warnings,
    clean_force,
    finger_spec,
    load_scene,
    object_part,
    warning_counts,
)
from ._state import Rollout

if TYPE_CHECKING:
    import mujoco

PLAIN_NAME = re.compile(r"^[A-Za-z0-9_.:-]+$")


def check_threshold(threshold_n):
    """None, or a margin threshold in [0, MAX_FORCE_N] newtons."""
    if threshold_n is None:
        return None
    return check_number("threshold_n (--threshold)", threshold_n, 0.0, MAX_FORCE_N, "N")


@dataclass
class StepFinger:
    """One finger at one step, in the scene's frame (the object moved to its first pose)."""

    normal_force_n: float
    friction_force_n: np.ndarray
    normal: np.ndarray
    center_of_pressure_m: np.ndarray
    points_m: np.ndarray
    slip_speed_m_per_s: float


@dataclass
class Handoff:
    """A scene, a schedule and its CSV profile made from a MuJoCo rollout, with MuJoCo's
    per-step finger forces (made by :func:`schedule_from_rollout`).

    Attributes
    ----------
    scene_dict, schedule_dict : dict
        The scene and schedule formats (SI units).
    profile_csv : str
        The CSV profile the schedule reads (loads in N per time in s).
    finger_names : list of str
        The scene's fingers: the columns of the arrays.
    times_s : numpy.ndarray
        The rollout's times, s, shape ``(T,)``.
    normal_forces_n : numpy.ndarray
        MuJoCo's finger normal forces, N, shape ``(T, F)``.
    friction_forces_n : numpy.ndarray
        MuJoCo's finger friction forces, world frame, N, shape ``(T, F, 3)``.
    external_n : numpy.ndarray
        The external force (N) and couple (N m) at the centre of mass, scene frame, ``(T, 6)``.
    mujoco_held : numpy.ndarray
        Whether MuJoCo held the object at each step, bool, ``(T,)``.
    slip_speeds_m_per_s : numpy.ndarray
        The fastest sliding speed of MuJoCo's contacts at each step, m/s, ``(T,)``.
    steps : list of dict
        Per step, MuJoCo's forces per finger.
    contact_drift_m : dict
        Per finger, how far its contact drifted on the object over the rollout, m.
    warnings : list of str
        The approximations made.
    files : dict
        Extra files beside the scene (a mesh's OBJ), by name.
    hold_speed_m_per_s : float
        MuJoCo holds the object when its contacts slide slower than this, m/s.
    """

    scene_dict: dict
    schedule_dict: dict
    profile_csv: str
    finger_names: list
    times_s: np.ndarray
    normal_forces_n: np.ndarray
    friction_forces_n: np.ndarray
    external_n: np.ndarray  # (T, 6): force N, couple N m at the centre of mass, scene frame
    mujoco_held: np.ndarray
    slip_speeds_m_per_s: np.ndarray
    steps: list  # per step: {finger: StepFinger}
    contact_drift_m: dict
    warnings: list = field(default_factory=list)
    files: dict = field(default_factory=dict)
    hold_speed_m_per_s: float = HOLD_SPEED_M_PER_S
    _scene: object = None

    @property
    def scene(self):
        """The scene as a :class:`grasp.Scene` (validated)."""
        if self._scene is None:
            self._scene = load_scene(self.scene_dict, self.files)
        return self._scene

    def outputs(self, prefix):
        """The files :meth:`write` writes.

        Parameters
        ----------
        prefix : str or os.PathLike
            The path of the files without their suffixes.

        Returns
        -------
        dict of str to str
            ``{path: text}`` of PREFIX.json, PREFIX.schedule.json, PREFIX.csv (and a mesh).
        """
        prefix = os.fspath(prefix)
        folder, stem = os.path.split(prefix)
        schedule = json.loads(json.dumps(self.schedule_dict))
        csv_name = f"{stem}.csv"
        for phases in schedule["fingers"].values():
            phases[0]["csv"]["path"] = csv_name
        schedule["external"]["csv"]["path"] = csv_name
        outs = {f"{prefix}.json": json.dumps(self.scene_dict, indent=2) + "\n",
                f"{prefix}.schedule.json": json.dumps(schedule, indent=2) + "\n",
                os.path.join(folder, csv_name): self.profile_csv}
        for name, text in self.files.items():
            outs[os.path.join(folder, name)] = text
        return outs

    def write(self, prefix, overwrite=False, inputs=()):
        """Writes PREFIX.json (scene), PREFIX.schedule.json and PREFIX.csv, all or nothing.

        Parameters
        ----------
        prefix : str or os.PathLike
            The path of the files without their suffixes; its folder must exist.
        overwrite : bool, default False
            Replace existing files.
        inputs : sequence of path, default ()
            Files the run read (never replaced).

        Returns
        -------
        list of str
            The paths written.

        Raises
        ------
        SceneError
            The scene is not valid (checked before anything is written).
        FileExistsError
            A file exists and ``overwrite`` is False.
        ValueError
            A path that may not be written (a folder, a link, an input of the run).
        """
        self.scene  # validated before anything is written
        return write_all(self.outputs(prefix), overwrite, inputs)

    def replay(self, mcap=None, rrd=None, csv=None, margins=False, threshold_n=None, solver="auto",
               overwrite=False, inputs=(), also=None, progress=None):
        """Runs the schedule with ``grasp.transfer`` and writes its files, all or nothing.

        Every step is solved (``keep_going=True``); the Rerun recording is merged with MuJoCo's
        forces.

        Parameters
        ----------
        mcap, rrd, csv : str or os.PathLike, optional
            The files to write, as ``grasp.transfer``'s.
        margins : bool, default False
            Compute each step's smallest disturbance margin, N.
        threshold_n : float, optional
            Flag the steps whose smallest margin is below this, N.
        solver : {"auto", "native", "clarabel"}, default "auto"
            As in ``grasp.solve``.
        overwrite : bool, default False
            Replace existing files.
        inputs : sequence of path, default ()
            Files the run read (never replaced).
        also : dict, optional
            More files to write with them, ``{path: text or bytes}``.
        progress : callable, optional
            ``progress(done, total)``, called after each step.

        Returns
        -------
        HandoffReplay
            The replay, with the steps where MuJoCo held but the elastic model found no
            equilibrium, or a margin below ``threshold_n``.

        Raises
        ------
        ScheduleError
            The schedule is not valid for the scene.
        MujocoError
            ``threshold_n`` is not a number in [0, 1e7] N.
        FileExistsError
            A file exists and ``overwrite`` is False.
        ValueError
            A path that may not be written (a folder, a link, an input of the run).
        """
        import grasp

        threshold_n = check_threshold(threshold_n)
        named = {"mcap": mcap, "rrd": rrd, "csv": csv}
        targets = [p for p in named.values() if p is not None] + list(also or {})
        check_targets(targets, overwrite, inputs)
        with tempfile.TemporaryDirectory(prefix="grasp-mujoco-handoff-") as tmp:
            for path, text in self.outputs(os.path.join(tmp, "handoff")).items():
                with open(path, "w", encoding="utf-8", newline="") as f:
                    f.write(text)
            scene = grasp.Scene(os.path.join(tmp, "handoff.json"))
            temps = {k: os.path.join(tmp, f"out.{k}") for k, p in named.items() if p is not None}
            run = grasp.transfer(scene, os.path.join(tmp, "handoff.schedule.json"), margins=margins,
                                 keep_going=True, solver=solver, progress=progress, **temps)
            if rrd is not None:
                from . import _rerun

                scale = _rerun.arrow_scale_m_per_n(scene)
                layer = [(i, float(t), [(name, sf.normal_force_n, sf.normal, sf.friction_force_n,
                                         sf.center_of_pressure_m, sf.points_m)
                                        for name, sf in self.steps[i].items()])
                         for i, t in enumerate(self.times_s)]
                _rerun.write_mujoco_layer(os.path.join(tmp, "mujoco.rrd"), layer, scale)
                _rerun.merge([temps["rrd"], os.path.join(tmp, "mujoco.rrd")], os.path.join(tmp, "merged.rrd"))
                temps["rrd"] = os.path.join(tmp, "merged.rrd")
            outs = {}
            for k, t in temps.items():
                with open(t, "rb") as f:
                    outs[os.fspath(named[k])] = f.read()
            outs.update(also or {})
            write_all(outs, overwrite, inputs)
        return HandoffReplay(self, run, threshold_n)


class HandoffReplay:
    """The elastic replay of a MuJoCo hand-off beside MuJoCo's run (made by
    :meth:`Handoff.replay`).

    Parameters
    ----------
    handoff : Handoff
        MuJoCo's side.
    run : grasp.Transfer
        The elastic model's run of its schedule.
    threshold_n : float or None
        Steps whose smallest margin is below this, N, are flagged.
    """

    def __init__(self, handoff, run, threshold_n):
        self.handoff = handoff
        self.run = run
        self.threshold_n = threshold_n

    @property
    def flagged_steps(self):
        """Steps where MuJoCo held the object but the elastic model found no equilibrium, or a
        smallest margin below the threshold: ``[(step, time s, why)]``.
        """
        out = []
        margins = self.run.smallest_margins_n
        for i, (status, held) in enumerate(zip(self.run.statuses, self.handoff.mujoco_held)):
            if not held:
                continue
            if status not in ("solved", "reduced_accuracy"):
                out.append((i, float(self.handoff.times_s[i]), status))
            elif self.threshold_n is not None and math.isfinite(margins[i]) and margins[i] < self.threshold_n:
                out.append((i, float(self.handoff.times_s[i]), f"margin {margins[i]:.4g} N"))
        return out

    def to_dict(self):
        """The replay's comparison as a dict of JSON values.

        Returns
        -------
        dict
            Steps held and solved, flagged steps, the largest load and friction differences (N),
            contact drift (m), the fastest slip (m/s) and the run's summary.
        """
        h, run = self.handoff, self.run
        ok = [s in ("solved", "reduced_accuracy") for s in run.statuses]
        return {
            "steps": len(run), "fingers": h.finger_names,
            "mujoco_held_steps": int(np.sum(h.mujoco_held)),
            "elastic_solved_steps": int(np.sum(ok)),
            "flagged_steps": [{"step": i, "time_s": t, "why": w} for i, t, w in self.flagged_steps],
            "threshold_n": self.threshold_n,
            "largest_normal_load_difference_n": float(np.nanmax(np.abs(
                np.where(np.isnan(run.commanded_loads_n), 0.0, run.commanded_loads_n) - h.normal_forces_n))),
            "contact_drift_m": h.contact_drift_m,
            "friction_difference_n": self.friction_differences(),
            "largest_slip_speed_m_per_s": float(np.max(h.slip_speeds_m_per_s)),
            "summary": run.summary,
        }

    def friction_differences(self):
        """Per finger, the largest difference between the elastic model's friction force and MuJoCo's.

        Returns
        -------
        dict
            ``{finger: {"largest_n", "step", "time_s"}}``: the vector difference, N, over the steps
            the elastic model solved, and where it is.
        """
        q = np.nan_to_num(self.run.tangential_forces_n)
        ok = np.array([s in ("solved", "reduced_accuracy") for s in self.run.statuses])
        diff = np.linalg.norm(q - self.handoff.friction_forces_n, axis=2)
        diff[~ok] = 0.0
        out = {}
        for j, name in enumerate(self.handoff.finger_names):
            i = int(np.argmax(diff[:, j]))
            out[name] = {"largest_n": float(diff[i, j]), "step": i, "time_s": float(self.handoff.times_s[i])}
        return out

    def summary_text(self):
        """The comparison in a few lines of text.

        Returns
        -------
        str
        """
        d = self.to_dict()
        s = d["summary"]
        lines = [f"{d['steps']} steps: MuJoCo held the object in {d['mujoco_held_steps']} (contacts sliding slower than "
                 f"{1e3 * self.handoff.hold_speed_m_per_s:g} mm/s; fastest {1e3 * d['largest_slip_speed_m_per_s']:.3g} mm/s), "
                 f"the elastic model found an equilibrium in {d['elastic_solved_steps']}"]
        drift = ", ".join(f"{k} {1e3 * v:.3g} mm" for k, v in d["contact_drift_m"].items())
        lines.append(f"contact drift on the object over the rollout (kept fixed in the replay): {drift}")
        fd = ", ".join(f"{k} {v['largest_n']:.3g} N (t = {v['time_s']:.3g} s)" for k, v in d["friction_difference_n"].items())
        lines.append(f"friction force, elastic model against MuJoCo, largest difference: {fd}")
        if s.get("receiving"):
            half, full = s.get("half_transfer_time_s"), s.get("full_transfer_time_s")
            lines.append(f"elastic replay: {', '.join(s['receiving'])} receive from {', '.join(s['releasing'])}; "
                         f"half the load at t = {'-' if half is None else f'{half:.4g} s'}, all at "
                         f"t = {'-' if full is None else f'{full:.4g} s'}")
        flagged = d["flagged_steps"]
        what = "no equilibrium" + ("" if self.threshold_n is None else f" or a margin below {self.threshold_n:g} N")
        if flagged:
            shown = ", ".join(f"{f['step']} (t = {f['time_s']:.4g} s: {f['why']})" for f in flagged[:10])
            more = f" and {len(flagged) - 10} more" if len(flagged) > 10 else ""
            lines.append(f"steps where MuJoCo held but the elastic model found {what}: {shown}{more}")
        else:
            lines.append(f"no step where MuJoCo held but the elastic model found {what}")
        return "\n".join(lines)


def pose(data, b):
    return np.array(data.xpos[b], dtype=float), np.array(data.xmat[b], dtype=float).reshape(3, 3)


def schedule_from_rollout(model: "mujoco.MjModel", rollout: Union[Rollout, dict, str, "os.PathLike[str]"],
                          object_body: Union[str, int], materials: Union[None, dict, str, "os.PathLike[str]"] = None,
                          patch: Optional[dict] = None, contact_model: str = "coulomb",
                          hold_speed_m_per_s: float = HOLD_SPEED_M_PER_S, description: Optional[str] = None,
                          mesh_name: Optional[str] = None, sensor: Optional[dict] = None) -> "Handoff":
    """A scene plus a load schedule from a MuJoCo rollout.

    ``mj_forward`` runs at every row; each finger's normal force becomes its load profile and
    MuJoCo's contact forces on the object the schedule's external load.

    Parameters
    ----------
    model : mujoco.MjModel
    rollout : Rollout, dict, str or os.PathLike
        A :class:`Rollout`, an .npz path, or a dict of arrays: time (s), qpos, qvel, and
        optionally ctrl, act, qacc_warmstart, mocap_pos, mocap_quat.
    object_body : str or int
        The grasped body, by name or id.
    materials : dict, str or os.PathLike, optional
        ``{geom or body name: material}`` (a dict or a JSON file), as in :func:`scene_from`.
    patch : dict, optional
        ``{"grid": [nx, ny], "margin_m": m, "size": [a, b]}`` (sizes in m).
    contact_model : {"energy", "coulomb"}, default "coulomb"
        The scene's contact model.
    hold_speed_m_per_s : float, default HOLD_SPEED_M_PER_S
        MuJoCo holds the object when its contacts slide slower than this, m/s.
    description : str, optional
        The scene's description.
    mesh_name : str, optional
        The file name of an object mesh written beside the scene.
    sensor : dict, optional
        A tactile sensor given to every finger's pad, as in :func:`scene_from`; the replay
        reads it at every step (``Transfer.sensor_history(finger)``, the MCAP, the recording).

    Returns
    -------
    Handoff
        ``write(PREFIX)`` writes PREFIX.json, PREFIX.schedule.json and PREFIX.csv;
        ``replay(...)`` runs it.

    Raises
    ------
    MujocoNotInstalled
        ``mujoco`` cannot be imported.
    StateError
        The rollout cannot be read or does not fit the model.
    NoContactError
        The body is held by no contact in any state.
    UnknownBodyError, MaterialMapError, ContactGeometryError, MujocoError
        As in :func:`scene_from`.
    """
    mujoco = require_mujoco()
    check_choice("contact_model", contact_model, MODELS)
    opts = patch_options(patch)
    opts["sensor"] = sensor_option(sensor)
    b = object_body_id(mujoco, model, object_body)
    mats = MaterialMap(mujoco, model, materials)
    # A Rollout is checked as a file or a dict is (its shapes, finite numbers, its length).
    rollout = Rollout.load(rollout.arrays() if isinstance(rollout, Rollout) else rollout, model)
    data = mujoco.MjData(model)
    per_step, poses, wrenches, speeds = [], [], [], []
    for i in range(len(rollout)):
        rollout.apply(data, i)
        before = warning_counts(data)
        mujoco.mj_forward(model, data)
        check_warnings(mujoco, data, before)
        contacts = object_contacts(mujoco, model, data, b)
        groups = {fl.key: fl for fl in group_fingers(contacts)}
        at = f" at state {i} (t = {rollout.time[i]:.6g} s)"
        check_forces(groups.values(), finger_names(model, list(groups)), at)
        sp = slip_speeds_m_per_s(mujoco, model, data, contacts)
        speed_of = {c.index: s for c, s in zip(contacts, sp)}
        per_step.append({k: (fl, max(speed_of[c.index] for c in fl.contacts)) for k, fl in groups.items()})
        poses.append(pose(data, b) + (np.array(data.xipos[b], dtype=float),))
        wrenches.append(contact_wrench(contacts, np.array(data.xipos[b], dtype=float)))
        speeds.append(max(sp) if sp else 0.0)
    loaded = [i for i, s in enumerate(per_step) if any(fl.normal_force_n > 0 for fl, _ in s.values())]
    if not loaded:
        raise NoContactError(f"body '{model.body(b).name}' is held by no contact in any of the {len(rollout)} states",
                             "give the rollout of a grasp, or the grasped object's body")
    warnings = []
    first, last = loaded[0], loaded[-1]
    if first > 0 or last < len(rollout) - 1:
        # Before the first and after the last loaded contact nothing holds the object (it falls
        # into the grasp, or flies off): the elastic model has nothing to solve there.
        n = len(rollout)
        spans = [(0, first - 1)] if first > 0 else []
        spans += [(last + 1, n - 1)] if last < n - 1 else []
        # "state 0", "states 0..3", "states 0, 150": one state is named in the singular.
        noun = "state" if len(spans) == 1 and spans[0][0] == spans[0][1] else "states"
        spans = ", ".join(str(a) if a == b else f"{a}..{b}" for a, b in spans)
        warnings.append(f"{noun} {spans} left out: no contact carries load there "
                        f"(t = {rollout.time[first]:.6g} to {rollout.time[last]:.6g} s kept)")
        keep = slice(first, last + 1)
        rollout = rollout.rows(keep)
        per_step, poses, wrenches, speeds = per_step[keep], poses[keep], wrenches[keep], speeds[keep]
    keys = sorted({k for s in per_step for k in s}, key=lambda k: (k[1], k[0]))
    names = finger_names(model, keys)
    x0, r0, _ = poses[0]

    def turn(i):
        return r0 @ poses[i][1].T

    def to_scene(i):
        x, a = poses[i][0], turn(i)
        return (lambda p: a @ (np.asarray(p) - x) + x0), (lambda v: a @ np.asarray(v))

    # The scene's object: its weight, centre of mass and shape at the first state.
    rollout.apply(data, 0)
    mujoco.mj_forward(model, data)
    weight, com, gravity, shape, files = object_part(
        mujoco, model, data, b, warnings, mesh_name or f"{model.body(b).name or 'object'}.obj")
    # The scene's own loads (the schedule replaces them) are those of the step where the most
    # fingers carry the most load (both grippers holding, in a hand-off), so that the scene
    # alone (`grasp solve`, `grasp plot`) shows a grasp.
    shown = max(range(len(per_step)), key=lambda i: (
        sum(1 for fl, _ in per_step[i].values() if fl.normal_force_n > 0),
        sum(max(fl.normal_force_n, 0.0) for fl, _ in per_step[i].values()), -i))
    # Each finger placed where it carried its largest normal force.
    specs, obj_mats, drift = [], [], {}
    for k in keys:
        loads = [s[k][0].normal_force_n if k in s else -math.inf for s in per_step]
        i = int(np.argmax(loads))
        rollout.apply(data, i)
        mujoco.mj_forward(model, data)
        fl = group_fingers([c for c in object_contacts(mujoco, model, data, b) if (c.object_geom, c.other_body) == k])[0]
        load = fl.normal_force_n if fl.normal_force_n > 0 else max(weight, 1.0)
        spec, notes, mat_o = finger_spec(mujoco, model, data, fl, names[k], mats, opts, load,
                                         "mujoco-force", exact=shape is not None)
        warnings += notes
        p_map, v_map = to_scene(i)
        spec["contact_point"] = p_map(spec["contact_point"]).tolist()
        spec["normal"] = v_map(spec["normal"]).tolist()
        spec["tangent"] = v_map(spec["tangent"]).tolist()
        if "cylinder" in spec.get("tip", {}):
            spec["tip"]["cylinder"]["axis"] = v_map(spec["tip"]["cylinder"]["axis"]).tolist()
        if "shape" in spec.get("tip", {}):
            spec["tip"]["shape"] = moved_shape(mujoco, spec["tip"]["shape"], p_map, turn(i))
        at = per_step[shown].get(k)
        spec["control"] = {"normal_load": clean_force(max(at[0].normal_force_n, 0.0)) if at else 0.0}
        specs.append(spec)
        obj_mats.append((fl.normal_force_n, mat_o))
        ref_cop = np.array(spec["contact_point"])
        drift[names[k]] = float(max(np.linalg.norm(to_scene(j)[0](s[k][0].center_of_pressure_m) - ref_cop)
                                    for j, s in enumerate(per_step) if k in s))
    obj_mat = max(obj_mats, key=lambda x: x[0])[1]
    obj = {"weight": weight, "center_of_mass": com.tolist(), "gravity": gravity.tolist(), "material": obj_mat}
    if shape is not None:
        obj["shape"] = shape
    warn = mats.warning()
    if warn:
        warnings.insert(0, warn)
    t_n = len(rollout)
    f_n = len(keys)
    loads = np.zeros((t_n, f_n))
    friction = np.zeros((t_n, f_n, 3))
    slip = np.zeros((t_n, f_n))
    external = np.zeros((t_n, 6))
    steps = []
    for i, s in enumerate(per_step):
        p_map, v_map = to_scene(i)
        row = {}
        for j, k in enumerate(keys):
            if k not in s:
                continue
            fl, speed = s[k]
            loads[i, j] = clean_force(max(fl.normal_force_n, 0.0))
            friction[i, j] = v_map(fl.friction_force_n)
            slip[i, j] = speed
            row[names[k]] = StepFinger(loads[i, j], friction[i, j], v_map(fl.normal), p_map(fl.center_of_pressure_m),
                                       np.array([p_map(c.point_m) for c in fl.contacts]), speed)
        steps.append(row)
        force, torque = wrenches[i]
        # What the contacts carried beyond the scene's weight, in the scene's frame.
        external[i, :3] = [clean_force(x) for x in -(v_map(force) + weight * gravity)]
        external[i, 3:] = [clean_force(x) for x in -v_map(torque)]
    held = np.array([any(s[k][0].normal_force_n > 0 for k in s) and speeds[i] < hold_speed_m_per_s
                     for i, s in enumerate(per_step)])
    columns = [f"{names[k]}_n" if PLAIN_NAME.match(names[k]) else f"finger{j}_n" for j, k in enumerate(keys)]
    wrench_cols = ["fx_n", "fy_n", "fz_n", "tx_nm", "ty_nm", "tz_nm"]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["t_s", *columns, *wrench_cols])
    for i in range(t_n):
        w.writerow([repr(float(rollout.time[i])), *map(repr, map(float, loads[i])), *map(repr, map(float, external[i]))])
    body_name = model.body(b).name
    scene = {
        "description": description or (
            f"From a MuJoCo {mujoco.__version__} rollout of body '{body_name}' ({t_n} states, t = "
            f"{rollout.time[0]:.6g} to {rollout.time[-1]:.6g} s): the object at its first pose; each finger where it "
            f"carried its largest normal force, force-controlled at MuJoCo's load at t = {rollout.time[shown]:.6g} s, "
            "the step where the most fingers carry the most load (the schedule drives them; its external wrench "
            "adds what the contacts carried beyond the weight, which this scene alone leaves out)."),
        "object": obj, "fingers": specs, "model": contact_model}
    schedule = {
        "description": (f"MuJoCo's per-finger normal forces at each of the {t_n} states (CSV columns, zero where "
                        "MuJoCo has no contact), and what the contacts carried beyond the weight (the object's inertia, "
                        "gravity turning with it, the solver's residual) as the external wrench at the centre of mass."),
        "time": {"times": [float(t) for t in rollout.time]},
        "fingers": {names[k]: [{"csv": {"path": "PROFILE.csv", "time_column": "t_s", "load_column": col}}]
                    for k, col in zip(keys, columns)},
        "external": {"csv": {"path": "PROFILE.csv", "time_column": "t_s", "force_columns": wrench_cols[:3],
                             "torque_columns": wrench_cols[3:]}},
    }
    return Handoff(scene_dict=scene, schedule_dict=schedule, profile_csv=buf.getvalue(),
                   finger_names=[names[k] for k in keys], times_s=np.array(rollout.time, dtype=float),
                   normal_forces_n=loads, friction_forces_n=friction, external_n=external, mujoco_held=held,
                   slip_speeds_m_per_s=slip, steps=steps, contact_drift_m=drift, warnings=warnings, files=files,
                   hold_speed_m_per_s=hold_speed_m_per_s)


__all__ = ["schedule_from_rollout", "simulate", "Handoff", "HandoffReplay", "load_controller"]
