"""Loading a MuJoCo model and a state into it (a keyframe, a qpos file, a rollout's rows)."""

import io
import json
import math
import os
from dataclasses import dataclass

import numpy as np

from ._assets import check_model_files, parse, tag_of
from ._errors import ModelLoadError, StateError, require_mujoco
from ._files import check_input, read_input
from ._limits import MAX_ROLLOUT_BYTES, MAX_STATE_FILE_BYTES, MAX_STATES
from ._npz import load_npy, load_npz, reason
from ._urdf import given_options, load_urdf, mesh_folder


MODEL_SUFFIXES = (".xml", ".urdf", ".mjb")


def load_model(path, *, mesh_dir=None, fuse_static=None, balance_inertia=False):
    """A MuJoCo model from a file: MJCF, URDF (compiled by MuJoCo's URDF import) or binary.

    The URDF options are set in the ``<mujoco><compiler>`` element of a copy of the URDF text
    in memory (they override the file's own); the file is never changed.

    Parameters
    ----------
    path : str or os.PathLike
        An MJCF (.xml), URDF (.urdf) or binary (.mjb) model file; the files it names (meshes,
        textures, includes) are checked as inputs too. An XML file is a URDF when its root
        element is ``<robot>``, as MuJoCo reads it.
    mesh_dir : str or os.PathLike, optional
        URDF only: the folder of its meshes (relative to the working folder, or absolute);
        each mesh is looked up there by its bare file name (``package://`` and folders
        stripped: MuJoCo's ``meshdir`` and ``strippath``).
    fuse_static : bool, optional
        URDF only: fuse links on fixed joints into their parents (MuJoCo's ``fusestatic``;
        None: MuJoCo's default for URDF, True).
    balance_inertia : bool, optional
        URDF only: let MuJoCo balance inertias that break the triangle inequality
        (``balanceinertia``).

    Returns
    -------
    mujoco.MjModel

    Raises
    ------
    MujocoNotInstalled
        ``mujoco`` cannot be imported.
    ModelLoadError
        The file, or one it names, cannot be read; its suffix is not one of .xml, .urdf,
        .mjb; a URDF option for a model that is not a URDF; a mesh folder that is not a
        folder; or MuJoCo cannot compile it.
    """
    mujoco = require_mujoco()
    p = os.fspath(path)
    # A regular file within the limit (never a FIFO or /dev/zero) before MuJoCo opens it, and
    # so is every file it names (meshes, textures, includes...).
    check_input(p, "mujoco_model", ModelLoadError)
    suffix = os.path.splitext(p)[1].lower()
    if suffix not in MODEL_SUFFIXES:
        raise ModelLoadError(f"model file {p} has the suffix '{suffix}', which is not a MuJoCo model's",
                             "give an MJCF .xml, a URDF .urdf or a binary .mjb file")
    urdf = {"mesh_dir": mesh_dir, "fuse_static": fuse_static, "balance_inertia": balance_inertia}
    root = None if suffix == ".mjb" else parse(p, None)
    if root is not None and tag_of(root) == "robot":
        check_model_files(p, [mesh_folder(mesh_dir)] if mesh_dir is not None else [])
        return load_urdf(mujoco, p, root, **urdf)
    given = given_options(**urdf)
    if given:
        why = "a binary model" if root is None else "its root element is not <robot>"
        raise ModelLoadError(f"{' and '.join(given)} {'applies' if len(given) == 1 else 'apply'} to a URDF model "
                             f"only; {p} is not one ({why})",
                             "leave them out: an MJCF sets them in its <compiler> "
                             "(meshdir, fusestatic, balanceinertia)")
    if root is not None:
        check_model_files(p)
    try:
        return mujoco.MjModel.from_binary_path(p) if root is None else mujoco.MjModel.from_xml_path(p)
    except Exception as e:  # MuJoCo raises ValueError with the compiler's message
        raise ModelLoadError(f"MuJoCo cannot load {p}: {str(e).strip()}", "fix the model file") from None


def keyframe_id(mujoco, model, key):
    if isinstance(key, int) or (isinstance(key, str) and key.isdigit()):
        k = int(key)
        if 0 <= k < model.nkey:
            return k
        raise StateError(f"keyframe {k} is out of range: the model has {model.nkey} keyframes",
                         "give a keyframe name or an index in range")
    if model.nkey == 0:
        raise StateError(f"the model has no keyframes, so none named '{key}' (a URDF has none)",
                         "give the state as a qpos file (--qpos FILE, qpos=): qpos numbers in the order of the "
                         f"model's joints, {qpos_layout(mujoco, model)}")
    k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, str(key))
    if k < 0:
        names = [model.key(i).name for i in range(model.nkey) if model.key(i).name]
        raise StateError(f"the model has no keyframe '{key}'",
                         f"give one of its keyframes: {', '.join(names) or '(none named)'}")
    return k


