"""grasp.mujoco without MuJoCo: importing it works; every call that needs MuJoCo, and both
commands, say that MuJoCo is not installed and give the install command; nothing is written.
MuJoCo is hidden from a fresh interpreter (``sys.modules["mujoco"] = None`` makes ``import
mujoco`` fail as if it were absent), so this runs whether MuJoCo is installed or not."""

import subprocess
import sys

from conftest import EXAMPLES, ROOT

HIDE = "import sys; sys.modules['mujoco'] = None\n"


def python(code, *args):
    return subprocess.run([sys.executable, "-c", HIDE + code, *map(str, args)], capture_output=True, text=True, cwd=ROOT)


def test_mujoco_missing_calls_raise_a_named_error_with_the_install_command():
    code = """
import grasp.mujoco as gm
for call in (lambda: gm.load_model("examples/mujoco/pinch.xml"), lambda: gm.scene_from(None, None, "box"),
             lambda: gm.schedule_from_rollout(None, {}, "cylinder")):
    try:
        call()
    except gm.MujocoNotInstalled as e:
        assert isinstance(e, ImportError) and isinstance(e, gm.MujocoError)
        print(e)
    else:
        raise SystemExit("no error")
"""
    proc = python(code)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert len(lines) == 3
    for line in lines:
        assert line.startswith("MuJoCo is not installed") and "pip install 'mujoco==4.0.0'" in line


def test_mujoco_missing_commands_exit_1_and_write_nothing(tmp_path):
    main = "from grasp.mujoco.__main__ import main; sys.exit(main(sys.argv[1:]))"
    mj = EXAMPLES / "mujoco"
    for args in (["scene", mj / "pinch.xml", "--object", "box", "--keyframe", "grasped", "--out", tmp_path / "s.json",
                  "--report", tmp_path / "r.json"],
                 ["handoff", mj / "handoff.xml", "--object", "cylinder", "--controller",
                  f"{mj / 'handoff_controller.py'}:control", "--steps", "10", "--out", tmp_path / "h"]):
        proc = python(main, *args)
        assert proc.returncode == 1, proc.stderr
        assert "error: MuJoCo is not installed" in proc.stderr
        assert "fix: install it with `pip install 'mujoco==4.0.0'`" in proc.stderr
    assert list(tmp_path.iterdir()) == []
