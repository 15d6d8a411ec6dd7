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
