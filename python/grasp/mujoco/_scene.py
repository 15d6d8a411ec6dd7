"""A grasp scene from a MuJoCo state: the object's weight, centre of mass and shape from the
model, one finger per (object geom, other body) pair of MuJoCo's active contacts."""

import json
import os
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
from ._errors import MujocoError, NoContactError, require_mujoco
from ._geometry import (
    HERTZ_SIDE_PER_SEMI_AXIS,
    MIN_SPREAD_M,
    RADIUS_SIDE_LIMIT,
    curvatures,
    frame_for,
    geom_type_name,
    hertz_semi_axes,
    object_shape,
    straight_length,
    surface_at,
    tip_shape,
)
from ._materials import MaterialMap, compliance
from ._patch import pad_cut_notes, patch_options, sensor_option
from ._servo import coupled_servos, finger_servo
from ._state import check_finite_state

if TYPE_CHECKING:
    import mujoco

CONTROLS = ("held", "mujoco-force", "mujoco-servo")
MODELS = ("energy", "coulomb")
# The scene format's smallest nonzero force component, N: smaller ones are written as 0.
MIN_FORCE_N = 1e-15


def clean_force(x):
    """A force (component) as the scene format takes it: 0, or at least 1e-15 N in magnitude."""
    return 0.0 if abs(x) < MIN_FORCE_N else float(x)


def check_choice(name, value, choices):
    if value not in choices:
        raise MujocoError(f"{name} is {value!r}", f"give one of {', '.join(choices)}")


@dataclass
class MujocoFinger:
    """One finger as MuJoCo sees it (world frame, N, m).

    Attributes
    ----------
    name : str
        The scene's finger name.
    body : str
        MuJoCo's body that touches the object.
    object_geom : str
        The object's geom it touches.
    geoms : list of str
        The body's geoms in contact.
    contact_count : int
        MuJoCo's contacts of the finger.
    normal_force_n : float
        MuJoCo's total normal force, N.
    friction_force_n : numpy.ndarray
        MuJoCo's total friction force, world frame, N, shape ``(3,)``.
    center_of_pressure_m : numpy.ndarray
        The centre of MuJoCo's normal forces, m, shape ``(3,)``.
    normal : numpy.ndarray
        The unit contact normal into the object, shape ``(3,)``.
    mu : float
        MuJoCo's combined sliding friction coefficient.
    slip_speed_m_per_s : float
        The fastest relative sliding speed of the finger's contacts, m/s.
    points_m : numpy.ndarray
        MuJoCo's contact points, m, shape ``(contact_count, 3)``.
    """

    name: str
    body: str
    object_geom: str
    geoms: list
    contact_count: int
    normal_force_n: float
    friction_force_n: np.ndarray
    center_of_pressure_m: np.ndarray
    normal: np.ndarray
    mu: float
    slip_speed_m_per_s: float
    points_m: np.ndarray

    @property
    def friction_utilisation(self):
        """|Q| / (mu P) of MuJoCo's forces (dimensionless; NaN without friction or load)."""
        denom = self.mu * self.normal_force_n
        return float(np.linalg.norm(self.friction_force_n) / denom) if denom > 0 else float("nan")

    def to_dict(self):
        """The finger as a dict of JSON values (the ``mujoco`` side of a report's row).

        Returns
        -------
        dict
        """
        return {
            "name": self.name, "body": self.body, "object_geom": self.object_geom, "geoms": self.geoms,
            "contacts": self.contact_count, "normal_force_n": self.normal_force_n,
            "friction_force_n": self.friction_force_n.tolist(),
            "friction_magnitude_n": float(np.linalg.norm(self.friction_force_n)),
            "mu": self.mu, "friction_utilisation": self.friction_utilisation,
            "center_of_pressure_m": self.center_of_pressure_m.tolist(), "normal": self.normal.tolist(),
            "slip_speed_m_per_s": self.slip_speed_m_per_s, "points_m": self.points_m.tolist(),
        }


