"""grasp.plan: the planned schedule, run by grasp.transfer, keeps its constraints (checked on
the run's own force histories), equals the CLI's plan of the same question, and constraints
no schedule can meet raise GraspError naming the binding one by its keyword."""

import json

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES

SCENE = EXAMPLES / "plate_handoff_coulomb.json"
TEMPLATE = EXAMPLES / "plate_handoff_coulomb.schedule.json"
MU = 0.4  # every pad of the plate
LOAD_SCALE_N = 8.0  # the largest of the weight (4.448 N) and the commanded loads
MARGIN_TOLERANCE = 1e-3  # the planner's stated tolerance on a margin


def test_the_plan_run_by_transfer_keeps_its_margin_and_rates(tmp_path, run_cli):
    scene = grasp.Scene(SCENE)
    plan = grasp.plan(
        scene, releasing=["f1", "f2"], receiving=["f3", "f4"], template=TEMPLATE, max_rate=1.5
    )
    assert plan["met"] and plan["binding"] is None
    run = grasp.transfer(scene, plan["schedule"])
    p = run.normal_forces_n
    q = np.linalg.norm(run.tangential_forces_n, axis=2)
    carrying = (p > 0) & (np.hypot(p, q) >= 0.05 * LOAD_SCALE_N)
    margins = 1 - q[carrying] / (MU * p[carrying])
    assert margins.min() >= -MARGIN_TOLERANCE
    assert run.times_s[-1] == pytest.approx(plan["duration_s"], abs=1e-9)
    assert plan["duration_s"] <= 12.0
    # The CLI plans the same schedule from the same question.
    out = tmp_path / "plan.schedule.json"
    proc = run_cli(
        "plan", SCENE, "--releasing", "f1,f2", "--receiving", "f3,f4",
        "--template", TEMPLATE, "--max-rate", "1.5", "--out", out,
    )
    assert proc.returncode == 0, proc.stderr
    assert json.loads(out.read_text()) == plan["schedule"]


def test_constraints_no_schedule_meets_raise_with_the_keyword_named():
    scene = grasp.Scene(SCENE)
    with pytest.raises(grasp.GraspError, match=r"`max_rate=` 0\.5 N/s that takes 16 s") as e:
        grasp.plan(
            scene, releasing=["f1", "f2"], objective="margin", duration=4.0, max_rate=0.5
        )
    assert "--" not in str(e.value)
    with pytest.raises(ValueError, match="objective=") as e:
        grasp.plan(scene, releasing=["f1", "f2"])
    # The library's message, every option in it named by its keyword, none by a CLI flag.
    assert str(e.value) == (
        "`objective=`: the shortest duration needs a rate limit (a quasi-static hand-off "
        "is as fast as its rates allow): give `max_rate=` (loads) or `max_speed=` (approaches), "
        'or `objective="margin"`'
    )
    with pytest.raises(ValueError) as e:
        grasp.plan(scene, releasing=["f1", "f2"], max_rate=1.5, min_load=5.0, max_load=3.0,
                   min_duration=5.0, max_duration=3.0, steps=1)
    assert str(e.value).splitlines() == [
        "`min_load=`: needs 0 <= `min_load < max_load` (got 5 and 3)",
        "`min_duration=`: needs 0 <= `min_duration <= max_duration`",
        "`steps=`: must be 2 to 10,000",
    ]
    with pytest.raises(grasp.GraspError, match="give `duration=` \\(s\\), `max_rate=`") as e:
        grasp.plan(scene, releasing=["f1", "f2"], objective="margin")
    assert "--" not in str(e.value)
    # The report's texts too: the search that ran out of runs names `max_runs=` (the report
    # of a plan that does not keep its constraints rides on the exception).
    with pytest.raises(grasp.GraspError) as e:
        grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"], max_rate=1.5,
                   steps=4, max_runs=2, min_slip_margin=0.9)
    plan = e.value.report
    assert plan["stopped"] == "it made the runs allowed (`max_runs=`)"
    assert "--" not in plan["binding"]["why"]
    assert "--" not in str(e.value)
    with pytest.raises(ValueError, match="objective="):
        grasp.plan(scene, releasing=["f1"], objective="fastest")


