#!/usr/bin/env python3
"""The peer measurement of the fine-patch cases: frictionless Hertz (or a given gap map) on an n x n grid, solved by tamaas.

`grasp bench` runs this script (compiled into the binary, fed on standard input) beside its
own `hertz_<n>x<n>_fft` cases; it also runs alone:

    ~/.cache/grasp-venv/bin/python scripts/peer-hertz.py --grid 128 --repeats 5

and prints one JSON line:

    {"peer": "tamaas", "version": "2.9.0", "grid": 128, "median_s": ..., "min_s": ...,
     "max_s": ..., "runs": 5, "tolerance": 1e-10, "p0_error": ..., "contact_radius_error": ...,
     "load_error": ...}

The peer: tamaas 2.9.0 (PyPI, installed by scripts/install-checkers.sh into
~/.cache/grasp-venv). Its pip build is serial (no OpenMP, no MPI). Tamaas models are periodic,
but it ships a non-periodic Boussinesq operator (`ModelFactory.registerNonPeriodic`, class
DCFFT): the influence coefficients of uniform pressure on each rectangular element, convolved
through a zero-padded 2N x 2N FFT (the DC-FFT construction). The solver is its
`PolonskyKeerRey` (conjugate gradients on the pressures, load-controlled: `solve(mean
pressure)`) with `setIntegralOperator(<that operator>)`. So no padding is done here: the peer
solves the free half-space problem, as grasp does.

The problem, the same as `examples/hertz_sphere_on_flat.json` on an n x n grid (the bench
passes the values it reads from the scene, so both solve the same numbers):
- square patch of width --width (0.212 mm) centred on the contact point, n x n square
  elements of side h = width / n, each value at the element's centre (x_i = (i + 1/2) h -
  width / 2), as grasp's elements;
- gap = the sphere's profile (x^2 + y^2) / (2 R), R = --radius (10 mm): tamaas's surface is
  the height -(x^2 + y^2) / (2 R);
- the half-space carries the combined modulus E* = --e-star (115.4 GPa for steel on steel):
  tamaas's E* is E / (1 - nu^2) of one body against a rigid one, so it gets nu = 0.3 and
  E = E* (1 - nu^2), which is the same E*;
- total load P = --load (10 N), i.e. mean pressure P / width^2 over the patch.

A gap map instead of the sphere (`--gap FILE`: n x n little-endian float64 values, m, element
`k = i n + j` with `i` along the patch's first side, as grasp's elements): the rough and ridged
cases (`rough_256x256_fft`, `ridged_256x256_fft`), whose gaps `grasp bench` writes from its
model, with the tilt its own solution gives the object (the object is free: the pressure's
resultant must pass under its centre of mass, which tilts a rough contact; tamaas's problem has
no moment rows, so it gets the tilted gap and solves the same contact). Hertz's errors are then
`null`; `p_max_pa` and `contact_elements` are reported in every case.

Tolerance: 1e-10, tamaas's own relative convergence measure (the value `solve` returns, which
must come out below it; max_iter stays at tamaas's default of 1000). grasp solves to 1e-10
on its scaled program's relative residuals, so the same number is the closest match the
peer's stopping rule allows. Checked at 128 x 128 and 256 x 256: the pressures at 1e-10 lie
within 3e-9 and 5e-9 of p0 of the peer's own answer at 1e-12, far below both codes'
discretisation error (7e-5 and 2e-5 of p0). Below about 1e-12 the peer's measure stalls: asked
for 1e-13 with max_iter 100,000 it ended at 128 x 128 with pressures 45 % of p0 away from that
answer, and ran for minutes at 256 x 256.

Time: as grasp's `build + solve` (model build, operator build, solve), the peer's whole setup
and solve: the profile array, `createModel`, `registerNonPeriodic` (its influence
coefficients and FFT), the solver object and `solve`; interpreter start and imports are not
timed (grasp's process start is not either). One untimed run first (as grasp's memory run),
then --repeats timed runs; the median is reported.

Checks against Hertz's closed form (Johnson 4.2; a = (3 P R / 4 E*)^(1/3), p0 = 3 P / (2 pi
a^2)), relative and signed:
- p0_error: the largest element pressure against p0;
- contact_radius_error: the radius of a circle of the contact area (elements with positive
  pressure times h^2) against a;
- load_error: the sum of element pressures times h^2 against P.

Exit codes: 0 with the JSON line; 3 when numpy or tamaas is missing (the message names
scripts/install-checkers.sh); 4 when the peer does not reach the tolerance; 2 for bad
arguments.
"""

import argparse
import json
import math
import statistics
import sys
import time

PEER = "tamaas"
TOLERANCE = 1e-10
MISSING = 3
NOT_CONVERGED = 4