def finger_spec(mujoco, model, data, fl, name, materials, opts, hertz_load_n, control, exact):
    """The scene finger of one (object geom, other body) group (world frame of ``data``), and
    notes on approximations; ``exact``: the scene has exact gaps (its object has a shape), so a
    box, cylinder or capsule fingertip is written as ``tip.shape``."""
    notes = []
    n = fl.normal
    cop = fl.center_of_pressure_m
    tip_geom = fl.main_other_geom
    if control == "mujoco-servo":
        # The patch is sized for the most the servo can push, k x (the elastic contact settles
        # at less overlap than MuJoCo's soft one, so it squeezes harder than MuJoCo's force).
        overlap = max(-c.dist_m for c in fl.contacts)
        bound = finger_servo(mujoco, model, data, fl.other_body, cop, n, overlap, name, 0.0)
        hertz_load_n = max(hertz_load_n, bound.stiffness_n_per_m * max(bound.approach_m, 0.0))
    obj = surface_at(mujoco, model, data, fl.object_geom, cop, -n)
    tip = surface_at(mujoco, model, data, tip_geom, cop, n)
    notes += [s.note for s in (obj, tip) if s.note]
    t1, t2 = frame_for(n, obj, tip, fl.contacts[0].tangent)
    k_obj = curvatures(obj, t1, t2, f"finger {name}")
    k_tip = curvatures(tip, t1, t2, f"finger {name}")
    k = k_obj + k_tip
    mat_f = materials.of_geom(tip_geom)
    mat_o = materials.of_geom(fl.object_geom)
    inv_e = compliance(mat_f) + compliance(mat_o)
    # The contact points' spread in the tangent plane, about the centre of pressure.
    rel = np.array([c.point_m - cop for c in fl.contacts])
    uv = np.stack([rel @ t1, rel @ t2], axis=1)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    spread = hi - lo
    margin = opts["margin_m"]
    axes = (t1, t2)
    lengths = []
    for d in range(2):
        known = [x for x in (straight_length(tip, axes[d]), straight_length(obj, axes[d])) if x]
        lengths.append(min(known) if known else None)
    point = cop.copy()
    if opts["size"] is not None:
        size = list(opts["size"])
    elif not k.any():
        # A flat pair: the patch covers the points' spread (MuJoCo's box-box points are the
        # corners of the overlap, so this is the pad on the face) plus the margin, centred on
        # it; where the points do not spread, the pad's side.
        size = []
        for d in range(2):
            if spread[d] >= MIN_SPREAD_M:
                size.append(float(spread[d] + 2 * margin))
                point = point + axes[d] * (0.5 * (lo[d] + hi[d]))
            elif lengths[d]:
                size.append(float(lengths[d] + 2 * margin))
                notes.append(f"finger {name}: MuJoCo's points do not spread along t{d + 1}; the patch takes the pad's side")
            elif margin > 0:
                size.append(2 * margin)
            else:
                raise MujocoError(
                    f"finger {name}: a flat contact whose points do not spread along t{d + 1} and no pad side to take",
                    "give patch={'margin_m': m} or patch={'size': [a, b]}")
    else:
        if inv_e <= 0:
            raise MujocoError(f"finger {name}: both bodies are rigid in the material map",
                              "give the finger or the object an elastic material")
        for d in range(2):
            if k[d] == 0 and lengths[d] is None:
                lengths[d] = float(spread[d] + 2 * margin) if spread[d] + 2 * margin >= MIN_SPREAD_M else None
        if any(k[d] == 0 and lengths[d] is None for d in range(2)):
            raise MujocoError(f"finger {name}: a line contact whose length is unknown",
                              "give patch={'size': [a, b]} or a margin")
        semi = hertz_semi_axes(hertz_load_n, k, 1.0 / inv_e, lengths)
        size = [HERTZ_SIDE_PER_SEMI_AXIS * semi[d] if semi[d] is not None else lengths[d] for d in range(2)]
        size = [max(s, float(spread[d] + 2 * margin)) for d, s in enumerate(size)]
    # The scene's limits: a radius at least half the patch side along it; a flat pad at least
    # as large as the patch.
    for d in range(2):
        limits = [1.0 / kk[d] for kk in (k_obj, k_tip) if kk[d] > 0]
        if tip.kind == "sphere":
            limits.append(tip.radius_m)
        for r in limits:
            if size[d] > 2 * r * RADIUS_SIDE_LIMIT:
                notes.append(f"finger {name}: patch side along t{d + 1} cut to the radius {r:.4g} m allows")
                size[d] = 2 * r * RADIUS_SIDE_LIMIT
    spec = {"name": name, "contact_point": point.tolist(), "normal": n.tolist(), "tangent": t1.tolist()}
    spec["material"] = mat_f
    if tip.box is not None:
        pad = [straight_length(tip, a) for a in axes]
        notes += pad_cut_notes(name, size, pad, opts)
        size = [min(size[d], pad[d]) for d in range(2)]
    # With exact gaps (the object has a shape) a box, cylinder or capsule fingertip is the solid
    # as MuJoCo poses it: a pad's real edges, wherever MuJoCo's points lie on it.
    posed = tip_shape(mujoco, model, data, tip_geom, point, n, f"finger {name}") if exact else None
    if posed is not None:
        spec["tip"] = {"shape": posed[0]}
    elif tip.kind == "sphere":
        spec["tip"] = {"sphere": {"radius": tip.radius_m}}
    elif tip.kind == "cylinder":
        spec["tip"] = {"cylinder": {"radius": tip.radius_m, "axis": (t2 if k_tip[0] > 0 else t1).tolist()}}
    elif tip.box is not None:
        spec["tip"] = {"flat": {"size": pad}}
    if obj.kind == "sphere":
        spec["object_radius"] = obj.radius_m
    elif obj.kind == "cylinder":
        spec["object_radius"] = [1 / k_obj[0] if k_obj[0] > 0 else None, 1 / k_obj[1] if k_obj[1] > 0 else None]
    spec["patch"] = {"size": [float(s) for s in size], "grid": list(opts["grid"])}
    mus = sorted({c.mu for c in fl.contacts})
    if len(mus) > 1:
        notes.append(f"finger {name}: MuJoCo's contacts have friction {mus}; the scene takes the smallest")
    spec["friction"] = {"mu": float(mus[0])}
    if control == "held":
        spec["control"] = "held"
    elif control == "mujoco-servo":
        overlap = posed[1] if posed is not None else max(-c.dist_m for c in fl.contacts)
        half_side = 0.5 * max(float(x) for x in size)
        servo = finger_servo(mujoco, model, data, fl.other_body, point, n, overlap, name, half_side, t1)
        spec["control"] = {"approach_m": servo.approach_m}
        if servo.mount() is not None:
            spec["mount"] = servo.mount()
        if servo.tendon_mark() is not None:
            spec["_tendon"] = servo.tendon_mark()
    else:
        spec["control"] = {"normal_load": clean_force(max(fl.normal_force_n, 0.0))}
    if opts.get("sensor") is not None:
        spec["sensor"] = json.loads(json.dumps(opts["sensor"]))
    return spec, notes, mat_o


