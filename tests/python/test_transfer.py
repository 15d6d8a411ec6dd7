"""grasp.transfer: force histories against the CLI's own run of the same hand-off, the files
it writes (checked by the independent `rerun` CLI), and the no-overwrite rule."""

import csv
import json
import subprocess

import numpy as np
import pytest

import grasp
from conftest import EXAMPLES, rerun_cli

SCENE = EXAMPLES / "plate_transfer.json"
SCHEDULE = EXAMPLES / "plate_transfer.schedule.json"


def cli_csv(run_cli, tmp_path):
    out = tmp_path / "cli.csv"
    proc = run_cli("transfer", SCENE, "--schedule", SCHEDULE, "--csv", out)
    assert proc.returncode == 0, proc.stderr
    with open(out, newline="") as f:
        return list(csv.DictReader(f))


def test_histories_equal_the_cli_run_and_the_files_are_written(run_cli, tmp_path):
    scene = grasp.Scene(SCENE)
    files = {k: tmp_path / f"py.{k}" for k in ("mcap", "rrd", "csv")}
    run = grasp.transfer(scene, SCHEDULE, **files)
    t, f = len(run), len(scene.finger_names)
    assert t == 200 and run.times_s.shape == (t,)
    assert run.normal_forces_n.shape == (t, f) and run.tangential_forces_n.shape == (t, f, 3)
    assert run.commanded_loads_n.shape == (t, f) and run.statuses.shape == (t,)
    assert set(run.statuses) == {"solved"}
    assert run.written == [str(files[k]) for k in ("mcap", "rrd", "csv")]
    # The CLI's CSV of the same run: the same forces to the digits it prints.
    rows = cli_csv(run_cli, tmp_path)
    assert len(rows) == t
    ours = list(csv.DictReader(open(files["csv"], newline="")))
    for name_i, name in enumerate(scene.finger_names):
        col = f"{name}_normal_force_n"
        assert [r[col] for r in ours] == [r[col] for r in rows]
        assert np.allclose([float(r[col]) for r in rows], run.normal_forces_n[:, name_i], rtol=1e-9, atol=1e-12)
    # The releasing pair's commands ramp to zero; the receiving pair ends with all the load.
    assert run.commanded_loads_n[-1, 0] == 0.0 and run.normal_forces_n[-1, :2].max() == 0.0
    s = run.summary
    assert s["steps"] == t and s["failed_step_count"] == 0 and s["releasing"] == ["f1", "f2"]
    full = run.step(-1)
    assert full.status == "solved" and full.positions_m.shape[1] == 3


@pytest.mark.skipif(rerun_cli() is None, reason="the rerun CLI (scripts/install-checkers.sh) is not installed")
def test_the_recording_and_the_mcap_pass_the_rerun_checks(tmp_path):
    rrd, mcap = tmp_path / "h.rrd", tmp_path / "h.mcap"
    grasp.transfer(grasp.Scene(SCENE), SCHEDULE, rrd=rrd, mcap=mcap)
    env = {"CI": "1", "PATH": "/usr/bin:/bin"}
    for args in (["rrd", "verify", str(rrd)], ["mcap", "check", str(mcap)]):
        proc = subprocess.run([rerun_cli(), *args], capture_output=True, text=True, env=env)
        assert proc.returncode == 0, proc.stdout + proc.stderr


def test_existing_files_are_kept_unless_overwrite(tmp_path):
    scene = grasp.Scene(SCENE)
    target = tmp_path / "h.csv"
    target.write_text("mine\n")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        grasp.transfer(scene, SCHEDULE, csv=target)
    assert target.read_text() == "mine\n"
    grasp.transfer(scene, SCHEDULE, csv=target, overwrite=True)
    assert target.read_text().startswith("time_s,")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]  # no temporary left
    with pytest.raises(ValueError, match="is also another output"):
        grasp.transfer(scene, SCHEDULE, csv=tmp_path / "a", mcap=tmp_path / "a")
    with pytest.raises(FileNotFoundError, match="folder .* does not exist"):
        grasp.transfer(scene, SCHEDULE, csv=tmp_path / "no" / "h.csv")


