"""The side-by-side report of one grasp: per finger, MuJoCo's normal and friction force
(``mj_contactForce``) beside this project's, the friction utilisation ``|Q| / (mu P)`` of both,
the project's stick / slip / separated element counts, and the grasp's smallest disturbance
margin (``grasp.transfer(..., margins=True)`` over the axis directions)."""

import json
import math
import os
import tempfile

from typing import TYPE_CHECKING

import numpy as np

from ._files import check_targets, write_all

if TYPE_CHECKING:
    from ._scene import MujocoGrasp

# MuJoCo "holds" the object while its contacts slide slower than this (m/s): MuJoCo's soft
# friction lets a pinched object creep at a steady rate, which is reported, not called a drop.
HOLD_SPEED_M_PER_S = 0.01
ONE_STEP = {"description": "one step: the scene as it is", "time": {"times": [0.0]}, "fingers": {}}


def fmt(x, spec=".4f"):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)


def state_counts(g, mu):
    """A finger's element counts as the CLI prints them: `stick/slip/separated`; a frictionless
    finger's elements in contact neither stick nor slip, so they are counted apart."""
    if g is None:
        return "-"
    if mu > 0:
        return f"{g['stick_count']}/{g['slip_count']}/{g['separated_count']}"
    return f"-/-/{g['separated_count']} +{g.get('frictionless_count', 0)} frictionless"