QPOS_WIDTH = {"free": "7: x y z, then the quaternion w x y z", "ball": "4: the quaternion w x y z", "slide": "1",
              "hinge": "1"}


def qpos_layout(mujoco, model):
    """The model's joints in qpos order, each with its count of numbers."""
    parts = []
    for j in range(model.njnt):
        kind = mujoco.mjtJoint(int(model.jnt_type[j])).name.removeprefix("mjJNT_").lower()
        parts.append(f"{model.joint(j).name or f'joint {j}'} ({QPOS_WIDTH[kind]})")
    return ", ".join(parts) or "(none)"


def numbers(values, what, source):
    """``values`` as a flat float array; StateError naming ``what`` where they are not numbers."""
    try:
        return np.asarray(values, dtype=float).reshape(-1)
    except (TypeError, ValueError) as e:
        raise StateError(f"{source}: {what} is not a list of numbers ({reason(e)})",
                         f"give {what} as numbers") from None


def vector(values, length, what, source):
    a = numbers(values, what, source) if values is not None else None
    if a is None or a.shape != (length,):
        got = "nothing" if a is None else f"{a.size} numbers"
        raise StateError(f"{source}: {what} has {got}, the model needs {length}",
                         f"give {length} numbers ({what} of this model)")
    if not np.all(np.isfinite(a)):
        raise StateError(f"{source}: {what} has a NaN or an infinity", "give finite numbers")
    return a


STATE_FIX = "give qpos as whitespace-separated numbers, .npy, .npz (qpos and optionally qvel, ctrl, act, time) or JSON"
ROLLOUT_WHAT = "a rollout written by `python -m grasp.mujoco handoff --save-rollout` or Rollout.save"
ROLLOUT_FIX = "give an .npz of time (T,), qpos (T, nq) and qvel (T, nv), as --save-rollout writes it"


def read_state_file(path):
    """{"qpos": ..., optional "qvel", "ctrl", "act"} from .npy/.txt (qpos only), .npz or .json."""
    p = os.fspath(path)
    raw = read_input(p, "mujoco_state", StateError)
    src = f"state file {p}"
    if p.endswith(".npz"):
        return load_npz(raw, src, "an .npz of qpos (and qvel, ctrl, act, time)", MAX_STATE_FILE_BYTES, StateError,
                        STATE_FIX)
    if p.endswith(".npy"):
        return {"qpos": load_npy(raw, src, "an .npy of qpos", StateError, STATE_FIX)}
    try:
        if p.endswith(".json"):
            d = json.loads(raw.decode("utf-8"))
            return d if isinstance(d, dict) else {"qpos": d}
        return {"qpos": np.loadtxt(io.BytesIO(raw), ndmin=1)}
    except Exception as e:  # noqa: BLE001 (a decode, JSON, nesting or number error: the file is not a state)
        raise StateError(f"cannot read the state file {p}: {reason(e)}", STATE_FIX) from None


# What ``mj_forward`` reads of a state: each must be finite (MuJoCo checks none of it there, and
# a NaN in qpos gives no contacts at all).
STATE_FIELDS = ("time", "qpos", "qvel", "act", "ctrl", "qacc_warmstart", "mocap_pos", "mocap_quat", "qfrc_applied",
                "xfrc_applied")


def check_finite_state(data, source):
    """StateError naming the first NaN or infinity of the state of ``data`` (``source``: how
    the message names the state)."""
    for k in STATE_FIELDS:
        a = np.asarray(getattr(data, k), dtype=float)
        bad = np.argwhere(~np.isfinite(a))
        if len(bad):
            at = "".join(f"[{i}]" for i in bad[0])
            raise StateError(f"{source}: {k}{at} is {a[tuple(bad[0])]}",
                             f"give finite numbers for {k} in {source} (a state MuJoCo can simulate)")


def state_name(model, keyframe, qpos):
    """How messages name the state ``load_state`` loads."""
    if keyframe is not None:
        k = str(keyframe)
        return f"keyframe '{model.key(int(k)).name or k}'" if k.isdigit() else f"keyframe '{k}'"
    if isinstance(qpos, (str, os.PathLike)):
        return f"state file {os.fspath(qpos)}"
    return "qpos" if qpos is not None else "the model's initial state"