def test_schedule_from_dict_and_errors():
    scene = grasp.Scene(SCENE)
    spec = json.loads(SCHEDULE.read_text())
    a = grasp.transfer(scene, spec)
    b = grasp.transfer(scene, json.dumps(spec))
    assert np.array_equal(a.normal_forces_n, b.normal_forces_n)
    spec["fingers"]["nope"] = spec["fingers"].pop("f1")
    with pytest.raises(grasp.ScheduleError) as e:
        grasp.transfer(scene, spec)
    assert [p["path"] for p in e.value.problems] == ["fingers.nope"]
    assert "f1" in e.value.problems[0]["fix"]
    # Non-finite numbers from Python objects are named by their path.
    spec = json.loads(SCHEDULE.read_text())
    spec["time"]["end"] = float("inf")
    with pytest.raises(grasp.ScheduleError) as e:
        grasp.transfer(scene, spec)
    assert [p["path"] for p in e.value.problems] == ["time.end"]
    assert "finite" in e.value.problems[0]["fix"]


def test_cold_runs_reach_the_same_forces_with_more_iterations():
    scene = grasp.Scene(SCENE)
    warm = grasp.transfer(scene, SCHEDULE)
    cold = grasp.transfer(scene, SCHEDULE, cold=True)
    assert np.abs(warm.normal_forces_n - cold.normal_forces_n).max() <= 1e-8 * warm.normal_forces_n.max()
    assert warm.iterations.sum() < cold.iterations.sum()


def test_dense_and_fft_compliance_give_the_same_hand_off():
    # Compliance= on grasp.transfer as on grasp.solve. The two paths discretise the
    # same operator, so every step's forces agree to the solver's tolerance; 1e-8 of the load,
    # as in tests/solver_equivalence.rs. A bad value is a ValueError naming the keyword.
    scene = grasp.Scene(SCENE)
    dense = grasp.transfer(scene, SCHEDULE, compliance="dense")
    fft = grasp.transfer(scene, SCHEDULE, compliance="fft")
    assert fft.step(len(fft) - 1).solver["compliance"] == "fft"
    assert dense.step(len(dense) - 1).solver["compliance"] == "dense"
    scale = dense.normal_forces_n.max()
    assert np.abs(dense.normal_forces_n - fft.normal_forces_n).max() <= 1e-8 * scale
    with pytest.raises(ValueError, match="compliance="):
        grasp.transfer(scene, SCHEDULE, compliance="sparse")


def test_progress_is_called_after_each_step_and_can_stop_the_run(tmp_path):
    # Progress on long runs, and a way to stop them (Ctrl-C is looked for at the
    # same place, between steps).
    scene = grasp.Scene(SCENE)
    seen = []
    run = grasp.transfer(scene, SCHEDULE, progress=lambda done, total: seen.append((done, total)))
    n = len(run.times_s)
    assert seen == [(k, n) for k in range(1, n + 1)]

    class Enough(Exception):
        pass

    def stop_at_ten(done, total):
        if done == 10:
            raise Enough()

    out = tmp_path / "h.csv"
    with pytest.raises(Enough):
        grasp.transfer(scene, SCHEDULE, csv=out, progress=stop_at_ten)
    assert sorted(p.name for p in tmp_path.iterdir()) == [], "a stopped run writes no file"
    with pytest.raises(TypeError, match="progress= is not callable"):
        grasp.transfer(scene, SCHEDULE, progress=3)


def test_warnings_are_told_once_with_their_steps_and_on_each_csv_row(tmp_path):
    # The disc's patches are too small for its contacts: each finger's warning once, with the
    # steps it applies to, as `grasp transfer` prints it; each step's own on its CSV row; the
    # run's in the MCAP's metadata; every one naming options as Python spells them.
    scene = grasp.Scene(EXAMPLES / "disc_transfer.json")
    files = {"csv": tmp_path / "d.csv", "mcap": tmp_path / "d.mcap"}
    run = grasp.transfer(scene, EXAMPLES / "disc_transfer.schedule.json", keep_solutions=True, **files)
    assert run.warnings == run.summary["warnings"]
    assert len(run.warnings) == 4
    for w in run.warnings:
        assert w["count"] == 150 and len(w["steps"]) == 1
        assert "the patch is too small" in w["message"] and "--auto-patch" not in w["message"]
    f3 = next(w for w in run.warnings if w["message"].startswith("fingers[2] `f3`"))
    assert f3["steps"] == [{"first": 0, "last": 149}]
    assert (f3["first_time_s"], f3["last_time_s"]) == (0.0, pytest.approx(14.9))
    rows = list(csv.DictReader(open(files["csv"], newline="")))
    for i, r in enumerate(rows):
        assert r["warnings"] == " | ".join(run.step(i).warnings)
    from mcap.reader import make_reader

    meta = [dict(m.metadata) for m in make_reader(open(files["mcap"], "rb")).iter_metadata()]
    assert [m["message"] for m in meta] == [w["message"] for w in run.warnings]
    assert [m["steps"] for m in meta] == ["0-149", "0-149", "1-150", "1-150"]
