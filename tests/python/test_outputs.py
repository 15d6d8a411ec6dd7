"""Python outputs keep the CLI's rules: one output policy (the same Rust
code as the CLI's). Threads writing the same outputs never mix them; targets that are links
(dangling ones too), devices or inputs of the run are refused even with overwrite=True; a
planted link at the old predictable temporary name redirects nothing; a run of the CLI holding
an output is named; every input is a regular file; a run keeps bounded memory."""

import concurrent.futures
import csv
import json
import os
import re
import signal
import subprocess
import time

import pytest

import grasp
from conftest import EXAMPLES

SCENE = EXAMPLES / "plate_transfer.json"
SCHEDULE = EXAMPLES / "plate_transfer.schedule.json"


def hidden(folder):
    """grasp's hidden files (temporary or lock files) left in `folder`."""
    return [p.name for p in folder.iterdir() if ".grasp-" in p.name]


def test_four_threads_writing_the_same_outputs_never_mix_them(tmp_path):
    scene = grasp.Scene(SCENE)
    files = {"csv": tmp_path / "h.csv", "mcap": tmp_path / "h.mcap"}

    def run(_):
        try:
            return len(grasp.transfer(scene, SCHEDULE, overwrite=True, **files))
        except grasp.GraspError as e:
            return str(e)

    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        outcomes = list(pool.map(run, range(4)))
    assert 200 in outcomes, outcomes
    for o in outcomes:
        assert o == 200 or "is being written by another run of grasp in this process" in o, o
    rows = list(csv.reader(open(files["csv"], newline="")))
    assert len(rows) == 201 and len({len(r) for r in rows}) == 1  # header + 200 steps, not ragged
    assert files["mcap"].read_bytes()[:8] == b"\x89MCAP0\r\n"
    assert hidden(tmp_path) == []


def test_links_devices_and_other_non_files_are_refused_even_with_overwrite(tmp_path):
    scene = grasp.Scene(SCENE)
    victim = tmp_path / "victim.txt"
    victim.write_text("keep")
    link = tmp_path / "link.csv"
    link.symlink_to(victim)
    dangling = tmp_path / "dangling.csv"
    dangling.symlink_to(tmp_path / "nowhere.csv")
    folder = tmp_path / "folder.csv"
    folder.mkdir()
    cases = [(link, "is a symbolic link"), (dangling, "dangling"), (folder, "is a folder"),
             ("/dev/null", "not a regular file (a device)")]
    fifo = tmp_path / "pipe.csv"
    if hasattr(os, "mkfifo"):
        os.mkfifo(fifo)
        cases.append((fifo, "a FIFO"))
    for target, words in cases:
        for overwrite in (False, True):
            with pytest.raises(ValueError, match=re.escape(words)):
                grasp.transfer(scene, SCHEDULE, csv=target, overwrite=overwrite)
    assert victim.read_text() == "keep"
    assert not (tmp_path / "nowhere.csv").exists()
    assert os.path.islink(dangling) and os.path.islink(link)
    assert hidden(tmp_path) == []


def test_a_planted_link_at_a_temporary_name_redirects_nothing(tmp_path):
    scene = grasp.Scene(SCENE)
    victim = tmp_path / "victim.txt"
    victim.write_text("keep")
    # The name the old writer used (predictable: the target and the process id).
    (tmp_path / f".h.csv.partial-{os.getpid()}").symlink_to(victim)
    run = grasp.transfer(scene, SCHEDULE, csv=tmp_path / "h.csv")
    assert run.written == [str(tmp_path / "h.csv")]
    assert victim.read_text() == "keep"
    assert (tmp_path / "h.csv").read_text().startswith("time_s,")


