"""Type stubs of the native module (``grasp._native``); see the package docstring."""

import os
from typing import Any, Callable, Dict, Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_TOLERANCE: float

Model = Literal["energy", "coulomb"]
SolverName = Literal["auto", "native", "clarabel"]
ComplianceName = Literal["auto", "dense", "fft"]
McapProfileName = Literal["json", "ros2"]
Source = Union[str, "os.PathLike[str]", dict[str, Any]]

class SceneError(ValueError):
    """A scene that cannot be used; ``problems``: list of {path, message, fix}."""

    problems: list[dict[str, str]]

class ScheduleError(ValueError):
    """A load schedule that cannot be used; ``problems``: list of {path, message, fix}."""

    problems: list[dict[str, str]]

class GraspError(RuntimeError):
    """A refused request that is not a scene or schedule problem. Raised by :func:`plan` when
    the best schedule found does not keep every constraint, it carries the report (``met``
    False, ``binding``) as ``report``."""

    report: Dict[str, Any]

class Scene:
    """A validated grasp scene (SI units). ``Scene(source)``: a path, a dict, or JSON text."""

    def __init__(self, source: Source) -> None: ...
    @staticmethod
    def from_file(path: Union[str, "os.PathLike[str]"]) -> "Scene": ...
    @staticmethod
    def from_json(text: str) -> "Scene": ...
    @staticmethod
    def from_dict(d: dict[str, Any]) -> "Scene":
        """The scene of a dict. A finger's texture heights may be a NumPy array instead of a
        file: ``"texture": {"heights": {"array": a, "pixel_m": [dx, dy]}}`` (heights in
        metres, rows of ``a`` along ``t1``, its centre on the contact point); ``to_dict()``
        then shows ``"file": "<array>"`` in its place."""
    @property
    def finger_names(self) -> list[str]: ...
    @property
    def model(self) -> Model: ...
    @property
    def planar(self) -> bool: ...
    @property
    def origin(self) -> str: ...
    @property
    def shape_report(self) -> Optional[dict[str, Any]]:
        """Derived finger frames (m, 1/m), volume (m^3), mass (kg), warnings; None without a shape."""
    @property
    def warnings(self) -> list[str]: ...
    def texture_heights_m(self, finger: Union[str, int]) -> Optional[npt.NDArray[np.float64]]:
        """The texture heights (m, a peak positive) of a finger at its patch's element centres,
        shape ``(nx, ny)``, rows along ``t1``; None without a texture."""
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self) -> str: ...

class Solution:
    """The answer of one solve; element arrays over all fingers, scene order."""

    @property
    def status(self) -> Literal["solved", "reduced_accuracy", "no_equilibrium", "no_convergence"]: ...
    @property
    def has_forces(self) -> bool: ...
    @property
    def reason(self) -> Optional[str]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def finger_names(self) -> list[str]: ...
    @property
    def fingers(self) -> list[dict[str, Any]]:
        """Per-finger resultants (N, N m, m, m^2), the CLI's JSON fields without elements."""
    @property
    def finger_normal_forces_n(self) -> npt.NDArray[np.float64]:
        """Finger normal forces P_i, N, shape (F,)."""
    @property
    def residuals(self) -> Optional[dict[str, float]]: ...
    @property
    def solver(self) -> dict[str, Any]: ...
    @property
    def sequential(self) -> Optional[dict[str, Any]]: ...
    @property
    def hands(self) -> list[dict[str, Any]]: ...
    @property
    def servos(self) -> list[dict[str, Any]]: ...
    @property
    def load_scale_n(self) -> float: ...
    @property
    def solve_time_s(self) -> float: ...
    @property
    def build_time_s(self) -> float: ...
    @property
    def finger(self) -> npt.NDArray[np.int64]:
        """Index into finger_names of each element, shape (N,)."""
    @property
    def positions_m(self) -> npt.NDArray[np.float64]:
        """Element centres, world frame, m, shape (N, 3)."""
    @property
    def normal_forces_n(self) -> npt.NDArray[np.float64]:
        """Element normal forces F_k, N, shape (N,)."""
    @property
    def tangential_forces_n(self) -> npt.NDArray[np.float64]:
        """Element friction forces G_k, world frame, N, shape (N, 3)."""
    @property
    def tangential_forces_local_n(self) -> npt.NDArray[np.float64]:
        """Element friction forces along [t1, t2], N, shape (N, 2)."""
    @property
    def pressures_pa(self) -> npt.NDArray[np.float64]: ...
    @property
    def gaps_m(self) -> npt.NDArray[np.float64]: ...
    @property
    def slips_m(self) -> npt.NDArray[np.float64]: ...
    @property
    def states(self) -> npt.NDArray[np.str_]:
        """"stick", "slip", "separated", "off_surface" or "frictionless" (in contact on a
        frictionless finger: neither stick nor slip), shape (N,)."""
    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``grasp solve --json``, as a dict."""
    def to_json(self) -> str: ...
    def element_fields(self, finger: str) -> dict[str, npt.NDArray[Any]]:
        """One finger's element fields by name, the arrays of ``grasp solve --npz``."""
    def to_npz(self, path: Union[str, "os.PathLike[str]"], *, overwrite: bool = False) -> None:
        """Writes every finger's element fields as ``grasp solve --npz`` does."""
    def sensor(self, finger: str) -> dict[str, dict[str, Any]]:
        """A finger's tactile readings: ``{"taxels": {"force_n": (nx, ny, 3), "centre_m":
        (nx, ny, 2), "depth_m", "size_m"}, "markers": {"displacement_m": (nx, ny, 3),
        "position_m": (nx, ny, 2)}, "gel": {"height_m": (nx, ny), "normal": (nx, ny, 3),
        "rgb": (nx, ny, 3), "position_m": (nx, ny, 2), "pixel_m", "path"}}``, each kind when the
        sensor has it."""