def load_state(model, keyframe=None, qpos=None):
    """A MuJoCo state of ``model``; ``mj_forward`` is left to the caller.

    Parameters
    ----------
    model : mujoco.MjModel
        The model the state belongs to.
    keyframe : str or int, optional
        A keyframe of the model, by name or index.
    qpos : str, os.PathLike or array_like, optional
        A state file (.json or .npz: ``qpos``, optionally ``qvel``, ``ctrl``, ``act``,
        ``time`` in s; .npy or .txt: ``qpos`` alone) or the ``qpos`` vector itself. Neither: the model's initial state.

    Returns
    -------
    mujoco.MjData

    Raises
    ------
    MujocoNotInstalled
        ``mujoco`` cannot be imported.
    StateError
        Both a keyframe and ``qpos``; no such keyframe; a state file that cannot be read, has
        unknown entries, the wrong lengths or numbers that are not finite.
    """
    mujoco = require_mujoco()
    if keyframe is not None and qpos is not None:
        raise StateError("both a keyframe and a qpos file are given", "give one of them")
    data = mujoco.MjData(model)
    if keyframe is not None:
        mujoco.mj_resetDataKeyframe(model, data, keyframe_id(mujoco, model, keyframe))
    elif qpos is not None:
        state = read_state_file(qpos) if isinstance(qpos, (str, os.PathLike)) else {"qpos": qpos}
        src = os.fspath(qpos) if isinstance(qpos, (str, os.PathLike)) else "qpos"
        unknown = set(state) - {"qpos", "qvel", "ctrl", "act", "time"}
        if unknown:
            raise StateError(f"{src}: unknown entries {sorted(unknown)}", "give qpos and optionally qvel, ctrl, act, time")
        try:
            data.qpos[:] = vector(state.get("qpos"), model.nq, "qpos", src)
        except StateError as e:
            raise StateError(e.message, f"{e.fix}, in the order of its joints: {qpos_layout(mujoco, model)}") from None
        for key, n in (("qvel", model.nv), ("ctrl", model.nu), ("act", model.na)):
            if key in state:
                getattr(data, key)[:] = vector(state[key], n, key, src)
        if "time" in state:
            t = numbers(state["time"], "time", src)
            t = float(t[0]) if t.size == 1 else math.nan
            if not math.isfinite(t):
                raise StateError(f"{src}: time is not one finite number", "give a finite time")
            data.time = t
    check_finite_state(data, state_name(model, keyframe, qpos))
    return data


ROLLOUT_KEYS = ("time", "qpos", "qvel", "ctrl", "act", "qacc_warmstart", "mocap_pos", "mocap_quat")


