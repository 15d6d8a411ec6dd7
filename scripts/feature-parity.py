"""Checks that Cargo resolves the same features for the Python module's dependencies when it
is built alone (`pip install .` runs `cargo rustc -p grasp-py`) as in the workspace's test
build. A difference makes the Python build compile those crates (Rerun's among them) a second
time; the fix is a feature pin in crates/grasp-py/Cargo.toml (see the rustix entry there).

    python scripts/feature-parity.py     (exit 1 and the differences when they differ)
"""

import subprocess
import sys


def features(*args):
    out = subprocess.run(
        ["cargo", "tree", *args, "-f", "{p}|{f}", "--prefix", "none"],
        capture_output=True, text=True, check=True,
    ).stdout
    found = {}
    for line in out.splitlines():
        if "|" not in line:
            continue
        package, feats = line.replace(" (*)", "").replace(" (proc-macro)", "").split("|", 1)
        found.setdefault(package, set()).update(f for f in feats.split(",") if f)
    return found


def main():
    workspace = features("--workspace", "--exclude", "grasp-py", "-e", "normal,build,dev")
    alone = features("-p", "grasp-py", "-e", "normal,build")
    diffs = [
        f"{p}: workspace has {sorted(workspace[p] - f)}, grasp-py alone has {sorted(f - workspace[p])}"
        for p, f in sorted(alone.items())
        if p in workspace and workspace[p] != f
    ]
    for d in diffs:
        print("feature parity:", d)
    print(f"feature parity: {len(alone)} packages of grasp-py checked, {len(diffs)} differ")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
