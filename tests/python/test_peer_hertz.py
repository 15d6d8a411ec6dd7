"""The peer of the fine-patch cases (tamaas, scripts/peer-hertz.py): its Hertz answer against the closed
form, its message when missing, and `grasp bench`'s peer rows (with the peer, and without it:
the bench goes on and says how to install it). The checker tamaas is installed by
scripts/install-checkers.sh; under scripts/test.sh (GRASP_REQUIRE_CHECKERS=1) a missing one
fails these tests instead of skipping them."""

import json
import re
import os
import subprocess
import sys

from conftest import ROOT, checker

SCRIPT = ROOT / "scripts" / "peer-hertz.py"

# examples/hertz_sphere_on_flat.json: patch width and the closed-form contact radius
# a = (3 P R / 4 E*)^(1/3) with P = 10 N, R = 10 mm, E* = 210 GPa / (2 (1 - 0.3^2)).
WIDTH = 0.000212
A = (3 * 10.0 * 0.01 / (4 * 210e9 / (2 * (1 - 0.09)))) ** (1 / 3)


def run_script(*args, python=(sys.executable,)):
    return subprocess.run([*python, str(SCRIPT), *map(str, args)], capture_output=True, text=True, cwd=ROOT)


def test_the_peer_matches_hertz_at_32x32():
    checker("tamaas", "the peer tamaas (scripts/install-checkers.sh) is not installed")
    out = run_script("--grid", 32, "--repeats", 1)
    assert out.returncode == 0, out.stderr
    record = json.loads(out.stdout.strip().splitlines()[-1])
    assert (record["peer"], record["version"], record["grid"], record["runs"]) == ("tamaas", "2.9.0", 32, 1)
    assert record["tolerance"] == 1e-10
    assert 0 < record["min_s"] <= record["median_s"] <= record["max_s"]
    # Peak pressure within 0.5 %: piecewise-constant pressure on 13 elements per contact
    # radius errs by about (h/a)^2 / 4 (measured: 0.41 % at 16x16, 0.13 % at 32x32, 0.03 % at
    # 64x64); a wrong E* convention (a factor 2 moves p0 by 59 %) or the periodic operator
    # instead of the non-periodic one (+9.4 % at 32x32) fails it.
    assert abs(record["p0_error"]) < 5e-3, record
    # Contact radius (of the contact area's circle) within one element, h / a = 7.6 %.
    assert abs(record["contact_radius_error"]) < WIDTH / 32 / A, record
    # The load is the peer's constraint: exact to rounding.
    assert abs(record["load_error"]) < 1e-9, record


def test_a_missing_peer_names_the_install_script():
    # -S: no site-packages, so neither numpy nor tamaas imports.
    out = run_script("--grid", 8, python=(sys.executable, "-S"))
    assert out.returncode == 3, out
    assert "scripts/install-checkers.sh" in out.stderr, out.stderr
    assert out.stdout == ""


def bench_rows(stdout):
    return [[c.strip() for c in line.strip("|").split(" | ")] for line in stdout.splitlines() if line.startswith("|")]


def test_bench_measures_the_peer_beside_the_fft_case(run_cli):
    checker("tamaas", "the peer tamaas (scripts/install-checkers.sh) is not installed")
    case = "hertz_128x128_fft"
    out = run_cli("bench", "--case", case, "--solver", "native", "--min-time", 0, "--markdown", "--peer", sys.executable)
    assert out.returncode == 0, out.stderr
    rows = bench_rows(out.stdout)
    assert all(len(r) == 12 for r in rows), out.stdout
    peer = [r for r in rows if r[0] == case and r[2] == "tamaas 2.9.0 (peer)"]
    assert len(peer) == 1, out.stdout
    assert peer[0][1] == "build + solve" and peer[0][6] == str(128 * 128), peer
    assert float(peer[0][10]) < 2e-4, peer  # the peer's peak-pressure error, as ours (7.3e-5)
    ratio = [r for r in rows if r[0] == f"{case} peer/ours"]
    assert len(ratio) == 1 and ratio[0][1] == "time ratio" and ratio[0][2] == "native", out.stdout
    assert ratio[0][3].endswith("x") and float(ratio[0][3][:-1]) > 0, ratio
    assert f"peer tamaas 2.9.0 on {case}: tolerance 1e-10" in out.stdout, out.stdout
    assert "bench: hertz_128x128_fft (peer)" in out.stderr.splitlines()


def test_bench_without_the_peer_goes_on_and_says_how_to_install_it(run_cli, tmp_path):
    # A Python without site-packages stands for a virtualenv without tamaas.
    python = tmp_path / "python"
    python.write_text(f'#!/bin/sh\nexec "{sys.executable}" -S "$@"\n')
    os.chmod(python, 0o755)
    case = "hertz_128x128_fft"
    out = run_cli("bench", "--case", case, "--solver", "native", "--min-time", 0, "--markdown", "--peer", python)
    assert out.returncode == 0, out.stderr
    rows = bench_rows(out.stdout)
    assert [r[2] for r in rows if r[0].startswith(case)] == ["native"], out.stdout
    notes = [line for line in out.stdout.splitlines() if line.startswith("peer not measured")]
    assert len(notes) == 1 and "scripts/install-checkers.sh" in notes[0], out.stdout


def test_the_peer_finds_our_rough_and_ridged_contacts(run_cli):
    """The rough and ridged pads at 256 x 256 (examples/rough_sphere_on_flat.json,
    ridged_sphere_on_flat.json): tamaas solves our gap map, tilted as our solution tilts the
    object, and finds our contact: the same elements in contact and the same peak pressure.
    Both solve the same discrete problem (the same rectangle influence coefficients through a
    zero-padded FFT, to relative tolerances 1e-10), so the peak pressures agree to 1e-8 (measured:
    5e-11 and 7e-11) and the contact sets to the element (9807 and 7908); the rough pad's own
    answer, reached from a coarser grid's (solver/grid_continuation.rs), is checked here by
    another code. A tilt of the wrong sign, or none, moves the rough peak by percents."""
    checker("tamaas", "the peer tamaas (scripts/install-checkers.sh) is not installed")
    cases = ["rough_256x256_fft", "ridged_256x256_fft"]
    out = run_cli("bench", "--case", ",".join(cases), "--solver", "native", "--min-time", 0, "--markdown",
                  "--peer", sys.executable)
    assert out.returncode == 0, out.stderr
    for case in cases:
        notes = [line for line in out.stdout.splitlines() if line.startswith(f"peer tamaas 2.9.0 on {case}:")]
        assert len(notes) == 1, out.stdout
        found = re.search(r"peak pressure ([0-9.e+-]+) Pa \(ours ([0-9.e+-]+), ([0-9.e+-]+)\), "
                          r"(\d+) elements in contact \(ours (\d+)\)", notes[0])
        assert found, notes[0]
        relative = float(found.group(3))
        assert abs(relative) < 1e-8, notes[0]
        assert int(found.group(4)) == int(found.group(5)) > 1000, notes[0]
        peer = [r for r in bench_rows(out.stdout) if r[0] == case and r[2] == "tamaas 2.9.0 (peer)"]
        assert len(peer) == 1 and peer[0][10] == "-", out.stdout
