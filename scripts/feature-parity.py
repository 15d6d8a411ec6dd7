"""Checks that Cargo resolves the same features for the Python module's dependencies when it
is built alone (`pip install .` runs `cargo rustc -p grasp-py`) as in the two builds that come
before it: the workspace's test build (scripts/test.sh) and the CLI built alone (the README's
`cargo run --release`, whose default member is grasp-cli). A difference makes the Python build
compile those crates (Rerun's among them) a second time; the fix is a feature pin (see the
rustix entries of crates/grasp-py/Cargo.toml and crates/grasp-cli/Cargo.toml).

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


def differences(before, alone, name):
    """Lines naming each package of `alone` whose features differ in the build `name`."""
    return [
        f"{p}: {name} has {sorted(before[p] - f)}, grasp-py alone has {sorted(f - before[p])}"
        for p, f in sorted(alone.items())
        if p in before and before[p] != f
    ]


def main():
    alone = features("-p", "grasp-py", "-e", "normal,build")
    builds = {
        "the workspace": features("--workspace", "--exclude", "grasp-py", "-e", "normal,build,dev"),
        "grasp-cli alone": features("-p", "grasp-cli", "-e", "normal,build"),
    }
    diffs = [d for name, before in builds.items() for d in differences(before, alone, name)]
    for d in diffs:
        print("feature parity:", d)
    print(f"feature parity: {len(alone)} packages of grasp-py checked against "
          f"{' and '.join(builds)}, {len(diffs)} differ")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
