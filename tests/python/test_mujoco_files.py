"""grasp.mujoco reads and writes through the project's one file policy (hardening issue items
2, 5, 9, 10), as tests/python/test_outputs.py checks it for the rest of the package: outputs
that are links (dangling ones too), FIFOs, devices or folders are refused even with
overwrite=True / --force; an output that is a hard link of an input is refused; an output
another process is writing is refused, naming it; inputs (state file, rollout, material map,
MuJoCo model) that are /dev/zero, a FIFO or larger than their limit are refused with a named
error and nothing written; SIGTERM and SIGHUP end `python -m grasp.mujoco` with 128 + the
signal and leave nothing behind."""

import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

import grasp
from conftest import EXAMPLES, ROOT, checker

mujoco = checker("mujoco", reason="MuJoCo is not installed (scripts/install-checkers.sh installs mujoco==4.0.0)")
import grasp.mujoco as gm  # noqa: E402

MJ = EXAMPLES / "mujoco"
PINCH = MJ / "pinch.xml"
MATERIALS = MJ / "pinch.materials.json"
SCENE_ARGS = ["--object", "box", "--keyframe", "grasped", "--no-margin"]
MIB = 1 << 20


def python_m(*args, env=None, timeout=120):
    return subprocess.run([sys.executable, "-m", "grasp.mujoco", *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, env=dict(os.environ, **(env or {})), timeout=timeout)


def hidden(folder):
    """grasp's hidden files (temporary or lock files) left in `folder`."""
    return [p.name for p in folder.iterdir() if ".grasp-" in p.name]


@pytest.fixture(scope="module")
def pinch():
    model = gm.load_model(PINCH)
    data = gm.load_state(model, keyframe="grasped")
    return model, data, gm.scene_from(model, data, "box", materials=MATERIALS)


def test_mujoco_outputs_that_are_not_regular_files_are_refused_even_with_overwrite(pinch, tmp_path):
    _, _, g = pinch
    report = gm.compare(g, margins=False)
    victim = tmp_path / "victim.txt"
    victim.write_text("keep")
    link = tmp_path / "link.json"
    link.symlink_to(victim)
    dangling = tmp_path / "dangling.json"
    dangling.symlink_to(tmp_path / "nowhere.json")
    folder = tmp_path / "folder.json"
    folder.mkdir()
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    cases = [(link, "is a symbolic link"), (dangling, "dangling"), (folder, "is a folder"),
             ("/dev/null", "not a regular file (a device)"), (fifo, "a FIFO")]
    for target, words in cases:
        for overwrite in (False, True):
            with pytest.raises(ValueError, match=re.escape(words)):
                g.write(target, overwrite=overwrite)
            with pytest.raises(ValueError, match=re.escape(words)):
                report.write(json_path=target, overwrite=overwrite)
            force = ["--force"] if overwrite else []
            proc = python_m("scene", PINCH, *SCENE_ARGS, "--out", target, *force)
            assert proc.returncode == 1 and words in proc.stderr, proc.stderr
            proc = python_m("scene", PINCH, *SCENE_ARGS, "--out", tmp_path / "s.json", "--report", target, *force)
            assert proc.returncode == 1 and words in proc.stderr, proc.stderr
    assert victim.read_text() == "keep"
    assert not (tmp_path / "nowhere.json").exists() and not (tmp_path / "s.json").exists()
    assert os.path.islink(dangling) and os.path.islink(link) and folder.is_dir()
    assert fifo.is_fifo()
    assert hidden(tmp_path) == []


def test_mujoco_an_output_that_is_a_hard_link_of_an_input_is_refused(pinch, tmp_path):
    _, data, g = pinch
    materials = tmp_path / "map.json"
    materials.write_bytes(MATERIALS.read_bytes())
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"qpos": list(data.qpos), "qvel": list(data.qvel), "ctrl": list(data.ctrl)}))
    for source, name in [(materials, "map-link.json"), (state, "state-link.json")]:
        os.link(source, tmp_path / name)
    base = ["scene", PINCH, "--object", "box", "--no-margin", "--materials", materials, "--qpos", state]
    for target in ("map-link.json", "state-link.json"):
        for flag in ("--out", "--report"):
            outs = {"--out": tmp_path / "s.json", flag: tmp_path / target}
            proc = python_m(*base, *[x for kv in outs.items() for x in kv], "--force")
            assert proc.returncode == 1 and "is also an input of this command" in proc.stderr, proc.stderr
    with pytest.raises(ValueError, match="is also an input of this command"):
        gm.compare(g, margins=False).write(json_path=tmp_path / "map-link.json", overwrite=True, inputs=[materials])
    assert materials.read_bytes() == MATERIALS.read_bytes()
    assert json.loads(state.read_text())["qpos"] == list(data.qpos)
    assert not (tmp_path / "s.json").exists() and hidden(tmp_path) == []