class Transfer:
    """A hand-off's force histories, time x finger (SI units)."""

    @property
    def finger_names(self) -> list[str]: ...
    @property
    def times_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def normal_forces_n(self) -> npt.NDArray[np.float64]:
        """Finger normal forces P_i, N, shape (T, F)."""
    @property
    def tangential_forces_n(self) -> npt.NDArray[np.float64]:
        """Finger friction forces Q_i, world frame, N, shape (T, F, 3)."""
    @property
    def commanded_loads_n(self) -> npt.NDArray[np.float64]:
        """Commanded normal loads, N, (T, F): NaN held, 0 released."""
    @property
    def external_forces_n(self) -> npt.NDArray[np.float64]: ...
    @property
    def statuses(self) -> npt.NDArray[np.str_]: ...
    @property
    def wall_times_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def iterations(self) -> npt.NDArray[np.int64]: ...
    @property
    def smallest_margins_n(self) -> npt.NDArray[np.float64]: ...
    def sensor_history(self, finger: str) -> dict[str, dict[str, npt.NDArray[np.float64]]]:
        """A finger's tactile readings at every step: ``{"taxels": {"force_n": (T, nx, ny,
        3)}, "markers": {"displacement_m": (T, nx, ny, 3)}, "gel": {"height_m": (T, nx, ny),
        "rgb": (T, nx, ny, 3)}}``, NaN where it has none."""
    @property
    def summary(self) -> dict[str, Any]: ...
    @property
    def warnings(self) -> list[dict[str, Any]]:
        """The warnings of the run's solves, each once: ``message``, ``count``, ``steps`` (runs
        ``{"first": i, "last": j}`` of step indices), ``first_time_s``, ``last_time_s``."""
    @property
    def written(self) -> list[str]: ...
    def step(self, index: int) -> Solution:
        """The full solution of a step (only the last one with keep_solutions=False)."""
    def __len__(self) -> int: ...

def solve(
    scene: Scene,
    *,
    model: Optional[Model] = None,
    solver: SolverName = "auto",
    tolerance: float = 1e-10,
    compliance: ComplianceName = "auto",
    at_time: Optional[float] = None,
    long_term: bool = False,
) -> Solution:
    """Solves one grasp (GIL released); see the package docstring. A viscoelastic scene is
    answered at t = 0+ (its instantaneous response), ``at_time`` seconds after its loads were
    applied as a step, or fully relaxed (``long_term=True``)."""

