"""The package's public API as a typed program uses it: not run by pytest, type-checked by
mypy --strict in the test command (scripts/test.sh) against python/grasp/_native.pyi, so a
stub that is missing, misspelt or wrongly typed fails the tests."""

from typing import Any

import numpy as np
import numpy.typing as npt

import grasp


def forces(path: str) -> npt.NDArray[np.float64]:
    scene = grasp.Scene(path)
    sol: grasp.Solution = grasp.solve(scene, solver="native", tolerance=1e-10, compliance="auto")
    names: list[str] = scene.finger_names
    assert len(names) == sol.finger_normal_forces_n.shape[0]
    record: dict[str, Any] = sol.to_dict()
    assert "fingers" in record
    return sol.normal_forces_n


def hand_off(scene_path: str, schedule_path: str) -> float:
    scene = grasp.Scene(scene_path)
    run: grasp.Transfer = grasp.transfer(scene, schedule_path, margins=False, keep_going=False)
    times: npt.NDArray[np.float64] = run.times_s
    return float(times[-1])


def planned(scene_path: str, template: str) -> bool:
    scene = grasp.Scene(scene_path)
    plan: dict[str, Any] = grasp.plan(
        scene, releasing=["f1", "f2"], receiving=["f3", "f4"], template=template, max_rate=1.5,
        objective="duration", keyframes=5,
    )
    grasp.transfer(scene, plan["schedule"])
    return bool(plan["met"])


def refused(path: str) -> list[dict[str, str]]:
    try:
        grasp.Scene(path)
    except grasp.SceneError as e:
        return e.problems
    return []
