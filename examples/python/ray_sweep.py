"""A parameter sweep on a Ray cluster (or a local Ray runtime), over the grasp Python package.

`grasp batch` uses every core of one machine; Ray spreads the same work over many machines.
The scenes come from `grasp sweep` (or any JSONL file `grasp batch` reads: one scene per
line, bare or as {"id": ..., "scene": {...}, "vary": {...}}); each Ray task solves a chunk of
lines with `grasp.solve`; the result lines are written in input order with the fields of
`grasp batch` (id, index, of, status, reason, problems, vary, fingers, residuals, solver,
time_s), so the two outputs compare line by line.

    grasp sweep examples/cube_a.json --vary 'fingers[*].friction.mu=0.2:1.0:9' --out sweep.jsonl
    python examples/python/ray_sweep.py sweep.jsonl --out results.jsonl            # local Ray
    python examples/python/ray_sweep.py sweep.jsonl --out results.jsonl --address auto  # a cluster

Needs `pip install .` (the grasp package) and `pip install "ray[default]"` on every node.
"""

import argparse
import json
import os
import sys
import time

import ray

import grasp


# The relative residuals whose largest is a batch line's `worst_residual`.
WORST_OF = ("equilibrium_relative", "cone_violation_relative", "penetration_relative",
            "compatibility_relative", "complementarity_relative", "stick_motion_relative",
            "slip_direction_error")


def scene_lines(path):
    """(index, line number, text) of every non-blank line, as `grasp batch` numbers them."""
    with open(path, encoding="utf-8") as f:
        numbered = [(n + 1, line) for n, line in enumerate(f) if line.strip()]
    return [(i, n, text) for i, (n, text) in enumerate(numbered)]


def unwrap(n, text):
    """(id, scene source, vary) of one line; a bare scene gets the id `line-N`."""
    value = json.loads(text)
    if isinstance(value, dict) and "scene" in value:
        raw = value.get("id")
        ident = raw if isinstance(raw, str) else (str(raw) if isinstance(raw, (int, float)) else f"line-{n}")
        return ident, value["scene"], value.get("vary")
    return f"line-{n}", text, None


def result_line(index, of, n, text):
    """The result record of one scene line (the fields of a `grasp batch` line)."""
    try:
        ident, source, vary = unwrap(n, text)
    except ValueError as e:
        problem = {"path": ".", "message": str(e), "fix": "write one scene per line"}
        return invalid(f"line-{n}", index, of, None, [problem])
    # A wrapped scene is already parsed (as `grasp batch` parses it once, as a value); its
    # problems name JSON paths, with no position, whichever way it is read.
    wrapped = not isinstance(source, str)
    text = json.dumps(source, separators=(",", ":"), sort_keys=True) if wrapped else source
    try:
        scene = grasp.Scene.from_json(text)
    except grasp.SceneError as e:
        # Paths inside a wrapped line's scene read `scene.<path>`, as `grasp batch` writes them.
        prefix = "scene." if wrapped else ""
        problems = [dict(p, path=prefix + p["path"]) for p in e.problems]
        return invalid(ident, index, of, vary, problems)
    clock = time.perf_counter()
    sol = grasp.solve(scene)
    line = {"id": ident, "index": index, "of": of, "status": sol.status}
    if sol.reason is not None:
        line["reason"] = sol.reason
    if vary is not None:
        line["vary"] = vary
    keep = ("name", "normal_force_n", "tangential_force_n", "tangential_magnitude_n",
            "torsional_moment_nm", "friction_utilization")
    line["fingers"] = [finger_line(f, keep) for f in sol.fingers]
    sensors = sol.to_dict().get("sensors")
    if sensors:
        line["sensors"] = sensors
    if sol.residuals is not None:
        r = sol.residuals
        line["equilibrium_residual"] = r["equilibrium_relative"]
        line["worst_residual"] = max(0.0, *(r[k] for k in WORST_OF))
    line["solver"] = sol.solver["solver"]
    line["time_s"] = time.perf_counter() - clock
    return line


def finger_line(f, keep):
    """A finger's fields of a `grasp batch` line: its resultants, its core's displacement on a
    mount, and its stick fraction (stick over stick and slip elements; none without either)."""
    out = {k: f[k] for k in keep}
    if "mount_displacement" in f:
        out["mount_displacement"] = f["mount_displacement"]
    touching = f.get("stick_count", 0) + f.get("slip_count", 0)
    if touching > 0:
        out["stick_fraction"] = f.get("stick_count", 0) / touching
    return out


def invalid(ident, index, of, vary, problems):
    line = {"id": ident, "index": index, "of": of, "status": "invalid"}
    if problems:
        line["reason"] = f"{problems[0]['path']}: {problems[0]['message']}"
        line["problems"] = problems
    if vary is not None:
        line["vary"] = vary
    line.update({"fingers": [], "time_s": 0.0})
    return line


@ray.remote
def solve_chunk(chunk, of):
    """One Ray task: the result lines of a chunk of (index, line number, text)."""
    return [result_line(i, of, n, text) for i, n, text in chunk]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", help="JSONL of scenes (e.g. from `grasp sweep`)")
    p.add_argument("--out", required=True, help="result JSONL to write")
    p.add_argument("--address", default=None, help="Ray cluster address (default: start a local runtime)")
    p.add_argument("--chunk", type=int, default=64, help="scenes per Ray task (default 64)")
    p.add_argument("--cpus", type=int, default=None, help="CPUs of the local runtime (default: all)")
    p.add_argument("--force", action="store_true", help="replace --out if it exists")
    a = p.parse_args(argv)
    if a.chunk < 1:
        p.error("--chunk must be at least 1")
    if os.path.exists(a.out) and not a.force:
        p.error(f"{a.out} exists; pass --force to replace it")
    lines = scene_lines(a.scenes)
    of = len(lines)
    start = time.perf_counter()
    ray.init(address=a.address, num_cpus=a.cpus if a.address is None else None,
             include_dashboard=False, log_to_driver=False)
    try:
        chunks = [lines[k:k + a.chunk] for k in range(0, of, a.chunk)]
        futures = [solve_chunk.remote(c, of) for c in chunks]
        results = [line for chunk in ray.get(futures) for line in chunk]
    finally:
        ray.shutdown()
    tmp = a.out + ".partial"
    with open(tmp, "w", encoding="utf-8") as f:
        for line in results:
            f.write(json.dumps(line) + "\n")
    os.replace(tmp, a.out)
    counts = {}
    for line in results:
        counts[line["status"]] = counts.get(line["status"], 0) + 1
    summary = ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
    print(f"{of} scenes on Ray in {time.perf_counter() - start:.2f} s: {summary}; wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