class Report:
    """MuJoCo's grasp beside this project's answer for the same scene (made by :func:`compare`).

    Parameters
    ----------
    grasp_state : MujocoGrasp
        MuJoCo's side.
    solution : grasp.Solution
        The elastic model's answer for its scene.
    margin_n : float or None
        The smallest disturbance margin, N: ``inf`` when unbounded (every direction held to the
        search's cap), None when not computed or undetermined.
    hold_speed_m_per_s : float, default HOLD_SPEED_M_PER_S
        MuJoCo holds the object when its contacts slide slower than this, m/s.
    """

    def __init__(self, grasp_state, solution, margin_n, hold_speed_m_per_s=HOLD_SPEED_M_PER_S):
        self.grasp = grasp_state
        self.solution = solution
        self.margin_n = margin_n
        self.hold_speed_m_per_s = hold_speed_m_per_s

    @property
    def mujoco_slip_speed_m_per_s(self):
        """The fastest sliding speed of MuJoCo's contacts, m/s."""
        return max(f.slip_speed_m_per_s for f in self.grasp.fingers)

    @property
    def mujoco_holds(self):
        """True when MuJoCo's fingers carry load and slide slower than ``hold_speed_m_per_s``."""
        loaded = any(f.normal_force_n > 0 for f in self.grasp.fingers)
        return bool(loaded and self.mujoco_slip_speed_m_per_s < self.hold_speed_m_per_s)

    @property
    def grasp_holds(self):
        """True when the elastic model found an equilibrium (solved, or to reduced accuracy)."""
        return self.solution.status in ("solved", "reduced_accuracy")

    def rows(self):
        """One row per finger: MuJoCo's forces beside the elastic model's.

        Returns
        -------
        list of dict
            ``{"name", "mujoco": {...}, "grasp": {...} or None}`` (N, m, Pa, m^2, N m).
        """
        ours = {f["name"]: f for f in (self.solution.fingers if self.solution.has_forces else [])}
        out = []
        for f in self.grasp.fingers:
            g = ours.get(f.name)
            out.append({
                "name": f.name,
                "mujoco": f.to_dict(),
                "grasp": None if g is None else {
                    k: g[k] for k in ("normal_force_n", "tangential_force_n", "tangential_magnitude_n",
                                      "friction_utilization", "stick_count", "slip_count", "separated_count",
                                      "center_of_pressure_m", "peak_pressure_pa", "contact_area_m2",
                                      "torsional_moment_nm")} | {"frictionless_count": g.get("frictionless_count", 0)},
            })
        return out

    def _margin_words(self):
        if math.isinf(self.margin_n):
            return "unbounded (held at the search's cap)"
        return f"{fmt(self.margin_n, '.4g')} N"

    def to_dict(self):
        """The whole report as a dict of JSON values (what :meth:`write` writes).

        Returns
        -------
        dict
            ``object`` (weight, centre of mass, unbalanced forces), ``fingers`` (:meth:`rows`),
            ``totals``, ``holds``, ``smallest_margin_n`` and ``warnings``.
        """
        g = self.grasp
        rows = self.rows()
        return {
            "mujoco_version": g.mujoco_version,
            "model": g.scene_dict["model"],
            "control": g.control,
            "object": {
                "weight_n": g.weight_n, "center_of_mass_m": g.center_of_mass_m.tolist(),
                "speed_m_per_s": g.object_speed_m_per_s,
                "unbalanced_force_n": g.unbalanced_force_n.tolist(),
                "inertial_force_n": g.inertial_force_n.tolist(),
                "unbalanced_torque_nm": g.unbalanced_torque_nm.tolist(),
            },
            "fingers": rows,
            "totals": {
                "mujoco_normal_force_n": float(sum(f.normal_force_n for f in g.fingers)),
                "grasp_normal_force_n": (float(sum(r["grasp"]["normal_force_n"] for r in rows if r["grasp"]))
                                         if self.solution.has_forces else None),
            },
            "holds": {
                "mujoco": self.mujoco_holds,
                "mujoco_slip_speed_m_per_s": self.mujoco_slip_speed_m_per_s,
                "hold_speed_m_per_s": self.hold_speed_m_per_s,
                "grasp": self.grasp_holds,
                "grasp_status": self.solution.status,
                "grasp_reason": self.solution.reason,
            },
            # JSON has no infinity: an unbounded margin is null with ``margin_unbounded``.
            "smallest_margin_n": (None if self.margin_n is not None and math.isinf(self.margin_n)
                                  else self.margin_n),
            "margin_unbounded": self.margin_n is not None and math.isinf(self.margin_n),
            "warnings": list(g.warnings) + list(self.solution.warnings),
        }

    def table(self, markdown=False):
        """The side-by-side table.

        Parameters
        ----------
        markdown : bool, default False
            A Markdown table (for a README) instead of aligned text.

        Returns
        -------
        str
        """
        # Friction |Q| and utilisation |Q| / (mu P) are spelled out: a '|' would split a Markdown cell.
        head = ["finger", "contacts", "MuJoCo P [N]", "MuJoCo friction [N]", "MuJoCo utilisation",
                "grasp P [N]", "grasp friction [N]", "grasp utilisation", "stick/slip/sep"]
        body = []
        for r in self.rows():
            m, g = r["mujoco"], r["grasp"]
            body.append([
                r["name"], str(m["contacts"]), fmt(m["normal_force_n"]), fmt(m["friction_magnitude_n"]),
                fmt(m["friction_utilisation"], ".3f"),
                fmt(g and g["normal_force_n"]), fmt(g and g["tangential_magnitude_n"]),
                fmt(g and g["friction_utilization"], ".3f"),
                state_counts(g, m["mu"])])
        d = self.to_dict()
        tot = d["totals"]
        body.append(["total", "", fmt(tot["mujoco_normal_force_n"]),
                     fmt(float(np.linalg.norm(sum(f.friction_force_n for f in self.grasp.fingers)))), "",
                     fmt(tot["grasp_normal_force_n"]),
                     fmt(float(np.linalg.norm(sum(np.array(r["grasp"]["tangential_force_n"]) for r in d["fingers"])))
                         if self.solution.has_forces else None), "", ""])
        if markdown:
            lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
            lines += ["| " + " | ".join(row) + " |" for row in body]
        else:
            widths = [max(len(x[i]) for x in [head] + body) for i in range(len(head))]
            lines = ["  ".join(x.rjust(w) if i else x.ljust(w) for i, (x, w) in enumerate(zip(row, widths)))
                     for row in [head] + body]
        lines.append("")
        lines.append(self.summary_line())
        return "\n".join(lines)

    def summary_line(self):
        """One line: whether MuJoCo and the elastic model hold, and the smallest margin.

        Returns
        -------
        str
        """
        h = self.to_dict()["holds"]
        mj = (f"MuJoCo {'holds' if h['mujoco'] else 'does not hold'} (contacts slide at up to "
              f"{1e3 * h['mujoco_slip_speed_m_per_s']:.3g} mm/s)")
        ours = f"grasp: {h['grasp_status']}" + (f" ({h['grasp_reason']})" if h["grasp_reason"] else "")
        margin = ("" if self.margin_n is None else
                  f"; smallest disturbance margin {self._margin_words()} ({self.grasp.scene_dict['model']} model, axis directions)")
        return f"{mj}; {ours}{margin}"

    def to_json(self):
        """The report as JSON text (NaN and infinities as null).

        Returns
        -------
        str
        """
        return json.dumps(finite(self.to_dict()), indent=2, allow_nan=False) + "\n"

    def write(self, json_path=None, rrd=None, overwrite=False, inputs=(), also=None):
        """Writes the report's JSON and/or its Rerun recording, all or nothing.

        Parameters
        ----------
        json_path : str or os.PathLike, optional
            The JSON of :meth:`to_dict`.
        rrd : str or os.PathLike, optional
            The project's recording of the scene merged with MuJoCo's forces.
        overwrite : bool, default False
            Replace existing files.
        inputs : sequence of path, default ()
            Files the run read (never replaced).
        also : dict, optional
            More files to write with them, ``{path: text or bytes}``.

        Returns
        -------
        list of str
            The paths written.

        Raises
        ------
        FileExistsError
            A file exists and ``overwrite`` is False.
        ValueError
            A path that may not be written (a folder, a link, an input of the run).
        MujocoNotInstalled
            ``rrd`` is asked for without ``rerun-sdk``.
        """
        targets = [p for p in (json_path, rrd) if p is not None] + list(also or {})
        check_targets(targets, overwrite, inputs)
        outs = dict(also or {})
        if json_path is not None:
            outs[os.fspath(json_path)] = self.to_json()
        if rrd is None:
            return write_all(outs, overwrite, inputs)
        with tempfile.TemporaryDirectory(prefix="grasp-mujoco-rrd-") as tmp:
            merged = recording(self.grasp, os.path.join(tmp, "merged.rrd"), tmp)
            with open(merged, "rb") as f:
                outs[os.fspath(rrd)] = f.read()
            return write_all(outs, overwrite, inputs)