def couple_as_forces(torque, center, arm_m):
    """A couple as two opposite forces at ``center +- arm u`` (u across the couple)."""
    m = np.linalg.norm(torque)
    u = np.eye(3)[int(np.argmin(np.abs(torque)))]
    u = u - (u @ torque) / m**2 * torque
    u = u / np.linalg.norm(u)
    f = np.cross(torque, u) / (2 * arm_m)
    return [{"force": [clean_force(x) for x in f], "at": (center + arm_m * u).tolist()},
            {"force": [clean_force(-x) for x in f], "at": (center - arm_m * u).tolist()}]


@dataclass
class MujocoGrasp:
    """A grasp scene made from a MuJoCo state, with MuJoCo's side of it.

    Attributes
    ----------
    scene_dict : dict
        The scene format (SI units); :attr:`scene` validates it.
    fingers : list of MujocoFinger
        MuJoCo's forces per finger, scene order.
    weight_n : float
        The object's weight, N.
    center_of_mass_m : numpy.ndarray
        The object's centre of mass, m, shape ``(3,)``.
    gravity : numpy.ndarray
        MuJoCo's gravity, m/s^2, shape ``(3,)``.
    unbalanced_force_n, unbalanced_torque_nm : numpy.ndarray
        What MuJoCo's contact forces leave unbalanced on the object, N and N m.
    object_speed_m_per_s : float
        The object's speed at the state, m/s.
    inertial_force_n : numpy.ndarray
        ``m a`` of the object from MuJoCo's accelerations, N.
    control : str
        ``"mujoco-force"`` or ``"held"``: how the scene's fingers are controlled.
    warnings : list of str
        The approximations made.
    files : dict
        Extra files beside the scene (a mesh's OBJ), by name.
    mujoco_version : str
        The version of MuJoCo that made it.
    """

    scene_dict: dict
    fingers: list
    weight_n: float
    center_of_mass_m: np.ndarray
    gravity: np.ndarray
    unbalanced_force_n: np.ndarray
    unbalanced_torque_nm: np.ndarray
    object_speed_m_per_s: float
    inertial_force_n: np.ndarray  # m a of the object from MuJoCo's accelerations
    control: str
    warnings: list = field(default_factory=list)
    files: dict = field(default_factory=dict)  # extra files beside the scene (a mesh's OBJ)
    mujoco_version: str = ""
    _scene: object = None

    @property
    def scene(self):
        """The scene as a :class:`grasp.Scene` (validated)."""
        if self._scene is None:
            self._scene = load_scene(self.scene_dict, self.files)
        return self._scene

    @property
    def finger_names(self):
        """The scene's finger names, scene order."""
        return [f.name for f in self.fingers]

    def to_json(self):
        """The scene as JSON text.

        Returns
        -------
        str
        """
        return json.dumps(self.scene_dict, indent=2) + "\n"

    def outputs(self, path):
        """The files :meth:`write` writes.

        Parameters
        ----------
        path : str or os.PathLike
            The scene file.

        Returns
        -------
        dict of str to str
            ``{path: text}`` of the scene file and a mesh beside it.
        """
        folder = os.path.dirname(os.path.abspath(path))
        outs = {os.fspath(path): self.to_json()}
        for name, text in self.files.items():
            outs[os.path.join(folder, name)] = text
        return outs

    def write(self, path, overwrite=False):
        """Writes the scene (and a mesh beside it), all or nothing.

        Parameters
        ----------
        path : str or os.PathLike
            The scene file; its folder must exist.
        overwrite : bool, default False
            Replace existing files.

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
        from ._files import write_all

        self.scene  # validated before anything is written
        return write_all(self.outputs(path), overwrite=overwrite)


def load_scene(scene_dict, files):
    """A grasp.Scene from a dict, its extra files written to a temporary folder first."""
    import grasp

    if not files:
        return grasp.Scene(scene_dict)
    with tempfile.TemporaryDirectory(prefix="grasp-mujoco-") as tmp:
        for name, text in files.items():
            with open(os.path.join(tmp, name), "w", encoding="utf-8") as f:
                f.write(text)
        path = os.path.join(tmp, "scene.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(scene_dict, f)
        return grasp.Scene(path)


def object_geoms(model, b):
    """The object's collision geoms."""
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] == b
            and (model.geom_contype[g] or model.geom_conaffinity[g])]