def test_mujoco_an_output_another_process_is_writing_is_refused_naming_it(grasp_bin, pinch, tmp_path):
    _, _, g = pinch
    spec = json.loads((EXAMPLES / "plate_transfer.schedule.json").read_text())
    spec["time"]["step"] = 0.001
    long = tmp_path / "long.schedule.json"
    long.write_text(json.dumps(spec))
    out = tmp_path / "o.json"
    cli = subprocess.Popen([grasp_bin, "transfer", str(EXAMPLES / "plate_transfer.json"), "--schedule", str(long),
                            "--csv", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        lock = tmp_path / ".o.json.grasp-lock"
        deadline = time.monotonic() + 60
        while not (lock.exists() and lock.read_text().strip() == str(cli.pid)):
            assert cli.poll() is None and time.monotonic() < deadline, "the CLI never held the lock"
            time.sleep(0.02)
        holder = f"another run of grasp (process {cli.pid})"
        with pytest.raises(grasp.GraspError, match=re.escape(holder)):
            g.write(out, overwrite=True)
        with pytest.raises(grasp.GraspError, match=re.escape(holder)):
            gm.compare(g, margins=False).write(json_path=out, overwrite=True)
        proc = python_m("scene", PINCH, *SCENE_ARGS, "--out", out, "--force")
        assert proc.returncode == 1 and holder in proc.stderr, proc.stderr
    finally:
        cli.send_signal(signal.SIGTERM)
        cli.wait()
    assert not out.exists() and hidden(tmp_path) == []


def bad_inputs(tmp_path, limit_bytes):
    """(path, words of the refusal): /dev/zero, a FIFO, a folder, a (sparse) file one byte over
    the limit."""
    fifo = tmp_path / "pipe.in"
    os.mkfifo(fifo)
    big = tmp_path / "big.in"
    with open(big, "wb") as f:
        f.truncate(limit_bytes + 1)
    return [("/dev/zero", "is a device, not a regular file"), (fifo, "is a FIFO (named pipe), not a regular file"),
            (tmp_path, "is a folder, not a regular file"),
            (big, f"has {limit_bytes + 1} bytes, more than the {limit_bytes // MIB} MiB")]


def test_mujoco_inputs_that_are_not_regular_files_or_too_large_are_refused(pinch, tmp_path):
    model, data, _ = pinch
    ins = tmp_path / "in"
    ins.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    hmodel = gm.load_model(MJ / "handoff.xml")
    kinds = [
        ("state file", 64 * MIB, gm.StateError, lambda p: gm.load_state(model, qpos=p),
         ["scene", PINCH, "--object", "box", "--qpos"]),
        ("material map", 64 * MIB, gm.MaterialMapError, lambda p: gm.scene_from(model, data, "box", materials=p),
         ["scene", PINCH, "--object", "box", "--keyframe", "grasped", "--materials"]),
        ("MuJoCo model", 256 * MIB, gm.ModelLoadError, gm.load_model, ["scene"]),
        ("rollout", 1024 * MIB, gm.StateError, lambda p: gm.Rollout.load(p, hmodel),
         ["handoff", MJ / "handoff.xml", "--object", "cylinder", "--rollout"]),
    ]
    for what, limit, error, load, command in kinds:
        for path, words in bad_inputs(ins, limit):
            with pytest.raises(error, match=re.escape(f"{what} {path} {words}")):
                load(path)
            tail = ["--object", "box"] if command == ["scene"] else []
            target = out / ("h" if command[0] == "handoff" else "s.json")
            proc = python_m(*command, path, *tail, "--out", target, "--no-margin" if command[0] == "scene" else "--no-replay")
            assert proc.returncode == 1, (what, path, proc.stderr)
            assert f"error: {what} {path} {words}" in proc.stderr and "fix: give a" in proc.stderr, proc.stderr
            assert sorted(p.name for p in out.iterdir()) == [], (what, path)
        for p in ins.iterdir():
            p.unlink()


def test_mujoco_sigterm_and_sighup_end_the_command_with_nothing_left(tmp_path):
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    started = tmp_path / "started"
    (tmp_path / "slow.py").write_text(
        "import pathlib, time\n"
        "def control(model, data):\n"
        f"    pathlib.Path({str(started)!r}).touch()\n"
        "    time.sleep(0.01)\n")
    for sig in (signal.SIGTERM, signal.SIGHUP):
        started.unlink(missing_ok=True)
        proc = subprocess.Popen(
            [sys.executable, "-m", "grasp.mujoco", "handoff", str(MJ / "handoff.xml"), "--object", "cylinder",
             "--controller", f"{tmp_path / 'slow.py'}:control", "--steps", "100000",
             "--materials", str(MJ / "handoff.materials.json"), "--out", str(out / "h"), "--csv", str(out / "r.csv")],
            cwd=ROOT, env=dict(os.environ, TMPDIR=str(scratch)), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True)
        deadline = time.monotonic() + 60
        while not started.exists():
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
            time.sleep(0.02)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 128 + sig, err
        assert "interrupted" in err, err
        assert list(out.iterdir()) == [] and list(scratch.iterdir()) == []


FIFO = object()  # a case's file that is made a FIFO
LOAD_EACH = """
import json, sys
import grasp.mujoco as gm
for path in sys.argv[1:]:
    try:
        gm.load_model(path)
        print(json.dumps("loaded"), flush=True)
    except gm.ModelLoadError as e:
        print(json.dumps(str(e)), flush=True)
"""


def mjcf(body):
    return f"<mujoco>{body}<worldbody><body name='o'><freejoint/><geom size='.01'/></body></worldbody></mujoco>"


def file_cases():
    """(files {relative path: text, FIFO or a folder ""}, model file, the element that names
    the bad file, its path, words of the refusal)."""
    mesh = "<asset><mesh name='a' file='a.obj'/></asset>"
    urdf = ("<robot name='r'><link name='l'><collision><geometry><mesh filename='package://p/m.stl'/></geometry>"
            "</collision></link></robot>")
    return [
        ({"m.xml": mjcf(mesh), "a.obj": FIFO}, "m.xml", '<mesh file="a.obj">', "a.obj", "is a FIFO (named pipe)"),
        ({"m.xml": mjcf("<compiler meshdir='meshes'/>" + mesh), "meshes/a.obj": FIFO}, "m.xml", '<mesh file="a.obj">',
         "meshes/a.obj", "is a FIFO"),
        ({"m.xml": mjcf("<compiler texturedir='tex'/><asset><texture name='t' type='2d' file='t.png'/></asset>"),
          "tex/t.png": FIFO}, "m.xml", '<texture file="t.png">', "tex/t.png", "is a FIFO"),
        ({"m.xml": mjcf("<asset><texture name='t' type='cube' fileright='r.png' fileleft='l.png'/></asset>"),
          "r.png": FIFO}, "m.xml", '<texture fileright="r.png">', "r.png", "is a FIFO"),
        ({"m.xml": mjcf("<compiler assetdir='assets'/><asset><hfield name='h' file='h.png' size='1 1 1 1'/></asset>"),
          "assets/h.png": FIFO}, "m.xml", '<hfield file="h.png">', "assets/h.png", "is a FIFO"),
        ({"m.xml": mjcf("<deformable><skin name='s' file='s.skn'/></deformable>"), "s.skn": FIFO}, "m.xml",
         '<skin file="s.skn">', "s.skn", "is a FIFO"),
        ({"m.xml": mjcf("<asset><model name='sub' file='sub.xml'/></asset>"), "sub.xml": FIFO}, "m.xml",
         '<model file="sub.xml">', "sub.xml", "is a FIFO"),
        ({"m.xml": mjcf("<include file='inc.xml'/>"), "inc.xml": FIFO}, "m.xml", '<include file="inc.xml">', "inc.xml",
         "is a FIFO"),
        ({"m.xml": mjcf("<INCLUDE file='inc.xml'/>"), "inc.xml": FIFO}, "m.xml", '<include file="inc.xml">', "inc.xml",
         "is a FIFO"),
        ({"m.xml": mjcf("<include file='sub/a.xml'/>"), "sub/a.xml": "<mujoco><include file='b.xml'/></mujoco>",
          "sub/b.xml": FIFO}, "sub/a.xml", '<include file="b.xml">', "sub/b.xml", "is a FIFO"),
        ({"m.xml": mjcf("<include file='sub/a.xml'/>"), "sub/a.xml": f"<mujoco>{mesh}</mujoco>", "sub/a.obj": FIFO},
         "sub/a.xml", '<mesh file="a.obj">', "sub/a.obj", "is a FIFO"),
        ({"r.urdf": urdf, "m.stl": FIFO}, "r.urdf", '<mesh filename="package://p/m.stl">', "m.stl", "is a FIFO"),
        ({"m.xml": mjcf("<asset><mesh name='a' file='/dev/zero'/></asset>")}, "m.xml", '<mesh file="/dev/zero">',
         "/dev/zero", "is a device, not a regular file"),
        ({"m.xml": mjcf(mesh), "a.obj": ""}, "m.xml", '<mesh file="a.obj">', "a.obj", "is a folder, not a regular file"),
        ({"m.xml": mjcf("<asset><mesh name='a' file=' a.obj'/></asset>"), " a.obj": FIFO}, "m.xml",
         '<mesh file=" a.obj">', " a.obj", "is a FIFO"),
    ]


def make_files(folder, files):
    for rel, text in files.items():
        p = folder / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if text is FIFO:
            os.mkfifo(p)
        elif text == "":
            p.mkdir()
        else:
            p.write_text(text)


def test_mujoco_files_a_model_names_are_checked_as_the_model_is(tmp_path):
    """Item 1 of the hostile review: every file an MJCF (or URDF) names, its includes
    recursively, is refused as the model would be (a FIFO blocked MuJoCo for ever)."""
    models, expected = [], []
    for i, (files, naming, element, bad, words) in enumerate(file_cases()):
        folder = tmp_path / f"case{i}"
        make_files(folder, files)
        models.append(folder / next(iter(files)))
        path = bad if bad.startswith("/") else str(folder / bad)
        expected.append(f"{folder / naming}: {element} names {path}, which {words}")
    proc = subprocess.run([sys.executable, "-c", LOAD_EACH, *map(str, models)], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)
    assert proc.returncode == 0, proc.stderr
    said = [json.loads(line) for line in proc.stdout.splitlines()]
    for want, got in zip(expected, said, strict=True):
        assert got.startswith(want) and "; fix: make " in got, (want, got)
    # The command refuses it too, at once, writing nothing.
    out = tmp_path / "out"
    out.mkdir()
    proc = python_m("scene", models[0], "--object", "o", "--out", out / "s.json", timeout=60)
    assert proc.returncode == 1 and f"error: {expected[0]}" in proc.stderr, proc.stderr
    assert list(out.iterdir()) == []


def test_mujoco_files_models_whose_files_are_regular_still_load(tmp_path):
    """The files check refuses nothing MuJoCo can load: meshes under the compiler's meshdir and
    beside an include in a sub-folder, the examples."""
    cube = "".join(f"v {x} {y} {z}\n" for x in (-.01, .01) for y in (-.01, .01) for z in (-.01, .01))
    cube += "f 1 2 3\nf 1 3 5\nf 1 5 2\nf 8 7 6\nf 8 4 7\nf 8 6 4\nf 2 4 3\nf 2 6 4\nf 3 7 5\nf 3 4 7\nf 5 6 2\nf 5 7 6\n"
    make_files(tmp_path, {
        "m.xml": mjcf("<compiler meshdir='meshes'/><include file='sub/part.xml'/>"
                      "<asset><mesh name='a' file='cube.obj'/></asset>"),
        "meshes/cube.obj": cube, "sub/part.xml": "<mujoco><asset><mesh name='b' file='c.obj'/></asset></mujoco>",
        "sub/c.obj": cube})
    assert gm.load_model(tmp_path / "m.xml").nmesh == 2
    for name in ("pinch.xml", "handoff.xml"):
        assert gm.load_model(MJ / name).nbody > 1
