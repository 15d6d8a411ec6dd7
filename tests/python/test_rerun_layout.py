"""The default layout a `grasp transfer --rrd` recording opens on equals the one Rerun's own
Python blueprint API writes for the same description (3-D view of `/world` above each finger's
patch seen flat, pressure and state, with their key, beside the force plots): the two
blueprint stores, printed by the rerun CLI and with their random ids replaced
by what they name, hold the same rows. The layout is built by hand in Rust (fixed ids, so the
file stays deterministic); this is the independent check that it is what the SDK would send.
"""

import os
import re
import subprocess

import pytest

from conftest import EXAMPLES, rerun_cli

pytestmark = pytest.mark.skipif(rerun_cli() is None, reason="the rerun CLI (scripts/install-checkers.sh) is not installed")

ENV = dict(os.environ, CI="1")
UUID = r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}"


def blueprint_rows(path):
    """{entity path: {component: value}} of every blueprint chunk in the file."""
    out = subprocess.run([rerun_cli(), "rrd", "print", "-vvv", str(path)], capture_output=True, text=True, env=ENV)
    assert out.returncode == 0, out.stderr
    rows, entity, header = {}, None, None
    for line in out.stdout.splitlines():
        m = re.match(r"Chunk\(\S+\) with \d+ rows \(.*?\) - (\S+) - ", line)
        if m:
            entity, header = m.group(1), None
            continue
        cells = [c.strip() for c in line.strip("│ ").split("┆")]
        if cells and cells[0] == "RowId":
            header = cells
        elif header and cells and cells[0].startswith("row_") and re.match(r"/(view|container|viewport|time_panel)", entity):
            rows[entity] = {k: v for k, v in zip(header, cells) if ":" in k}
    return rows


def uuid_bytes_text(u):
    return "[[" + ", ".join(str(b) for b in bytes.fromhex(u.replace("-", ""))) + "]]"


def normalised(rows):
    """Rows with each view's id replaced by its origin and each container's by its contents."""
    names = {}
    for entity, comps in rows.items():
        m = re.fullmatch(rf"/view/({UUID})", entity)
        if m:
            names[m.group(1)] = "view" + comps["ViewBlueprint:space_origin"]
    for _ in range(3):  # containers hold views, then containers
        for entity, comps in rows.items():
            m = re.fullmatch(rf"/container/({UUID})", entity)
            if m:
                names[m.group(1)] = "container" + rename(comps["ContainerBlueprint:contents"], names)
    out = {}
    for entity, comps in rows.items():
        comps = dict(comps)
        if "ViewportBlueprint:root_container" in comps:
            for u, name in names.items():
                comps["ViewportBlueprint:root_container"] = comps["ViewportBlueprint:root_container"].replace(
                    uuid_bytes_text(u), name)
        out[rename(entity, names)] = {k: rename(v, names) for k, v in comps.items()}
    return out


def rename(text, names):
    """Ids replaced by names; an id the printer cut short (cells end with "…" past about 100
    characters) becomes "…" on both sides."""
    text = re.sub(r"[0-9a-f-]*…", "…", text)
    return re.sub(UUID, lambda m: names.get(m.group(0), "?"), text)


def python_layout(path, margins, fingers, steps=True):
    import rerun.blueprint as rrb

    if not steps:
        # Nothing to plot and no patch to show: the 3-D view alone.
        rrb.Blueprint(rrb.Horizontal(rrb.Spatial3DView(origin="/world", name="grasp")),
                      rrb.TimePanel(timeline="schedule_time"),
                      auto_layout=False, auto_views=False).save("grasp", str(path))
        return

    plots = [rrb.TimeSeriesView(origin="/plots/normal_force", name="normal force [N]"),
             rrb.TimeSeriesView(origin="/plots/friction", name="friction force [N]")]
    if margins:
        plots.append(rrb.TimeSeriesView(origin="/plots/margin", name="smallest margin [N]"))
    patches = []
    for finger in fingers:
        patches += [rrb.TensorView(origin=f"/patches/{finger}/pressure", name=f"{finger} pressure [kPa]"),
                    rrb.Spatial2DView(origin=f"/patches/{finger}/state", name=f"{finger} stick / slip")]
    if patches:
        patches.append(rrb.TextDocumentView(origin="/patches/key", name="key"))
        left = rrb.Vertical(rrb.Spatial3DView(origin="/world", name="hand-off"), rrb.Grid(*patches, name="patches"),
                            row_shares=[3, 2], name="hand-off and patches")
    else:
        left = rrb.Spatial3DView(origin="/world", name="hand-off")
    rrb.Blueprint(
        rrb.Horizontal(left, rrb.Vertical(*plots, name="forces"), column_shares=[3, 2]),
        rrb.TimePanel(timeline="schedule_time"),
        auto_layout=False, auto_views=False,
    ).save("grasp", str(path))