def finite(v):
    """A JSON value with NaN and infinities as null (JSON has neither)."""
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    if isinstance(v, dict):
        return {k: finite(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [finite(x) for x in v]
    return v


def recording(grasp_state, out_path, tmp):
    """The project's one-step recording of the scene merged with MuJoCo's forces."""
    import grasp

    from . import _rerun

    _rerun.require_rerun()
    ours = os.path.join(tmp, "grasp.rrd")
    theirs = os.path.join(tmp, "mujoco.rrd")
    grasp.transfer(grasp_state.scene, ONE_STEP, rrd=ours)
    scale = _rerun.arrow_scale_m_per_n(grasp_state.scene)
    fingers = [(f.name, f.normal_force_n, f.normal, f.friction_force_n, f.center_of_pressure_m, f.points_m)
               for f in grasp_state.fingers]
    _rerun.write_mujoco_layer(theirs, [(0, 0.0, fingers)], scale)
    _rerun.merge([ours, theirs], out_path)
    return out_path


def compare(grasp_state: "MujocoGrasp", margins: bool = True, solver: str = "auto",
            hold_speed_m_per_s: float = HOLD_SPEED_M_PER_S) -> Report:
    """Solves the scene of a :class:`MujocoGrasp` and puts it beside MuJoCo's forces.

    Parameters
    ----------
    grasp_state : MujocoGrasp
        From :func:`scene_from`.
    margins : bool, default True
        Also find the smallest disturbance margin, N, over the axis directions (one
        ``grasp.transfer`` step with ``margins=True``; seconds on fine grids).
    solver : {"auto", "native", "clarabel"}, default "auto"
        As in ``grasp.solve``.
    hold_speed_m_per_s : float, default HOLD_SPEED_M_PER_S
        MuJoCo holds the object when its contacts slide slower than this, m/s.

    Returns
    -------
    Report
        ``table()``, ``to_dict()``, ``write(json_path=, rrd=)``.

    Raises
    ------
    SceneError
        The scene made from MuJoCo is not valid.
    ValueError
        ``solver`` is not one of the choices.
    """
    import grasp

    sol = grasp.solve(grasp_state.scene, solver=solver)
    margin = None
    if margins and sol.has_forces:
        run = grasp.transfer(grasp_state.scene, ONE_STEP, margins=True, solver=solver, keep_going=True)
        m = float(run.smallest_margins_n[0])
        margin = None if math.isnan(m) else m
    return Report(grasp_state, sol, margin, hold_speed_m_per_s)
