"""Viscoelastic pads from Python: grasp.solve answers a viscoelastic scene at t = 0+,
at a later time, or fully relaxed, as `grasp solve` does; bad times are ValueErrors naming the
keyword."""

import json

import pytest

import grasp
from conftest import EXAMPLES


def test_at_time_and_long_term_follow_the_relaxation():
    scene = grasp.Scene(EXAMPLES / "plate_hold_viscoelastic.json")
    p0 = grasp.solve(scene).to_dict()["fingers"][0]["normal_force_n"]
    p10 = grasp.solve(scene, at_time=10.0).to_dict()["fingers"][0]["normal_force_n"]
    relaxed = grasp.solve(scene, long_term=True).to_dict()["fingers"][0]["normal_force_n"]
    # Standard linear solid, tau 5 s, half the modulus relaxes: E(t)/E0 = 0.5 + 0.5 exp(-t/5).
    assert p10 / p0 == pytest.approx(0.5 + 0.5 * 2.718281828459045 ** -2, rel=5e-3)
    assert relaxed / p0 == pytest.approx(0.5, rel=5e-3)


def test_bad_times_name_the_keyword(run_cli, tmp_path):
    scene = grasp.Scene(EXAMPLES / "plate_hold_viscoelastic.json")
    with pytest.raises(ValueError, match="at_time"):
        grasp.solve(scene, at_time=-1.0)
    with pytest.raises(ValueError, match="long_term"):
        grasp.solve(scene, at_time=1.0, long_term=True)
    # True was read as 1 s; 1e300 was written out in 301 digits.
    with pytest.raises(TypeError, match="at_time= is a bool"):
        grasp.solve(scene, at_time=True)
    with pytest.raises(ValueError) as e:
        grasp.solve(scene, at_time=1e300)
    assert "1e300" in str(e.value) and "000000" not in str(e.value)
    # The CLI's answer at the same time is the same to the last bit.
    out = tmp_path / "s.json"
    proc = run_cli("solve", EXAMPLES / "plate_hold_viscoelastic.json", "--at-time", "3", "--json", out)
    assert proc.returncode == 0, proc.stderr
    cli = json.loads(out.read_text())
    assert cli["time"] == {"at_s": 3.0}
    py = grasp.solve(scene, at_time=3.0).to_dict()
    assert [f["normal_force_n"] for f in py["fingers"]] == [f["normal_force_n"] for f in cli["fingers"]]
    # The solved time too (to_dict lacked it), and the whole answer but its timings.
    assert py["time"] == {"at_s": 3.0}
    assert grasp.solve(scene, long_term=True).to_dict()["time"] == "long_term"
    assert grasp.solve(scene).to_dict()["time"] == "instantaneous"
    assert json.loads(grasp.solve(scene, at_time=3.0).to_json())["time"] == {"at_s": 3.0}
    assert "time" not in grasp.solve(grasp.Scene(EXAMPLES / "cube_a.json")).to_dict()


def test_a_time_on_an_elastic_scene_is_warned_about():
    # As the CLI's note: the time changes nothing on an elastic scene.
    cube = grasp.Scene(EXAMPLES / "cube_a.json")
    with pytest.warns(UserWarning, match="the scene is elastic"):
        timed = grasp.solve(cube, at_time=1.0)
    assert timed.to_dict()["fingers"] == grasp.solve(cube).to_dict()["fingers"]