@pytest.mark.parametrize("margins", [False, True])
def test_the_recording_opens_on_the_layout_rerun_would_write(run_cli, tmp_path, margins):
    rrd = tmp_path / "h.rrd"
    args = ["transfer", EXAMPLES / "cylinder_handoff.json", "--schedule", EXAMPLES / "cylinder_handoff.schedule.json",
            "--rrd", rrd] + (["--margins"] if margins else [])
    done = run_cli(*args)
    assert done.returncode == 0, done.stderr
    # Every finger of the cylinder hand-off has a patch small enough for flat views.
    fingers = ["a1", "a2", "b1", "b2"]
    python_layout(tmp_path / "ref.rbl", margins, fingers)
    ours, ref = normalised(blueprint_rows(rrd)), normalised(blueprint_rows(tmp_path / "ref.rbl"))
    # Two rows a view (its contents and itself); containers: forces, patches, the left column,
    # the root; the viewport.
    views = 3 + margins + 2 * len(fingers) + 1
    assert len(ref) == 2 * views + 4 + 1 + 1, ref.keys()  # and the time panel
    assert ours == ref
    assert "?" not in repr(ours)


def test_a_margin_recording_has_no_empty_views(run_cli, tmp_path):
    """`grasp margin --rrd` logs no step: its layout has no patch grid and no force plots
    (nothing would fill them), only the 3-D view with the wrench surface; the recording logs
    nothing under `/plots` or `/patches` and is named after the scene."""
    rrd = tmp_path / "m.rrd"
    done = run_cli("margin", EXAMPLES / "box_pinch.json", "--rrd", rrd)
    assert done.returncode == 0, done.stderr
    python_layout(tmp_path / "ref.rbl", False, [], steps=False)
    ours = normalised(blueprint_rows(rrd))
    assert ours == normalised(blueprint_rows(tmp_path / "ref.rbl"))
    assert "/patches" not in repr(ours) and "/plots" not in repr(ours)
    out = subprocess.run([rerun_cli(), "rrd", "print", str(rrd)], capture_output=True, text=True, env=ENV)
    assert out.returncode == 0, out.stderr
    entities = set(re.findall(r" - (/\S+) - ", out.stdout))
    assert any(e.startswith("/world/margin/") for e in entities), entities
    assert not any(e.startswith(("/plots", "/patches")) for e in entities), entities
    verbose = subprocess.run([rerun_cli(), "rrd", "print", "-vvv", str(rrd)], capture_output=True, text=True, env=ENV)
    assert "box_pinch margins" in verbose.stdout
    assert not re.search(r"smallest margin [0-9.]+e", verbose.stdout)


def plot_names(path):
    """The series names the recording gives its force plots (the rerun CLI's print)."""
    out = subprocess.run([rerun_cli(), "rrd", "print", "-vvv", str(path)], capture_output=True, text=True, env=ENV)
    assert out.returncode == 0, out.stderr
    return set(re.findall(r"\[(\w+ (?:normal|friction) force \[N\](?: \([^)]*\))?)\]", out.stdout))


def test_symmetric_fingers_plots_say_their_curves_coincide(run_cli, tmp_path):
    """Fingers with identical curves (one hidden behind the other) say so in the recording's
    plot legends, the same groups as the SVG's note names: the plate's pairs f1 = f2 and
    f3 = f4 among them; a finger with a curve of its own says nothing."""
    for scene in ["plate_transfer", "disc_transfer"]:
        rrd, svg = tmp_path / f"{scene}.rrd", tmp_path / f"{scene}.svg"
        done = run_cli("transfer", EXAMPLES / f"{scene}.json", "--schedule", EXAMPLES / f"{scene}.schedule.json",
                       "--rrd", rrd, "--plot", svg)
        assert done.returncode == 0, done.stderr
        note = re.search(r">\s*([^<>]*?): identical curves", svg.read_text())
        groups = [g.split(" = ") for g in note.group(1).split(", ")] if note else []
        if scene == "plate_transfer":
            assert groups == [["f1", "f2"], ["f3", "f4"]]
        expected = {f"{f} {what} force [N] ({' = '.join(g)}: identical curves)"
                    for g in groups for f in g for what in ["normal", "friction"]}
        names = plot_names(rrd)
        assert names, "no plot names in the recording"
        assert {n for n in names if "identical" in n} == expected