def test_no_input_of_a_run_is_an_output(tmp_path):
    for name in ("plate_handoff_coulomb.json", "plate_bump.schedule.json", "plate_bump.csv"):
        (tmp_path / name).write_bytes((EXAMPLES / name).read_bytes())
    scene = grasp.Scene(tmp_path / "plate_handoff_coulomb.json")
    schedule = tmp_path / "plate_bump.schedule.json"
    link = tmp_path / "scene-link.json"
    link.symlink_to(tmp_path / "plate_handoff_coulomb.json")
    linked = grasp.Scene(link)
    for s, target in [(scene, "plate_handoff_coulomb.json"), (linked, "plate_handoff_coulomb.json"),
                      (scene, "plate_bump.schedule.json"), (scene, "plate_bump.csv")]:
        with pytest.raises(ValueError, match="is also an input of this command"):
            grasp.transfer(s, schedule, csv=tmp_path / target, overwrite=True)
    for name in ("plate_handoff_coulomb.json", "plate_bump.schedule.json", "plate_bump.csv"):
        assert (tmp_path / name).read_bytes() == (EXAMPLES / name).read_bytes()


def test_an_output_the_cli_is_writing_is_refused_naming_its_process(grasp_bin, tmp_path):
    spec = json.loads(SCHEDULE.read_text())
    spec["time"]["step"] = 0.001
    long = tmp_path / "long.schedule.json"
    long.write_text(json.dumps(spec))
    out = tmp_path / "o.csv"
    cli = subprocess.Popen([grasp_bin, "transfer", str(SCENE), "--schedule", str(long), "--csv", str(out)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        lock = tmp_path / ".o.csv.grasp-lock"
        deadline = time.monotonic() + 60
        while not (lock.exists() and lock.read_text().strip() == str(cli.pid)):
            assert cli.poll() is None and time.monotonic() < deadline, "the CLI never held the lock"
            time.sleep(0.02)
        with pytest.raises(grasp.GraspError, match=f"another run of grasp \\(process {cli.pid}\\)"):
            grasp.transfer(grasp.Scene(SCENE), SCHEDULE, csv=out, overwrite=True)
    finally:
        cli.send_signal(signal.SIGTERM)
        cli.wait()
    assert not out.exists() and hidden(tmp_path) == []


def test_inputs_are_regular_files(tmp_path):
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    for path, words in [("/dev/zero", "a device"), (fifo, "a FIFO"), (tmp_path, "a folder")]:
        with pytest.raises(OSError, match=words):
            grasp.Scene(path)
        with pytest.raises(OSError, match=words):
            grasp.transfer(grasp.Scene(SCENE), path)
    # A mesh whose OBJ names /dev/zero as its material library: the geometry is read.
    (tmp_path / "meshes").mkdir()
    mug = (EXAMPLES / "meshes" / "mug.obj").read_text()
    (tmp_path / "meshes" / "mug.obj").write_text("mtllib /dev/zero\n" + mug)
    (tmp_path / "mug.json").write_text((EXAMPLES / "mug_power_grasp.json").read_text())
    assert grasp.solve(grasp.Scene(tmp_path / "mug.json")).status == "solved"


def test_a_run_keeps_bounded_memory():
    scene = grasp.Scene(SCENE)
    full = grasp.transfer(scene, SCHEDULE)
    lean = grasp.transfer(scene, SCHEDULE, keep_solutions=False)
    assert (lean.normal_forces_n == full.normal_forces_n).all()
    assert (lean.statuses == full.statuses).all() and len(lean) == len(full) == 200
    assert lean.step(-1).to_dict()["fingers"] == full.step(-1).to_dict()["fingers"]
    with pytest.raises(IndexError, match="keep_solutions=False"):
        lean.step(0)
    # 800,001 steps: every solution would need gigabytes; refused before the run.
    spec = json.loads(SCHEDULE.read_text())
    spec["time"] = {"start": 0, "end": 20, "step": 2.5e-5}
    with pytest.raises(grasp.GraspError, match="keep_solutions=False"):
        grasp.transfer(scene, spec, max_memory=2**30)
    with pytest.raises(grasp.GraspError, match="shorten the schedule"):
        grasp.transfer(scene, spec, keep_solutions=False, max_memory=2**20)