@dataclass
class Rollout:
    """States of a MuJoCo run, one row per recorded step (SI units, MuJoCo's layouts).

    Attributes
    ----------
    time : numpy.ndarray
        Simulation times, s, shape ``(T,)``, strictly increasing.
    qpos, qvel, ctrl, act, qacc_warmstart : numpy.ndarray
        MuJoCo's state vectors per row, shapes ``(T, nq)``, ``(T, nv)``, ``(T, nu)``,
        ``(T, na)``, ``(T, nv)`` (m and rad, m/s and rad/s, the actuators' units).
    mocap_pos, mocap_quat : numpy.ndarray
        Mocap bodies' positions (m) and orientations, shapes ``(T, nmocap, 3)`` and
        ``(T, nmocap, 4)``.
    """

    time: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    ctrl: np.ndarray
    act: np.ndarray
    qacc_warmstart: np.ndarray
    mocap_pos: np.ndarray
    mocap_quat: np.ndarray

    def __len__(self):
        return len(self.time)

    @staticmethod
    def row_bytes(model):
        """Bytes of one state of ``model`` in a rollout.

        Parameters
        ----------
        model : mujoco.MjModel

        Returns
        -------
        int
        """
        return 8 * (1 + model.nq + 2 * model.nv + model.nu + model.na + 7 * model.nmocap)

    @staticmethod
    def empty(model, n):
        """A rollout of ``n`` states of ``model``, all zero, to be filled by :meth:`store`.

        Parameters
        ----------
        model : mujoco.MjModel
        n : int
            The number of states.

        Returns
        -------
        Rollout
        """
        data = require_mujoco().MjData(model)
        return Rollout(**{k: np.zeros((n, *np.shape(getattr(data, k)))) for k in ROLLOUT_KEYS})

    def store(self, i, data):
        """Puts the state of ``data`` into row ``i``.

        Parameters
        ----------
        i : int
            The row.
        data : mujoco.MjData
            The state to store.

        Returns
        -------
        None
        """
        for k in ROLLOUT_KEYS:
            getattr(self, k)[i] = getattr(data, k)

    @staticmethod
    def record(model, data):
        """The state of ``data`` as a row for :meth:`from_rows`.

        Parameters
        ----------
        model : mujoco.MjModel
        data : mujoco.MjData

        Returns
        -------
        dict
            ``{name: value}``: ``time`` (s) and copies of the state vectors.
        """
        return {k: np.array(getattr(data, k), dtype=float).copy() if k != "time" else float(data.time)
                for k in ROLLOUT_KEYS}

    @staticmethod
    def from_rows(rows):
        """A rollout of the rows of :meth:`record`.

        Parameters
        ----------
        rows : sequence of dict
            Rows as :meth:`record` returns them, in time order.

        Returns
        -------
        Rollout
        """
        return Rollout(**{k: np.array([r[k] for r in rows], dtype=float) for k in ROLLOUT_KEYS})

    def arrays(self):
        """The rollout's arrays by name (what :meth:`load` and :meth:`save` take).

        Returns
        -------
        dict of str to numpy.ndarray
        """
        return {k: getattr(self, k) for k in ROLLOUT_KEYS}

    def save(self, path):
        """Writes the rollout as .npz (the format ``--rollout`` and :meth:`load` read).

        Parameters
        ----------
        path : str or os.PathLike
            The file to write (replaced if it exists).

        Returns
        -------
        None
        """
        np.savez(path, **{k: getattr(self, k) for k in ROLLOUT_KEYS})

    @staticmethod
    def load(source, model):
        """A rollout from an .npz file or a dict of arrays.

        Parameters
        ----------
        source : str, os.PathLike or dict
            An .npz path or a dict of arrays: ``time`` (T,) in s, finite, >= 0 and strictly
            increasing, ``qpos`` (T, nq) and ``qvel`` (T, nv) required; ``ctrl``, ``act``,
            ``qacc_warmstart``, ``mocap_pos``, ``mocap_quat`` optional (the model's defaults).
        model : mujoco.MjModel
            The model the states belong to (it gives the shapes).

        Returns
        -------
        Rollout

        Raises
        ------
        StateError
            The file cannot be read; an unknown or missing array, a wrong shape, a number that is
            not finite, times that do not increase, or more states than a schedule may have.
        """
        src = os.fspath(source) if isinstance(source, (str, os.PathLike)) else "rollout"
        if isinstance(source, (str, os.PathLike)):
            raw = read_input(source, "mujoco_rollout", StateError)
            arrays = load_npz(raw, src, ROLLOUT_WHAT, MAX_ROLLOUT_BYTES, StateError, ROLLOUT_FIX)
        else:
            arrays = dict(source)
        unknown = set(arrays) - set(ROLLOUT_KEYS)
        if unknown:
            raise StateError(f"{src}: unknown arrays {sorted(unknown)}", f"give only {', '.join(ROLLOUT_KEYS)}")
        for k in ("time", "qpos", "qvel"):
            if k not in arrays:
                raise StateError(f"{src}: no '{k}' array", "give time (T,), qpos (T, nq) and qvel (T, nv)")
        time = np.asarray(arrays["time"], dtype=float).reshape(-1)
        t = len(time)
        if t == 0 or not np.all(np.isfinite(time)) or np.any(np.diff(time) <= 0) or time[0] < 0:
            raise StateError(f"{src}: time must be finite, >= 0 and strictly increasing, with at least one row",
                             "give the times of the recorded steps")
        if t > MAX_STATES:
            raise StateError(f"{src}: {t} states, more than the {MAX_STATES} a schedule may have",
                             f"give at most {MAX_STATES} states (record every K-th step)")
        data = require_mujoco().MjData(model)
        shapes = {"qpos": model.nq, "qvel": model.nv, "ctrl": model.nu, "act": model.na,
                  "qacc_warmstart": model.nv, "mocap_pos": (model.nmocap, 3), "mocap_quat": (model.nmocap, 4)}
        out = {"time": time}
        for k, shape in shapes.items():
            want = (t, *shape) if isinstance(shape, tuple) else (t, shape)
            if k in arrays:
                a = np.asarray(arrays[k], dtype=float)
                if a.shape != want:
                    raise StateError(f"{src}: '{k}' has shape {a.shape}, the model needs {want}",
                                     f"record {k} of this model at every step")
                if not np.all(np.isfinite(a)):
                    raise StateError(f"{src}: '{k}' has a NaN or an infinity", "give finite numbers")
            else:
                a = np.broadcast_to(np.array(getattr(data, k), dtype=float), want).copy()
            out[k] = a
        return Rollout(**out)

    def rows(self, index):
        """Some of the rollout's rows.

        Parameters
        ----------
        index : slice or array_like of int
            The rows to keep.

        Returns
        -------
        Rollout
        """
        return Rollout(**{k: np.asarray(getattr(self, k))[index] for k in ROLLOUT_KEYS})

    def apply(self, data, i):
        """Puts row ``i`` into ``data`` (``mj_forward`` is left to the caller).

        Parameters
        ----------
        data : mujoco.MjData
            The state to overwrite.
        i : int
            The row.

        Returns
        -------
        None
        """
        data.time = float(self.time[i])
        for k in ROLLOUT_KEYS[1:]:
            target = getattr(data, k)
            if target.size:
                target[...] = getattr(self, k)[i].reshape(target.shape)