def object_part(mujoco, model, data, b, warnings, mesh_name):
    """Weight (N), centre of mass (m), gravity direction and shape of body ``b``."""
    g = np.array(model.opt.gravity, dtype=float)
    g_norm = float(np.linalg.norm(g))
    weight = float(model.body_mass[b]) * g_norm
    com = np.array(data.xipos[b], dtype=float)
    gravity = g / g_norm if g_norm > 0 else np.array([0.0, 0.0, -1.0])
    children = [i for i in range(model.nbody) if i != b and model.body_parentid[i] == b]
    if children:
        warnings.append(f"body '{model.body(b).name}' has child bodies ({len(children)}): the object is the "
                        "body alone (its own mass, centre of mass and contacts)")
    shape, files, geoms = None, {}, object_geoms(model, b)
    if len(geoms) == 1:
        shape, obj_text, why = object_shape(mujoco, model, data, geoms[0])
        if shape is None:
            warnings.append(f"the object's geom is not drawn: {why}")
        elif obj_text is not None:
            shape["mesh"]["file"] = mesh_name
            files[mesh_name] = obj_text
    elif len(geoms) > 1:
        warnings.append(f"the object has {len(geoms)} collision geoms: the scene has no shape (pictures draw "
                        "the box around the contacts)")
    return weight, com, gravity, shape, files


