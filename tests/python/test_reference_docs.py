"""The package's Python reference: every public function, class, method and property of
`grasp` and `grasp.mujoco` (their `__all__`) has a docstring, in the numpy convention: a
callable's `Parameters` section names exactly its parameters, every callable has a `Returns`
section, every module-level function a `Raises` section, and a class built with arguments
names them under `Parameters` (or `Attributes`, for a dataclass). `help(grasp.solve)` shows
the keywords with their units. The checker is run on a badly documented function and class
too, so it can fail."""

import dataclasses
import inspect
import re

import grasp
import grasp.mujoco

PACKAGES = [grasp, grasp.mujoco]


def sections(doc):
    """The numpy-style sections of `doc` (cleaned): {heading: [lines]}; '' is the summary."""
    lines = inspect.cleandoc(doc).splitlines()
    out, current = {"": []}, ""
    for i, line in enumerate(lines):
        underline = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", underline.strip()) and len(underline.strip()) == len(line.strip()):
            current = line.strip()
            out[current] = []
        elif not re.fullmatch(r"-{3,}", line.strip()):
            out[current].append(line)
    return out


def named(lines):
    """The names a Parameters / Attributes section defines: its unindented `a, b : type` lines."""
    names = set()
    for line in lines:
        if line.strip() and not line[0].isspace():
            names |= {n.strip() for n in line.split(" : ")[0].split(",")}
    return names


def parameters(f):
    """The parameter names of callable `f`, without self, cls and private ones; None when
    Python cannot tell (a callable without a signature)."""
    try:
        sig = inspect.signature(f)
    except (TypeError, ValueError):
        return None
    return [p for p in sig.parameters if p not in ("self", "cls", "$self", "$cls") and not p.startswith("_")]


def callable_problems(where, f, module_level):
    doc = inspect.getdoc(f)
    if not doc:
        return [f"{where}: no docstring"]
    s, problems = sections(doc), []
    params = parameters(f)
    if params is None:
        problems.append(f"{where}: no signature Python can read (help() shows no parameters)")
    elif params and named(s.get("Parameters", [])) != set(params):
        problems.append(f"{where}: the Parameters section names {sorted(named(s.get('Parameters', [])))}, "
                        f"its parameters are {params}")
    if "Returns" not in s:
        problems.append(f"{where}: no Returns section")
    if module_level and "Raises" not in s:
        problems.append(f"{where}: no Raises section")
    return problems


def class_problems(where, cls):
    doc = cls.__doc__ if cls.__doc__ is not object.__doc__ else None
    if not doc or not doc.strip():
        return [f"{where}: no docstring"]
    problems = []
    if not issubclass(cls, BaseException):
        params = parameters(cls) or []
        s = sections(doc)
        given = named(s.get("Parameters", [])) | named(s.get("Attributes", []))
        if params and not set(params) <= given:
            problems.append(f"{where}: the class doc does not name {sorted(set(params) - given)} "
                            "under Parameters or Attributes")
    for name, member in vars(cls).items():
        if name.startswith("_") or (dataclasses.is_dataclass(cls) and name in {f.name for f in dataclasses.fields(cls)}):
            continue
        if isinstance(member, (property, type(grasp.Solution.status))):
            if not (member.__doc__ or "").strip():
                problems.append(f"{where}.{name}: property without a docstring")
        elif isinstance(member, (staticmethod, classmethod)) or callable(member):
            problems += callable_problems(f"{where}.{name}", getattr(cls, name), module_level=False)
    return problems


def reference_problems(objects):
    """Every problem of the documentation of `objects` ({qualified name: object})."""
    problems = []
    for where, obj in objects.items():
        if inspect.isclass(obj):
            problems += class_problems(where, obj)
        elif callable(obj):
            problems += callable_problems(where, obj, module_level=True)
    return problems


def public_objects():
    return {f"{p.__name__}.{n}": getattr(p, n) for p in PACKAGES for n in p.__all__}


def test_every_public_name_is_documented_with_parameters_returns_and_raises():
    objects = public_objects()
    assert {"grasp.solve", "grasp.Scene", "grasp.mujoco.scene_from", "grasp.mujoco.Rollout"} <= set(objects)
    problems = reference_problems(objects)
    assert not problems, "\n".join(problems)


def test_the_checker_finds_an_undocumented_function_and_class():
    def bare(scene, tolerance=1e-10):
        return scene

    def stale(scene, tolerance=1e-10):
        """Solves.

        Parameters
        ----------
        scene : Scene
            The grasp.

        Returns
        -------
        Solution
        """

    class Bare:
        def __init__(self, source):
            self.source = source

        def to_dict(self, indent):
            """The dict."""

    problems = reference_problems({"bare": bare, "stale": stale, "Bare": Bare})
    assert "bare: no docstring" in problems
    assert "stale: the Parameters section names ['scene'], its parameters are ['scene', 'tolerance']" in problems
    assert "stale: no Raises section" in problems
    assert "Bare: no docstring" in problems


def test_help_of_solve_shows_the_keywords_with_their_units():
    text = inspect.getdoc(grasp.solve)
    signature = str(inspect.signature(grasp.solve))
    for keyword in ["model", "solver", "tolerance", "compliance", "at_time", "long_term"]:
        assert keyword in signature
    s = sections(text)
    assert s[""][0].startswith("Solves one grasp")
    assert "seconds" in "\n".join(s["Parameters"]) and "SceneError" in named(s["Raises"])
