"""The controller of a MuJoCo run: ``MODULE:FN`` loaded, and run before every step
(``simulate``), the states recorded as a :class:`Rollout`."""

import importlib
import importlib.util
import os
from typing import TYPE_CHECKING, Callable, Optional, Union

from ._errors import ControllerError, Interrupted, StateError, require_mujoco
from ._limits import MAX_ROLLOUT_BYTES, MAX_STATES, MAX_STEPS, check_count
from ._scene import check_warnings, warning_counts
from ._state import Rollout, check_finite_state

if TYPE_CHECKING:
    import mujoco

# What a controller's errors let pass: Ctrl-C, and the signals of `python -m grasp.mujoco`.
STOPS = (KeyboardInterrupt, Interrupted)


def name_of(controller):
    """How messages name a controller: its MODULE:FN, or the function's module and name."""
    if isinstance(controller, str):
        return controller
    return f"{getattr(controller, '__module__', None) or '?'}:{getattr(controller, '__qualname__', repr(controller))}"


def failure(name, when, e):
    """The ControllerError of the controller ``name`` that raised ``e`` (``sys.exit`` too:
    it would end the command with exit 0, no message and no output)."""
    if isinstance(e, SystemExit):
        return ControllerError(f"the controller {name} called sys.exit({e.code!r}) {when}",
                               "return from the controller (it sets data.ctrl and returns); to end the run "
                               "earlier, give fewer steps (steps=, --steps)")
    return ControllerError(f"the controller {name} failed {when}: {e!r}", "fix the controller")


def import_module(module):
    """A dotted module on the path, or a .py file, imported."""
    if not module.endswith(".py"):
        return importlib.import_module(module)
    s = importlib.util.spec_from_file_location(f"grasp_mujoco_controller_{abs(hash(module))}", module)
    if s is None or not os.path.isfile(module):
        raise ImportError(f"no file {module}")
    mod = importlib.util.module_from_spec(s)
    s.loader.exec_module(mod)
    return mod


def load_controller(spec):
    """The controller function named by ``MODULE:FN``.

    Parameters
    ----------
    spec : str or callable
        ``MODULE:FN``: a dotted module on the Python path, or a .py file, and the name of a
        function ``FN(model, data)`` in it; a callable is returned as it is.

    Returns
    -------
    callable
        ``FN(model, data)``, which sets ``data.ctrl`` (and anything else) before a step.

    Raises
    ------
    ControllerError
        ``spec`` is not ``MODULE:FN``, its module cannot be imported (or exits), or it has no
        function ``FN``.
    """
    if callable(spec):
        return spec
    if not isinstance(spec, str) or ":" not in spec:
        raise ControllerError(f"controller {spec!r} is not MODULE:FN", "give e.g. examples/mujoco/handoff_controller.py:control")
    module, _, fn = spec.rpartition(":")
    try:
        mod = import_module(module)
    except STOPS:
        raise
    except SystemExit as e:
        raise failure(spec, "while its module was imported", e) from None
    except BaseException as e:
        raise ControllerError(f"cannot import the controller module {module}: {e}",
                              "give a module on the Python path or a .py file") from None
    f = getattr(mod, fn, None)
    if not callable(f):
        raise ControllerError(f"{module} has no function {fn}", "give MODULE:FN naming a function FN(model, data)")
    return f


def recorded_states(steps, every):
    """How many states ``simulate`` records: every ``every``-th of the ``steps + 1``, and the last."""
    return steps // every + 1 + (steps % every != 0)


def check_run(model, steps, every):
    """``steps`` and ``every`` in range, and the rollout they record within a rollout's limits
    (the states of a schedule, the bytes of a rollout file); StateError naming them otherwise."""
    steps = check_count("steps (--steps)", steps, 1, MAX_STEPS, StateError)
    every = check_count("every (--every)", every, 1, MAX_STEPS, StateError)
    n = recorded_states(steps, every)
    mib = n * Rollout.row_bytes(model) / (1 << 20)
    if n > MAX_STATES or mib > MAX_ROLLOUT_BYTES >> 20:
        raise StateError(f"steps {steps} (--steps) recorded every {every} (--every) give {n} states of this model "
                         f"({mib:.0f} MiB), more than a rollout may have ({MAX_STATES} states, "
                         f"{MAX_ROLLOUT_BYTES >> 20} MiB)", "record fewer states: a larger every (--every) or "
                         "fewer steps (--steps)")
    return steps, every, n


def simulate(model: "mujoco.MjModel", data: "mujoco.MjData", controller: Union[str, Callable], steps: int,
             every: int = 1, progress: Optional[Callable[[int, int], object]] = None) -> Rollout:
    """Runs MuJoCo under a controller and records the states.

    Before each step ``controller(model, data)`` sets the controls. The state (with its
    controls and the solver's warm start, so ``mj_forward`` there gives the forces ``mj_step``
    used) is recorded every ``every`` steps, the first and the last state included.

    Parameters
    ----------
    model : mujoco.MjModel
        The model to step.
    data : mujoco.MjData
        The state to start from; it is stepped in place.
    controller : str or callable
        ``MODULE:FN`` (see :func:`load_controller`) or a function ``FN(model, data)``.
    steps : int
        MuJoCo steps to run (of the model's timestep, s), in [1, 1,000,000].
    every : int, default 1
        Record every ``every``-th state (at most 1,000,000 states and 1 GiB recorded).
    progress : callable, optional
        ``progress(done, steps)``, called after each step.

    Returns
    -------
    Rollout
        The recorded states (times in s, MuJoCo's layouts).

    Raises
    ------
    MujocoNotInstalled
        ``mujoco`` cannot be imported.
    StateError
        ``steps`` or ``every`` out of range, a state that is not finite, or MuJoCo warned.
    ControllerError
        The controller cannot be loaded, raised, or called ``sys.exit``.
    TypeError
        ``progress`` is not callable.
    """
    mujoco = require_mujoco()
    steps, every, n = check_run(model, steps, every)
    if progress is not None and not callable(progress):
        raise TypeError("progress= is not callable: give a function progress(done, total), or None")
    check_finite_state(data, "data")
    fn = load_controller(controller)
    rollout, k = Rollout.empty(model, n), 0
    for i in range(steps + 1):
        try:
            fn(model, data)
        except STOPS:
            raise
        except BaseException as e:
            raise failure(name_of(controller), f"at step {i} (t = {data.time:.6g} s)", e) from None
        if i % every == 0 or i == steps:
            rollout.store(k, data)
            k += 1
        if i < steps:
            before = warning_counts(data)
            mujoco.mj_step(model, data)
            check_warnings(mujoco, data, before)
            if progress is not None:
                progress(i + 1, steps)
    return rollout

