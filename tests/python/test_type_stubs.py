"""The package's type stubs (python/grasp/_native.pyi) are complete and right for its public
API: mypy --strict checks the stubs, the package's __init__ and tests/python/typed_usage.py (a
typed program calling the public functions and classes) and finds nothing; and a call the
stubs do not allow is caught (the check can fail)."""

import subprocess
import sys

from conftest import ROOT, checker

API = [ROOT / "python" / "grasp" / "_native.pyi", ROOT / "python" / "grasp" / "__init__.py"]


def mypy(files, tmp_path):
    checker("mypy", "the type check needs mypy (scripts/install-checkers.sh installs it)")
    args = [sys.executable, "-m", "mypy", "--strict", "--cache-dir", str(tmp_path / "mypy-cache")]
    return subprocess.run(args + [str(f) for f in files], capture_output=True, text=True, cwd=ROOT)


def test_the_public_api_type_checks_strictly(tmp_path):
    done = mypy(API + [ROOT / "tests" / "python" / "typed_usage.py"], tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_call_the_stubs_do_not_allow_is_caught(tmp_path):
    bad = tmp_path / "bad_usage.py"
    bad.write_text("import grasp\n\ngrasp.plan(grasp.Scene('s.json'), releasing=['f1'], bogus=1)\n")
    done = mypy(API + [bad], tmp_path)
    assert done.returncode == 1, done.stdout + done.stderr
    assert 'Unexpected keyword argument "bogus" for "plan"' in done.stdout


def stub_definitions():
    """{name: ast node} of the functions and classes the stub file defines at its top level."""
    import ast

    tree = ast.parse((ROOT / "python" / "grasp" / "_native.pyi").read_text())
    return {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}


def stub_parameters(node):
    args = node.args
    return [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs if a.arg not in ("self", "cls")]


def runtime_parameters(f):
    import inspect

    return [p for p in inspect.signature(f).parameters if p not in ("self", "cls", "$self", "$cls")]


def test_the_stubs_name_every_function_class_member_and_parameter_of_the_native_module():
    import ast
    import inspect

    import grasp._native as native

    stubs = stub_definitions()
    runtime = {n: getattr(native, n) for n in dir(native) if not n.startswith("__") and callable(getattr(native, n))}
    assert set(runtime) == set(stubs), (sorted(set(runtime) ^ set(stubs)))
    problems = []
    for name, obj in runtime.items():
        node = stubs[name]
        if not inspect.isclass(obj):
            if runtime_parameters(obj) != stub_parameters(node):
                problems.append(f"{name}: {runtime_parameters(obj)} at run time, {stub_parameters(node)} in the stub")
            continue
        members = {m: n for m, n in ((n.name, n) for n in node.body if isinstance(n, ast.FunctionDef))}
        public = {m for m in vars(obj) if not m.startswith("_")}
        if issubclass(obj, BaseException):
            public = set()
        if public != {m for m in members if not m.startswith("_")}:
            problems.append(f"{name}: members {sorted(public)} at run time, {sorted(members)} in the stub")
        for m in public & set(members):
            decorators = [ast.unparse(d) for d in members[m].decorator_list]
            if "property" in decorators:
                continue
            got = runtime_parameters(getattr(obj, m))
            if got != stub_parameters(members[m]):
                problems.append(f"{name}.{m}: {got} at run time, {stub_parameters(members[m])} in the stub")
    assert not problems, "\n".join(problems)