def build(mujoco, model, data, b, materials, opts, control, contact_model, description, mesh_name):
    """The MujocoGrasp at the state of ``data`` (``mj_forward`` done)."""
    warnings = []
    contacts = object_contacts(mujoco, model, data, b)
    body_name = model.body(b).name
    if not contacts:
        raise NoContactError(
            f"body '{body_name}' has no active contact with another body at this state",
            "give a state where the object is grasped (--keyframe, --qpos), or the grasped object's body")
    weight, com, gravity, shape, files = object_part(mujoco, model, data, b, warnings, mesh_name)
    groups = group_fingers(contacts)
    names = finger_names(model, [fl.key for fl in groups])
    check_forces(groups, names)
    speeds = slip_speeds_m_per_s(mujoco, model, data, contacts)
    speed_of = {c.index: s for c, s in zip(contacts, speeds)}
    fingers, specs, obj_mats = [], [], []
    for fl in groups:
        name = names[fl.key]
        load = fl.normal_force_n if fl.normal_force_n > 0 else max(weight, 1.0)
        spec, notes, mat_o = finger_spec(mujoco, model, data, fl, name, materials, opts, load, control,
                                         exact=shape is not None)
        warnings += notes
        specs.append(spec)
        obj_mats.append(mat_o)
        fingers.append(mujoco_finger(model, fl, name, max(speed_of[c.index] for c in fl.contacts)))
    obj_mat = obj_mats[int(np.argmax([f.normal_force_n for f in fingers]))]
    if any(m != obj_mat for m in obj_mats):
        warnings.append("the object's geoms have different materials: the scene takes the one of the most loaded contact")
    force, torque = contact_wrench(contacts, com)
    unbalanced_f = force + weight * gravity
    obj = {"weight": weight, "center_of_mass": com.tolist(), "gravity": gravity.tolist(), "material": obj_mat}
    if shape is not None:
        obj["shape"] = shape
    # MuJoCo's contacts and weight leave the object's inertia (m a) and the solver's residual
    # unbalanced; the scene applies what MuJoCo's contacts carried beyond the weight, so the
    # elastic model balances exactly their load.
    external = []
    if any(clean_force(x) for x in unbalanced_f):
        external.append({"force": [clean_force(-x) for x in unbalanced_f], "at": com.tolist()})
    if np.linalg.norm(torque) > MIN_FORCE_N:
        arm = max([float(np.linalg.norm(c.point_m - com)) for c in contacts] + [1e-3])
        external += couple_as_forces(-torque, com, arm)
    if external:
        obj["external_forces"] = external
    warn = materials.warning()
    if warn:
        warnings.insert(0, warn)
    scene = {"description": description, "object": obj, "fingers": specs, "model": contact_model}
    servos = coupled_servos(specs)
    if servos:
        scene["servos"] = servos
    v = np.zeros(6)
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, b, v, 0)
    return MujocoGrasp(inertial_force_n=inertial_force_n(mujoco, model, data, b),
        scene_dict=scene, fingers=fingers, weight_n=weight, center_of_mass_m=com, gravity=gravity,
        unbalanced_force_n=unbalanced_f, unbalanced_torque_nm=torque, object_speed_m_per_s=float(np.linalg.norm(v[3:])),
        control=control, warnings=warnings, files=files, mujoco_version=mujoco.__version__)


def inertial_force_n(mujoco, model, data, b):
    """``m a`` of body ``b`` at its centre of mass from MuJoCo's accelerations (``cacc`` holds
    ``a - g``: MuJoCo puts gravity in as the world's acceleration)."""
    mujoco.mj_rnePostConstraint(model, data)
    acc = np.zeros(6)
    mujoco.mj_objectAcceleration(model, data, mujoco.mjtObj.mjOBJ_BODY, b, acc, 0)
    return float(model.body_mass[b]) * (acc[3:] + np.array(model.opt.gravity, dtype=float))


def mujoco_finger(model, fl, name, slip_speed):
    geoms = sorted({model.geom(c.other_geom).name or f"geom{c.other_geom}" for c in fl.contacts})
    return MujocoFinger(
        name=name, body=model.body(fl.other_body).name or f"body{fl.other_body}",
        object_geom=model.geom(fl.object_geom).name or f"geom{fl.object_geom}", geoms=geoms,
        contact_count=len(fl.contacts), normal_force_n=fl.normal_force_n, friction_force_n=fl.friction_force_n,
        center_of_pressure_m=fl.center_of_pressure_m, normal=fl.normal, mu=min(c.mu for c in fl.contacts),
        slip_speed_m_per_s=slip_speed, points_m=np.array([c.point_m for c in fl.contacts]))