def parse_args():
    ap = argparse.ArgumentParser(prog="peer-hertz.py", description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, required=True, help="elements per side, n (n x n)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs after one untimed run")
    ap.add_argument("--radius", type=float, default=0.01, help="sphere radius R, m")
    ap.add_argument("--e-star", type=float, default=210e9 / (2 * (1 - 0.3**2)), help="combined modulus E*, Pa")
    ap.add_argument("--load", type=float, default=10.0, help="total normal load P, N")
    ap.add_argument("--width", type=float, default=0.000212, help="patch width, m (square)")
    ap.add_argument("--gap", default=None, help="gap map instead of the sphere: n x n little-endian float64, m")
    args = ap.parse_args()
    if not 2 <= args.grid <= 4096:
        ap.error(f"--grid is {args.grid}; give 2 to 4096 elements per side")
    if not 1 <= args.repeats <= 1000:
        ap.error(f"--repeats is {args.repeats}; give 1 to 1000")
    for name in ("radius", "e_star", "load", "width"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            ap.error(f"--{name.replace('_', '-')} is {value}; give a positive number")
    return args


def import_peer():
    """numpy and tamaas, or exit 3 with the fix."""
    try:
        import numpy as np
        import tamaas as tm
    except ImportError as e:
        print(
            f"peer-hertz.py: {e.name or e} is missing for this Python; install the peer with "
            "`bash scripts/install-checkers.sh` (tamaas==2.9.0 into ~/.cache/grasp-venv)",
            file=sys.stderr,
        )
        sys.exit(MISSING)
    tm.set_log_level(tm.LogLevel.error)
    return np, tm


def solve_once(np, tm, args):
    """One setup and solve; returns (seconds, pressures, the peer's final error)."""
    n, width = args.grid, args.width
    nu = 0.3
    t0 = time.perf_counter()
    h = width / n
    if args.gap_m is not None:
        surface = -args.gap_m
    else:
        x = (np.arange(n) + 0.5) * h - width / 2
        xx, yy = np.meshgrid(x, x, indexing="ij")
        surface = -(xx**2 + yy**2) / (2 * args.radius)
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [width, width], [n, n])
    model.E = args.e_star * (1 - nu**2)
    model.nu = nu
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    solver = tm.PolonskyKeerRey(model, surface, TOLERANCE)
    solver.setIntegralOperator("dcfft")
    error = solver.solve(args.load / width**2)
    seconds = time.perf_counter() - t0
    return seconds, np.array(model.traction, copy=True), error


def closed_form_errors(np, args, pressure):
    """Signed relative errors of peak pressure, contact radius and load against Hertz (None
    for a gap map), with the peak pressure and the contact's elements."""
    h = args.width / args.grid
    found = {"p_max_pa": float(pressure.max()), "contact_elements": int(np.count_nonzero(pressure > 0))}
    if args.gap_m is not None:
        return {"p0_error": None, "contact_radius_error": None, "load_error": None, **found}
    a = (3 * args.load * args.radius / (4 * args.e_star)) ** (1 / 3)
    p0 = 3 * args.load / (2 * math.pi * a**2)
    area = np.count_nonzero(pressure > 0) * h * h
    return {
        "p0_error": float(pressure.max() / p0 - 1),
        "contact_radius_error": float(math.sqrt(area / math.pi) / a - 1),
        "load_error": float(pressure.sum() * h * h / args.load - 1),
        **found,
    }


def main():
    args = parse_args()
    np, tm = import_peer()
    from importlib.metadata import version

    args.gap_m = None
    if args.gap is not None:
        gap = np.fromfile(args.gap, dtype="<f8")
        if gap.size != args.grid**2 or not np.all(np.isfinite(gap)):
            print(f"peer-hertz.py: --gap {args.gap} has {gap.size} values (finite: {np.all(np.isfinite(gap))}); "
                  f"give {args.grid}^2 finite float64 values", file=sys.stderr)
            sys.exit(2)
        args.gap_m = gap.reshape(args.grid, args.grid)

    _, pressure, error = solve_once(np, tm, args)
    times = []
    for _ in range(args.repeats):
        seconds, pressure, error = solve_once(np, tm, args)
        times.append(seconds)
    if not error <= TOLERANCE:
        print(f"peer-hertz.py: {PEER} stopped at error {error:.3e} above the tolerance {TOLERANCE:g}", file=sys.stderr)
        sys.exit(NOT_CONVERGED)
    record = {
        "peer": PEER,
        "version": version(PEER),
        "grid": args.grid,
        "median_s": statistics.median(times),
        "min_s": min(times),
        "max_s": max(times),
        "runs": len(times),
        "tolerance": TOLERANCE,
        **closed_form_errors(np, args, pressure),
    }
    print(json.dumps(record))


if __name__ == "__main__":
    main()
