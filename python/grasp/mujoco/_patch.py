"""The patch options of ``scene_from`` and ``schedule_from_rollout`` (``--grid``, ``--margin``,
``--patch-size``): checked against the scene's ranges, and the warning where a patch is cut to a
box pad's size; and the tactile sensor given to every pad (``--sensor``)."""

import json
from collections.abc import Mapping

from ._errors import MujocoError
from ._limits import MARGIN_RANGE_M, MAX_ELEMENTS_PER_PATCH, PATCH_SIDE_RANGE_M, check_count, check_number

DEFAULT_GRID = [9, 9]
# A patch side longer than the pad's by more than this fraction is cut, with a warning (less is
# round-off: a flat pair's patch is the pad).
PAD_CUT_TOLERANCE = 1e-9


def patch_options(patch):
    """``patch``: None or {"grid": [nx, ny], "margin_m": m, "size": [a, b]} (size overrides)."""
    if patch is not None and not isinstance(patch, Mapping):
        raise MujocoError(f"patch is {patch!r} (a {type(patch).__name__}), not a dict",
                          "give None or a dict such as {'grid': [9, 9], 'margin_m': 0.001, 'size': [0.01, 0.01]} "
                          "(the command's --grid, --margin, --patch-size)")
    p = dict(patch or {})
    unknown = set(p) - {"grid", "margin_m", "size"}
    if unknown:
        raise MujocoError(f"patch has unknown keys {sorted(unknown)}", "give grid, margin_m and/or size")
    size = p.get("size")
    return {"grid": patch_grid(p.get("grid", DEFAULT_GRID)),
            "margin_m": check_number("patch margin_m (--margin)", p.get("margin_m", 0.0), *MARGIN_RANGE_M, "m"),
            "size": None if size is None else patch_size(size)}


SENSOR_KINDS = ("taxels", "markers", "gel")


def sensor_option(sensor):
    """``sensor``: None or a tactile sensor spec given to every finger's pad (the scene's
    ``fingers[i].sensor``: ``{"taxels": {...}, "markers": {...}, "gel": {...}}``); its numbers
    are checked with the scene."""
    if sensor is None:
        return None
    if not isinstance(sensor, Mapping):
        raise MujocoError(f"sensor is {sensor!r} (a {type(sensor).__name__}), not a dict",
                          "give None or a dict such as {'taxels': {'count': [4, 4], 'pitch_m': 0.002, "
                          "'size_m': 0.002, 'depth_m': 0.001}} (the command's --sensor)")
    unknown = set(sensor) - set(SENSOR_KINDS)
    if unknown or not sensor:
        raise MujocoError(f"sensor has the keys {sorted(sensor)}",
                          f"give one or more of {', '.join(SENSOR_KINDS)} (docs/guide/tactile.md)")
    try:
        return json.loads(json.dumps(sensor, allow_nan=False))
    except (TypeError, ValueError) as e:
        raise MujocoError(f"sensor is not plain JSON data ({e})", "give numbers, lists and dicts only") from None


def patch_grid(grid):
    """[nx, ny], each at least 1, with at most a patch's most elements."""
    if not (isinstance(grid, (list, tuple)) and len(grid) == 2):
        raise MujocoError(f"patch grid (--grid) is {grid!r}", "give [nx, ny], each a whole number >= 1")
    grid = [check_count(f"patch grid[{i}] (--grid)", n, 1, MAX_ELEMENTS_PER_PATCH) for i, n in enumerate(grid)]
    if grid[0] * grid[1] > MAX_ELEMENTS_PER_PATCH:
        raise MujocoError(f"patch grid (--grid) is {grid[0]} x {grid[1]}: {grid[0] * grid[1]} elements per finger, "
                          f"more than the {MAX_ELEMENTS_PER_PATCH} (2048 x 2048) a patch may have",
                          "give a coarser grid")
    return grid


def patch_size(size):
    """[a, b], each a patch side in the scene's range, m."""
    if not (isinstance(size, (list, tuple)) and len(size) == 2):
        raise MujocoError(f"patch size (--patch-size) is {size!r}", "give [a, b], the patch's sides in metres")
    return [check_number(f"patch size[{i}] (--patch-size)", s, *PATCH_SIDE_RANGE_M, "m") for i, s in enumerate(size)]


def pad_cut_notes(name, size, pad, opts):
    """Warnings for the sides of finger ``name``'s patch that are cut to its box pad's ``pad``."""
    if opts["size"] is not None:
        asked = "patch size (--patch-size)"
    else:
        asked = "MuJoCo's points" + (" plus twice margin_m (--margin)" if opts["margin_m"] > 0 else "")
    return [f"finger {name}: patch side along t{d + 1} ({size[d]:.4g} m, {asked}) cut to the pad's side "
            f"{pad[d]:.4g} m" for d in range(2) if size[d] > pad[d] * (1 + PAD_CUT_TOLERANCE)]