def test_a_disturbance_margin_threshold_is_kept_and_named_by_its_keyword():
    scene = grasp.Scene(SCENE)
    # Few steps and runs: each run's margins cost seconds.
    plan = grasp.plan(
        scene, releasing=["f1", "f2"], receiving=["f3", "f4"], objective="margin",
        duration=8.0, steps=4, max_runs=5, min_margin=0.5,
    )
    assert plan["met"], plan["binding"]
    along = [m["disturbance_n"] for m in plan["margins"]]
    assert len(along) == 5
    # The planner's tolerance on a disturbance margin: 2e-3 of the threshold.
    assert min(along) >= 0.5 * (1 - 2e-3)
    # grasp.transfer's own margins along the schedule are the ones the plan reports.
    run = grasp.transfer(scene, plan["schedule"], margins=True)
    assert run.smallest_margins_n == pytest.approx(along, rel=1e-12)
    with pytest.raises(ValueError, match="min_margin="):
        grasp.plan(scene, releasing=["f1", "f2"], max_rate=1.5, min_margin=0.0)


def test_a_plan_that_fails_its_own_check_raises_as_the_cli_writes_nothing(tmp_path, run_cli):
    # The plate cannot keep a slip margin of 0.1 (the guide's example): the CLI writes no
    # schedule (exit 2); grasp.plan raises, naming the binding constraint, and hands over the
    # report on the exception rather than a schedule to run.
    scene = grasp.Scene(SCENE)
    with pytest.raises(grasp.GraspError, match=r"no schedule written.*binding: slip margin") as e:
        grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"], template=TEMPLATE,
                   max_rate=2.0, min_slip_margin=0.1)
    report = e.value.report
    assert report["met"] is False
    assert report["binding"]["constraint"] == "slip margin"
    assert report["binding"]["limit"] == 0.1
    assert report["binding"]["value"] < 0.1 - MARGIN_TOLERANCE
    assert "--" not in str(e.value)
    out = tmp_path / "plan.schedule.json"
    proc = run_cli(
        "plan", SCENE, "--releasing", "f1,f2", "--receiving", "f3,f4", "--template", TEMPLATE,
        "--max-rate", "2", "--min-slip-margin", "0.1", "--out", out,
    )
    assert proc.returncode == 2, proc.stderr
    assert not out.exists()


def test_a_bool_for_a_number_or_a_str_for_finger_names_is_refused_by_keyword():
    scene = grasp.Scene(SCENE)
    # True is an int to Python: it used to plan at 1 N/s.
    with pytest.raises(TypeError, match=r"`max_rate=` is True, a bool: give a number"):
        grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"], max_rate=True)
    with pytest.raises(TypeError, match=r"`steps=` is False: give a whole number"):
        grasp.plan(scene, releasing=["f1", "f2"], max_rate=1.5, steps=False)
    # A single name used to say "Can't extract `str` to `Vec`".
    with pytest.raises(TypeError) as e:
        grasp.plan(scene, releasing="f1", max_rate=1.5)
    assert str(e.value) == (
        "`releasing=` is the string 'f1', not a list of finger names; give ['f1']"
    )
    with pytest.raises(TypeError, match=r"`receiving=` is \[3\]: give a list of finger names"):
        grasp.plan(scene, releasing=["f1", "f2"], receiving=[3], max_rate=1.5)
    # Negative numbers reach the planner's checks, named by keyword.
    with pytest.raises(ValueError, match=r"`min_load=`: needs 0 <= `min_load < max_load`"):
        grasp.plan(scene, releasing=["f1", "f2"], max_rate=1.5, min_load=-1.0)


GRIPPER = EXAMPLES / "plate_transfer_gripper.json"
GRIPPER_TEMPLATE = EXAMPLES / "plate_transfer_gripper.schedule.json"
GRIPPER_MU = 0.5  # every pad of the gripper hand-off
GRIPPER_LOAD_SCALE_N = 4.448  # the weight: no finger has a commanded load


def approach_keyframes(schedule, finger):
    (phase,) = schedule["fingers"][finger]
    return phase["approach"]["keyframes"]