def transfer(
    scene: Scene,
    schedule: Source,
    *,
    mcap: Optional[Union[str, "os.PathLike[str]"]] = None,
    rrd: Optional[Union[str, "os.PathLike[str]"]] = None,
    csv: Optional[Union[str, "os.PathLike[str]"]] = None,
    npz: Optional[Union[str, "os.PathLike[str]"]] = None,
    mcap_profile: McapProfileName = "json",
    ros2_start_time: Optional[float] = None,
    solver: SolverName = "auto",
    cold: bool = False,
    keep_going: bool = False,
    margins: bool = False,
    overwrite: bool = False,
    keep_solutions: bool = True,
    max_memory: Optional[int] = None,
    compliance: ComplianceName = "auto",
    progress: Optional[Callable[[int, int], object]] = None,
) -> Transfer:
    """Runs a hand-off schedule (GIL released), writing the CLI's files; see the package docstring.
    ``progress(done, total)`` is called after each step; an exception it raises (or Ctrl-C) stops
    the run between steps."""

def plan(
    scene: Scene,
    *,
    releasing: Sequence[str],
    receiving: Sequence[str] = (),
    template: Optional[Source] = None,
    min_slip_margin: float = 0.0,
    min_margin: Optional[float] = None,
    min_load: float = 0.0,
    max_load: Optional[float] = None,
    max_rate: Optional[float] = None,
    max_speed: Optional[float] = None,
    open_to: Optional[float] = None,
    close_to: Optional[float] = None,
    min_approach: Optional[float] = None,
    max_approach: Optional[float] = None,
    min_duration: float = 0.0,
    max_duration: Optional[float] = None,
    duration: Optional[float] = None,
    objective: Literal["duration", "margin"] = "duration",
    steps: Optional[int] = None,
    keyframes: int = 5,
    max_runs: int = 30,
    solver: SolverName = "auto",
    compliance: ComplianceName = "auto",
) -> Dict[str, Any]:
    """Plans a hand-off's load ramps (GIL released), as ``grasp plan`` does: the report of a
    schedule that keeps every constraint, as a dict with ``met``, ``schedule`` (runs unchanged
    in :func:`transfer`), ``margins``, ``template_margins``, ``slip_margin_rule``,
    ``smallest_not_counted``, ``checked``, ``warnings`` (the checked run's, each once with
    its steps), ``duration_s``, ``loads_n``, ``approaches_m``, ``runs`` and ``time_s``.
    Loads N, rates N/s, approaches m (position-controlled fingers: a servo's jaws opened to let
    go), speeds m/s, times s. Raises :class:`GraspError` for constraints no schedule can meet, naming
    the one that binds, and when the best schedule found does not keep every constraint (as
    ``grasp plan`` writes none): then its ``report`` attribute holds the report, ``binding``
    and all; ``ValueError`` for arguments out of range, ``TypeError`` for a bool or str given
    for a number or a str for a list of finger names."""

# For the pure-Python readers and writers of the package (grasp.mujoco): the project's file
# policy (grasp-io). `kind`: "mujoco_model", "mujoco_state", "mujoco_rollout", "material_map".
def _read_input(path: Union[str, "os.PathLike[str]"], kind: str) -> bytes:
    """The whole regular file within its kind's limit; OSError with `message` and `fix`."""

def _check_input(path: Union[str, "os.PathLike[str]"], kind: str) -> None:
    """Checks a regular file within its kind's limit without reading it."""

def _check_outputs(
    targets: list[Union[str, "os.PathLike[str]"]],
    *,
    overwrite: bool = False,
    inputs: list[Union[str, "os.PathLike[str]"]] = ...,
    force_name: str = "overwrite=True",
) -> None:
    """Checks the targets against the output policy and tries their locks."""

def _write_outputs(
    contents: list[tuple[Union[str, "os.PathLike[str]"], bytes]],
    *,
    overwrite: bool = False,
    inputs: list[Union[str, "os.PathLike[str]"]] = ...,
    force_name: str = "overwrite=True",
) -> None:
    """Writes every (path, bytes) through the output policy, all moved into place together."""

def _arrow_scale_m_per_n(scene: Scene) -> float:
    """The force arrows' scale of the scene's recordings, m per N (grasp.mujoco's drawings)."""
