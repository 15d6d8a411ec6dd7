#!/usr/bin/env bash
# Where a fine-patch solve spends its time, per part: `perf record` of `grasp solve` on the
# bundled Hertz scene refined to N x N, on T threads, its samples grouped by the functions of
# each part. Prints a Markdown row per (N, T): the whole process's wall time and each part's
# share of the CPU samples (of all threads).
#
#   scripts/profile-fine-patch.sh [GRASP_BINARY] [N ...]     (default: target/release/grasp 512 1024)
#
# Needs Linux `perf` (linux-tools); threads from RAYON_NUM_THREADS (1 and 2 here).
set -euo pipefail
bin=${1:-target/release/grasp}
shift || true
sizes=${*:-512 1024}
command -v perf >/dev/null || { echo "perf is not installed (linux-tools): nothing to profile" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
here=$(cd "$(dirname "$0")/.." && pwd)
echo "| grid | threads | wall | model build | FFTs | tile gathers and spectrum products | D_F scatter and gather | CG vectors and sums | linearisation and line search | allocation and page faults | other |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for n in $sizes; do
  sed "s/\"grid\": \[21, 21\]/\"grid\": [$n, $n]/" "$here/examples/hertz_sphere_on_flat.json" > "$work/h$n.json"
  for t in 1 2; do
    start=$(date +%s.%N)
    RAYON_NUM_THREADS=$t perf record -q -o "$work/p.data" "$bin" solve "$work/h$n.json" > /dev/null 2>&1
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    perf report -i "$work/p.data" --no-children --sort symbol --stdio 2>/dev/null \
      | python3 -c '
import re, sys
parts = [
  ("model build", r"atan|__ieee754_log|log@@|RectangleIntegrals|KernelTable|BlockKernels|ComplianceOperator::set|CirculantInverse::new|wrapped_spectrum|half_space"),
  ("FFTs", r"rustfft|realfft"),
  ("tile gathers and spectrum products", r"grid_fft::"),
  ("D_F scatter and gather", r"free_operator::"),
  ("CG vectors and sums", r"projected_step|parallel_vectors"),
  ("linearisation and line search", r"linearisation|semismooth_newton|element_cone|projection"),
  ("allocation and page faults", r"\[k\]|memset|memmove|memcpy|malloc|free|_int_"),
]
share = {p: 0.0 for p, _ in parts}; other = 0.0
for line in sys.stdin:
    m = re.match(r"\s*([\d.]+)%\s+(.*)", line)
    if not m: continue
    pct, sym = float(m.group(1)), m.group(2)
    for p, rx in parts:
        if re.search(rx, sym):
            share[p] += pct; break
    else:
        other += pct
print(" | ".join(f"{share[p]:.0f} %" for p, _ in parts) + f" | {other:.0f} %")
' > "$work/row"
    echo "| ${n}x${n} | $t | ${wall:0:5} s | $(cat "$work/row") |"
  done
done