def test_a_plan_of_jaw_positions_opens_at_the_speed_limit_and_lets_go():
    """The gripper hand-off planned by its jaws' positions: the servo's jaws open from 4 mm to
    -1 mm, the receiving jaws close from 0.1 mm towards 1 mm, at most 0.5 mm/s. The shortest
    such hand-off opens the releasing jaws at the limit all the way: 5 mm / 0.5 mm/s = 10 s
    (to 1e-6 of it, the program's accuracy). Checked on the run's own force histories: every
    step holds, the counted slip margins keep 0 (to the planner's 1e-3), the releasing jaws
    carry nothing at the end (1e-9 of the weight: separated elements' round-off)."""
    scene = grasp.Scene(GRIPPER)
    speed = 5e-4
    plan = grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"],
                      open_to=-0.001, close_to=0.001, max_speed=speed)
    assert plan["met"], plan["binding"]
    assert plan["duration_s"] == pytest.approx(0.005 / speed, rel=1e-6)
    assert plan["loads_n"] == [] and [a[0] for a in plan["approaches_m"]] == ["f1", "f2", "f3", "f4"]
    for finger in ["f1", "f2", "f3", "f4"]:
        keys = approach_keyframes(plan["schedule"], finger)
        for (t0, a0), (t1, a1) in zip(keys, keys[1:]):
            assert abs(a1 - a0) / (t1 - t0) <= speed * (1 + 1e-6), finger
    assert approach_keyframes(plan["schedule"], "f1")[0][1] == 0.004
    assert approach_keyframes(plan["schedule"], "f1")[-1][1] == -0.001
    run = grasp.transfer(scene, plan["schedule"])
    assert all(s == "solved" for s in run.statuses)
    p = run.normal_forces_n
    q = np.linalg.norm(run.tangential_forces_n, axis=2)
    carrying = (p > 0) & (np.hypot(p, q) >= 0.05 * GRIPPER_LOAD_SCALE_N)
    assert (1 - q[carrying] / (GRIPPER_MU * p[carrying])).min() >= -MARGIN_TOLERANCE
    assert p[-1, :2].max() <= 1e-9 * GRIPPER_LOAD_SCALE_N
    # From the template: no longer than it, every constraint kept.
    planned = grasp.plan(scene, releasing=["f1", "f2"], receiving=["f3", "f4"],
                         template=GRIPPER_TEMPLATE, max_speed=speed)
    assert planned["met"] and planned["duration_s"] <= 15.0


def test_position_plans_that_cannot_be_made_are_refused_by_keyword(tmp_path, run_cli):
    scene = grasp.Scene(GRIPPER)
    both = dict(releasing=["f1", "f2"], receiving=["f3", "f4"], max_speed=5e-4)
    with pytest.raises(grasp.GraspError, match="give `open_to=`"):
        grasp.plan(scene, **both, close_to=0.001)
    with pytest.raises(grasp.GraspError, match="give `close_to=`"):
        grasp.plan(scene, **both, open_to=-0.001)
    with pytest.raises(grasp.GraspError, match="a releasing jaw opens"):
        grasp.plan(scene, **both, open_to=0.005, close_to=0.001)
    with pytest.raises(grasp.GraspError, match="longer than the 4 s allowed"):
        grasp.plan(scene, **both, open_to=-0.001, close_to=0.001, max_duration=4.0)
    with pytest.raises(ValueError, match="max_speed="):
        grasp.plan(scene, **{**both, "max_speed": -1.0}, open_to=-0.001, close_to=0.001)
    spec = json.loads(GRIPPER.read_text())
    spec["fingers"][2]["control"] = {"normal_load": 1.0}
    mixed = grasp.Scene(spec)
    with pytest.raises(grasp.GraspError, match="`receiving=` mixes force-controlled fingers"):
        grasp.plan(mixed, **both, open_to=-0.001, max_rate=1.0)
    with pytest.raises(grasp.GraspError, match="`max_rate=` is given but applies to no planned finger"):
        grasp.plan(scene, **both, open_to=-0.001, close_to=0.001, max_rate=1.0)
    spec["fingers"][3]["control"] = {"normal_load": 1.0}
    by_load = grasp.Scene(spec)
    with pytest.raises(grasp.GraspError, match="the receiving fingers have no rate limit.*give `max_rate=`"):
        grasp.plan(by_load, **both, open_to=-0.001, max_load=4.0)
    # The CLI names its flags.
    proc = run_cli("plan", GRIPPER, "--releasing", "f1,f2", "--receiving", "f3,f4",
                   "--max-speed", "5e-4", "--close-to", "0.001", "--out", tmp_path / "p.json")
    assert proc.returncode == 1 and "give --open-to" in proc.stderr, proc.stderr
