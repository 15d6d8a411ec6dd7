"""Materials of MuJoCo geoms: MuJoCo has no Young's moduli, so they come from a map of geom
(or body) names to materials, with one default for every geom the map does not name."""

import difflib
import json
import math
import os

from ._errors import MaterialMapError
from ._files import read_input

# The default: a rubber fingertip pad (the project's examples use it for every finger).
DEFAULT_MATERIAL = {"youngs_modulus": 2e6, "poisson_ratio": 0.45}
DEFAULT_TEXT = "rubber, E 2 MPa, nu 0.45"


def load_map(source):
    """A material map from a dict, a JSON file path, or None (empty)."""
    if source is None:
        return {}
    if isinstance(source, (str, os.PathLike)):
        raw = read_input(source, "material_map", MaterialMapError)
        try:
            data = json.loads(raw.decode("utf-8"), object_pairs_hook=_unique_keys,
                              parse_constant=_no_constant, parse_int=_bounded_int)
        except UnicodeDecodeError as e:
            raise MaterialMapError(f"the material map {os.fspath(source)} is not UTF-8 text: {e}",
                                   "save it as plain (UTF-8) JSON") from None
        except json.JSONDecodeError as e:
            raise MaterialMapError(f"the material map {os.fspath(source)} is not JSON: {e}",
                                   "give a JSON object {\"geom or body name\": material}") from None
    else:
        data = source
    if not isinstance(data, dict):
        raise MaterialMapError(f"the material map is a {type(data).__name__}, not an object",
                               "give {\"geom or body name\": {\"youngs_modulus\": Pa, \"poisson_ratio\": -}}")
    out = {}
    for name, m in data.items():
        if m == "rigid":
            out[name] = m
            continue
        if isinstance(m, dict) and m.get("layer_thickness_m", 0) is None:
            # null: no layer, as the scene format reads it.
            m = {k: v for k, v in m.items() if k != "layer_thickness_m"}
        required = {"youngs_modulus", "poisson_ratio"}
        if not (isinstance(m, dict) and required <= set(m) <= required | {"layer_thickness_m"}
                and all(_finite_number(v) for v in m.values())):
            raise MaterialMapError(
                f"material of '{name}' is {_shown(m)}",
                "give \"rigid\" or {\"youngs_modulus\": Pa, \"poisson_ratio\": -} with finite "
                "numbers (and \"layer_thickness_m\": m for a pad bonded to a rigid core)")
        out[name] = m
    return out


def _finite_number(v):
    """A finite int or float (not a bool, not NaN or an infinity, not an int too large for a
    float)."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    try:
        return math.isfinite(float(v))
    except OverflowError:
        return False


def _shown(m):
    """A material as JSON for a message, numbers beyond a float's range shown short."""
    try:
        text = json.dumps(m, allow_nan=True)
    except (ValueError, TypeError):
        text = repr(m)
    return text if len(text) <= 200 else text[:200] + "..."


def _unique_keys(pairs):
    """A JSON object's pairs as a dict, refusing a key given twice (the second would win)."""
    out = {}
    for k, v in pairs:
        if k in out:
            raise MaterialMapError(f"the material map gives '{k}' twice",
                                   "give each geom or body once")
        out[k] = v
    return out


def _no_constant(name):
    """NaN and Infinity are not JSON numbers."""
    raise MaterialMapError(f"the material map has {name}, which is no number",
                           "give finite numbers (Pa for youngs_modulus, m for layer_thickness_m)")


def _bounded_int(text):
    """An integer of the map, refused past 300 digits (beyond any float; Python itself would
    stop at 4,300 with its own message)."""
    if len(text.lstrip("-")) > 300:
        raise MaterialMapError(f"the material map has an integer of {len(text)} digits",
                               "give moduli in Pa and lengths in m as ordinary numbers")
    return int(text)


class MaterialMap:
    """Looks materials up by geom name, then by the geom's body name; remembers defaults."""

    def __init__(self, mujoco, model, source):
        self._map = load_map(source)
        self._model = model
        geoms = {model.geom(i).name for i in range(model.ngeom)} - {""}
        bodies = {model.body(i).name for i in range(model.nbody)} - {""}
        unknown = sorted(set(self._map) - geoms - bodies)
        if unknown:
            known = sorted(geoms | bodies)
            hints = []
            for u in unknown:
                close = difflib.get_close_matches(u, known, n=1)
                hints.append(f"'{u}'" + (f" (did you mean '{close[0]}'?)" if close else ""))
            raise MaterialMapError(
                f"the material map names {', '.join(hints)}, not a geom or body of the model",
                f"use names of the model's geoms or bodies: {', '.join(known)}")
        self.defaulted = []

    def of_geom(self, geom_id):
        """The material of a geom (scene format); the default when the map has neither its name
        nor its body's (the geom is then listed in ``defaulted``)."""
        g = self._model.geom(geom_id)
        body = self._model.body(int(self._model.geom_bodyid[geom_id])).name
        for key in (g.name, body):
            if key and key in self._map:
                m = self._map[key]
                return "rigid" if m == "rigid" else {k: float(v) for k, v in m.items()}
        label = g.name or f"geom {geom_id} (of body '{body}')"
        if label not in self.defaulted:
            self.defaulted.append(label)
        return dict(DEFAULT_MATERIAL)

    def warning(self):
        """The warning naming every geom that used the default, or None."""
        if not self.defaulted:
            return None
        return (f"no material in the map for {', '.join(repr(n) for n in self.defaulted)}: "
                f"using the default ({DEFAULT_TEXT}); name them in the material map")


def compliance(material):
    """(1 - nu^2) / E of a material, 0 for rigid (the half-space's: a layer's thickness, which
    only stiffens it, is left to the contact model)."""
    if material == "rigid":
        return 0.0
    return (1.0 - material["poisson_ratio"] ** 2) / material["youngs_modulus"]
