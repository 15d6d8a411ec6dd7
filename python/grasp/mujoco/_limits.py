"""The ranges of ``grasp.mujoco``'s arguments and of what it takes from MuJoCo, from the
project's limits (``crates/grasp-model/src/scene/limits.rs``,
``crates/grasp-transfer/src/schedule_spec.rs``, ``crates/grasp-io/src/input_file.rs``), and
the checks that name the argument (its Python name, and its option where the command has one)
and the range.
"""

import math
import numbers

from ._errors import MujocoError

# Largest force anywhere in a scene or schedule, N (MAX_FORCE_N).
MAX_FORCE_N = 1e7
# Physical range of a patch side, m (PATCH_SIDE_RANGE_M).
PATCH_SIDE_RANGE_M = (1e-9, 10.0)
# A patch's margin around MuJoCo's points, m: none, to half the largest patch side.
MARGIN_RANGE_M = (0.0, PATCH_SIDE_RANGE_M[1] / 2)
# Most elements of one patch (MAX_ELEMENTS_PER_PATCH, 2048 x 2048).
MAX_ELEMENTS_PER_PATCH = 2048 * 2048
# Most MuJoCo steps of one controller run (`steps`, `--steps`), and most `every`.
MAX_STEPS = 1_000_000
# Most states of a rollout: the most steps of a schedule (grasp-transfer's MAX_STEPS).
MAX_STATES = 1_000_000
# Most bytes of a rollout's arrays: what a rollout file may have (1 GiB).
MAX_ROLLOUT_BYTES = 1 << 30
# Most bytes of a state file's arrays: what the file may have (64 MiB).
MAX_STATE_FILE_BYTES = 64 << 20


def is_whole(x):
    return isinstance(x, numbers.Integral) and not isinstance(x, bool)


def is_real(x):
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def check_count(name, value, low, high, error=MujocoError):
    """A whole number in ``[low, high]``; ``error`` naming ``name`` otherwise."""
    if not (is_whole(value) and low <= value <= high):
        raise error(f"{name} is {value!r}, not a whole number from {low} to {high}",
                          f"give a whole number from {low} to {high}")
    return int(value)


def check_number(name, value, low, high, unit):
    """A finite number in ``[low, high]`` (``unit``); MujocoError naming ``name`` otherwise."""
    if not (is_real(value) and math.isfinite(value) and low <= value <= high):
        raise MujocoError(f"{name} is {value!r}, not a finite number from {low:g} to {high:g} {unit}",
                          f"give a number from {low:g} to {high:g} {unit}")
    return float(value)
