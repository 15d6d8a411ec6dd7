"""Python overhead per grasp.solve call, as a table (a benchmark, not a test).

For each scene: the median wall time of `grasp.solve(scene)` seen from Python, against the
median in-process time of the same calls measured inside Rust (model build + solve:
`build_time_s + solve_time_s`), and the same with every element array fetched as well
(positions, normal and tangential forces, states). Overhead = Python / in-process - 1.

    python scripts/bench-python.py [--repeat N] [--markdown]
"""

import argparse
import json
import pathlib
import statistics
import time

import grasp

ROOT = pathlib.Path(__file__).resolve().parents[1]


def cases():
    cube = json.loads((ROOT / "examples/cube_a.json").read_text())
    fine = json.loads(json.dumps(cube))
    for f in fine["fingers"]:
        f["patch"]["grid"] = [16, 16]
    return [
        ("cube A, 3 x 5x5", grasp.Scene(cube), 400),
        ("plate, 4 fingers", grasp.Scene(ROOT / "examples/plate_transfer.json"), 200),
        ("plate coulomb", grasp.Scene(ROOT / "examples/plate_handoff_coulomb.json"), 100),
        ("cube A, 3 x 16x16", grasp.Scene(fine), 8),
    ]


def measure(scene, repeat):
    """Medians of (in-process, Python call, in-process, call + arrays), calls interleaved so
    that both see the same machine."""
    inside, call, inside_full, full = [], [], [], []
    for _ in range(repeat):
        for fetch, wall, rust in ((False, call, inside), (True, full, inside_full)):
            t0 = time.perf_counter()
            sol = grasp.solve(scene)
            if fetch:
                (sol.positions_m, sol.normal_forces_n, sol.tangential_forces_n, sol.states)
            wall.append(time.perf_counter() - t0)
            rust.append(sol.build_time_s + sol.solve_time_s)
    return tuple(statistics.median(v) for v in (inside, call, inside_full, full))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=float, default=1.0, help="scale the repetitions (default 1)")
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    a = p.parse_args()
    rows = []
    for name, scene, n in cases():
        n = max(3, int(n * a.repeat))
        measure(scene, max(1, n // 10))  # warm-up
        inside, call, inside_full, full = measure(scene, n)
        rows.append((name, n, inside * 1e3, call * 1e3, call / inside - 1, full * 1e3, full / inside_full - 1))
    head = ("case", "calls", "in-process ms", "Python call ms", "overhead", "call + arrays ms", "overhead")
    if a.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
    else:
        print("  ".join(f"{h:>16}" for h in head))
    for r in rows:
        cells = (r[0], str(r[1]), f"{r[2]:.3f}", f"{r[3]:.3f}", f"{100 * r[4]:+.1f} %", f"{r[5]:.3f}", f"{100 * r[6]:+.1f} %")
        print("| " + " | ".join(cells) + " |" if a.markdown else "  ".join(f"{c:>16}" for c in cells))


if __name__ == "__main__":
    main()