def scene_from(model: "mujoco.MjModel", data: "mujoco.MjData", object_body: Union[str, int],
               materials: Union[None, dict, str, "os.PathLike[str]"] = None, patch: Optional[dict] = None,
               control: str = "mujoco-force", contact_model: str = "energy", description: Optional[str] = None,
               mesh_name: Optional[str] = None, sensor: Optional[dict] = None) -> "MujocoGrasp":
    """A grasp scene from a MuJoCo state.

    Runs ``mj_forward`` at the state of ``data``, takes every active contact between
    ``object_body`` and another body, and makes one finger per (object geom, other body) pair:
    its contact point the centre of pressure of MuJoCo's normal forces (a flat pair: the centre
    of the points' spread, which is the pad), its normal the common contact normal into the
    object, its patch the points' spread plus ``patch["margin_m"]`` (flat pairs) or 2.4 Hertz
    semi-axes at MuJoCo's normal force (curved pairs), its friction MuJoCo's combined sliding
    friction. The object's weight is ``body_mass |gravity|`` at its centre of mass
    (``data.xipos``), its shape its geom's (box, sphere, cylinder, capsule, mesh). With that
    shape (exact gaps) a box, cylinder or capsule fingertip geom is the scene's ``tip.shape``:
    the solid as MuJoCo poses it, moved back out of the object along the normal by MuJoCo's
    overlap; without it a box is a flat pad of its size. A sphere is ``tip.sphere``; a mesh is
    taken flat.

    Parameters
    ----------
    model : mujoco.MjModel
    data : mujoco.MjData
        The state (``mj_forward`` is run on it).
    object_body : str or int
        The grasped body, by name or id (a free body with mass).
    materials : dict, str or os.PathLike, optional
        ``{geom or body name: material}`` (a dict or a JSON file; moduli in Pa); unnamed geoms
        get the default (rubber) with a warning.
    patch : dict, optional
        ``{"grid": [nx, ny], "margin_m": m, "size": [a, b]}`` (sizes in m).
    control : {"mujoco-force", "held", "mujoco-servo"}, default "mujoco-force"
        Each finger force-controlled at MuJoCo's normal force, held in place, or on its servo:
        a jaw on one slide joint along the contact normal, its position actuators' ``kp`` and
        the joint's stiffness the finger's ``mount`` (``K_q / J_n^2``, N/m) and the position
        their force at the state commands its ``approach_m`` (docs/guide/mujoco.md, "Servo
        jaws").
    contact_model : {"energy", "coulomb"}, default "energy"
        The scene's contact model.
    description : str, optional
        The scene's description.
    mesh_name : str, optional
        The file name of an object mesh written beside the scene.
    sensor : dict, optional
        A tactile sensor given to every finger's pad (the scene's ``fingers[i].sensor``:
        ``{"taxels": ..., "markers": ..., "gel": ...}``, docs/guide/tactile.md); its readings
        come with the scene's solution (``Solution.sensor(finger)``).

    Returns
    -------
    MujocoGrasp

    Raises
    ------
    MujocoNotInstalled
        ``mujoco`` cannot be imported.
    UnknownBodyError
        ``object_body`` is not a body that can be grasped.
    NoContactError
        The body touches nothing at the state.
    MaterialMapError
        The material map names what the model lacks, or is malformed.
    ContactGeometryError
        A contact whose geometry the model cannot represent.
    StateError
        MuJoCo warned at the state.
    MujocoError
        Another option out of range (its message names it and the fix).
    """
    mujoco = require_mujoco()
    check_choice("control", control, CONTROLS)
    check_choice("contact_model", contact_model, MODELS)
    opts = patch_options(patch)
    opts["sensor"] = sensor_option(sensor)
    b = object_body_id(mujoco, model, object_body)
    mats = MaterialMap(mujoco, model, materials)
    check_finite_state(data, "data")
    before = warning_counts(data)
    mujoco.mj_forward(model, data)
    check_warnings(mujoco, data, before)
    desc = description or (f"From MuJoCo {mujoco.__version__}: body '{model.body(b).name}' at t = {data.time:.6g} s; "
                           f"fingers {control}.")
    return build(mujoco, model, data, b, mats, opts, control, contact_model, desc,
                 mesh_name or f"{model.body(b).name or 'object'}.obj")


def warning_counts(data):
    return [int(w.number) for w in data.warning]


def check_warnings(mujoco, data, before):
    """StateError when MuJoCo warned while computing the state (bad qacc, contact overflow...)."""
    from ._errors import StateError

    bad = []
    for i, (w, n0) in enumerate(zip(data.warning, before)):
        if w.number > n0:
            bad.append(f"{mujoco.mjtWarning(i).name} (info {w.lastinfo})")
    if bad:
        raise StateError(f"MuJoCo warned at this state: {', '.join(bad)}",
                         "give a state the model can simulate (check the qpos, the keyframe, contact limits)")


__all__ = ["scene_from", "MujocoGrasp", "MujocoFinger", "geom_type_name"]
