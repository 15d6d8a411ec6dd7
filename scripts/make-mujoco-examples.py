"""Regenerates the MuJoCo examples (examples/mujoco/) and their gallery pictures.

1. the pinches: simulates examples/mujoco/pinch.xml (the motor squeezing 10 N), servo_pinch.xml
   (position servos on slides), hinge_pinch.xml (position servos on hinges) and
   coupled_pinch.xml (one servo on a tendon driving both jaws) from their keyframes "start"
   for 1 s and writes the states reached into their keyframes "grasped";
2. `python -m grasp.mujoco scene` of the pinches at "grasped": examples/mujoco/pinch.json,
   servo_pinch.json, hinge_pinch.json and coupled_pinch.json (`--control mujoco-servo`), and the side-by-side reports
   pinch.report.json and servo_pinch.report.json (their tables are printed, as
   docs/guide/mujoco.md shows them);
3. `python -m grasp.mujoco handoff` of examples/mujoco/handoff.xml driven by
   handoff_controller.py:control (1600 steps of 1 ms, every 10th recorded):
   examples/mujoco/handoff.json, handoff.schedule.json, handoff.csv;
4. `grasp plot` of both scenes: docs/gallery/mujoco/pinch.svg, handoff.svg.

Needs the Python package installed with MuJoCo (`pip install '.[mujoco]'`) and the grasp CLI
(GRASP_BIN, else target/release/grasp). tests/python/test_mujoco_examples.py regenerates
steps 1 to 4 and compares them with the committed files.
Usage: python scripts/make-mujoco-examples.py
"""

import os
import re
import subprocess
import sys

import mujoco

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EX = os.path.join(ROOT, "examples", "mujoco")
GALLERY = os.path.join(ROOT, "docs", "gallery", "mujoco")
SETTLE_S = 1.0


def grasped_key(xml_text):
    """The keyframe "grasped" line for the state 1 s after "start"."""
    model = mujoco.MjModel.from_xml_string(xml_text)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("start").id)
    for _ in range(round(SETTLE_S / model.opt.timestep)):
        mujoco.mj_step(model, data)

    def nums(a):
        return " ".join(repr(float(x)) for x in a)

    return (f'<key name="grasped" time="{data.time!r}" qpos="{nums(data.qpos)}" qvel="{nums(data.qvel)}" '
            f'ctrl="{nums(data.ctrl)}"/>')


def with_grasped_key(xml_text):
    return re.sub(r'<key name="grasped"[^>]*/>', grasped_key(xml_text), xml_text)


def run(*args):
    print("+", " ".join(args))
    subprocess.run(args, check=True, cwd=ROOT)


def settle(name):
    """Writes the keyframe "grasped" of examples/mujoco/<name>.xml."""
    path = os.path.join(EX, f"{name}.xml")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    new = with_grasped_key(text)
    if new != text:
        with open(path, "w", encoding="utf-8") as f:
            f.write(new)


def main():
    settle("pinch")
    settle("servo_pinch")
    settle("hinge_pinch")
    settle("coupled_pinch")
    py = sys.executable
    run(py, "-m", "grasp.mujoco", "scene", "examples/mujoco/pinch.xml", "--object", "box", "--keyframe", "grasped",
        "--materials", "examples/mujoco/pinch.materials.json", "--out", "examples/mujoco/pinch.json",
        "--report", "examples/mujoco/pinch.report.json", "--markdown", "--force")
    run(py, "-m", "grasp.mujoco", "scene", "examples/mujoco/servo_pinch.xml", "--object", "box", "--keyframe",
        "grasped", "--control", "mujoco-servo", "--materials", "examples/mujoco/servo_pinch.materials.json",
        "--out", "examples/mujoco/servo_pinch.json", "--report", "examples/mujoco/servo_pinch.report.json",
        "--markdown", "--force")
    run(py, "-m", "grasp.mujoco", "scene", "examples/mujoco/hinge_pinch.xml", "--object", "box", "--keyframe",
        "grasped", "--control", "mujoco-servo", "--materials", "examples/mujoco/hinge_pinch.materials.json",
        "--out", "examples/mujoco/hinge_pinch.json", "--force")
    run(py, "-m", "grasp.mujoco", "scene", "examples/mujoco/coupled_pinch.xml", "--object", "box", "--keyframe",
        "grasped", "--control", "mujoco-servo", "--materials", "examples/mujoco/coupled_pinch.materials.json",
        "--out", "examples/mujoco/coupled_pinch.json", "--force")
    run(py, "-m", "grasp.mujoco", "handoff", "examples/mujoco/handoff.xml", "--object", "cylinder",
        "--controller", "examples/mujoco/handoff_controller.py:control", "--steps", "1600", "--every", "10",
        "--materials", "examples/mujoco/handoff.materials.json", "--out", "examples/mujoco/handoff", "--force")
    grasp_bin = os.environ.get("GRASP_BIN") or os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "grasp")
    os.makedirs(GALLERY, exist_ok=True)
    for name in ("pinch", "handoff"):
        run(grasp_bin, "plot", f"examples/mujoco/{name}.json", "--out", f"docs/gallery/mujoco/{name}.svg", "--force")


if __name__ == "__main__":
    main()
