"""Writes examples/meshes/mug.obj: a mug of outer radius 40 mm and height 100 mm (a closed
cylinder, 48 segments around and a ring every 5 mm, its axis along z from z = 0) and a handle (a closed tube of radius 6 mm
bent on a circle of radius 30 mm in the x-z plane, its ends 4 mm inside the body), in mm.
Two closed components; the tube's ends are capped. Deterministic: the same file every run.

    python3 scripts/make-mug.py
"""

import math
import pathlib

N = 48            # segments around the body
R, H = 40.0, 100.0
TUBE_R, BEND_R, BEND_C = 6.0, 30.0, (R - 4.0, 50.0)   # handle: tube radius, bend radius, bend centre (x, z)
M, K = 36, 32     # handle: segments along the bend, around the tube


def body():
    """A closed cylinder with a ring of vertices every 5 mm up the side (the curvature fit
    needs vertices around each contact) and a centre vertex on each cap."""
    rings = [H * r / 20 for r in range(21)]
    v = [(0.0, 0.0, 0.0), (0.0, 0.0, H)]
    for z in rings:
        v += [(R * math.cos(2 * math.pi * i / N), R * math.sin(2 * math.pi * i / N), z) for i in range(N)]
    ring = lambda r, i: 2 + r * N + i % N
    top = len(rings) - 1
    f = []
    for i in range(N):
        f += [(0, ring(0, i + 1), ring(0, i)), (1, ring(top, i), ring(top, i + 1))]
        for r in range(top):
            f += [(ring(r, i), ring(r, i + 1), ring(r + 1, i + 1)), (ring(r, i), ring(r + 1, i + 1), ring(r + 1, i))]
    return v, f


def handle():
    # Bend angles from -100 to +100 degrees about the +x direction, in the x-z plane.
    angles = [math.radians(-100 + 200 * k / M) for k in range(M + 1)]
    v = []
    for a in angles:
        cx, cz = BEND_C[0] + BEND_R * math.cos(a) - BEND_R * math.cos(math.radians(100)), BEND_C[1] + BEND_R * math.sin(a)
        nx, nz = math.cos(a), math.sin(a)          # outward direction of the bend
        for k in range(K):
            t = 2 * math.pi * k / K
            v.append((cx + TUBE_R * math.cos(t) * nx, TUBE_R * math.sin(t), cz + TUBE_R * math.cos(t) * nz))
    f = []
    for s in range(M):
        for k in range(K):
            a, b = s * K + k, s * K + (k + 1) % K
            c, d = a + K, b + K
            f += [(a, c, b), (b, c, d)]
    ends = len(v)
    for s, centre_index in ((0, ends), (M, ends + 1)):
        a = angles[s]
        cx = BEND_C[0] + BEND_R * math.cos(a) - BEND_R * math.cos(math.radians(100))
        v.append((cx, 0.0, BEND_C[1] + BEND_R * math.sin(a)))
        for k in range(K):
            p, q = s * K + k, s * K + (k + 1) % K
            f.append((centre_index, p, q) if s == 0 else (centre_index, q, p))
    return v, f


def main():
    vb, fb = body()
    vh, fh = handle()
    lines = [f"# mug: body radius {R} mm, height {H} mm; handle tube {TUBE_R} mm (scripts/make-mug.py)"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vb + vh]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in fb]
    off = len(vb)
    lines += [f"f {a + off + 1} {c + off + 1} {b + off + 1}" for a, b, c in fh]  # wound outward
    out = pathlib.Path(__file__).resolve().parents[1] / "examples" / "meshes" / "mug.obj"
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}: {len(vb) + len(vh)} vertices, {len(fb) + len(fh)} triangles")


if __name__ == "__main__":
    main()
