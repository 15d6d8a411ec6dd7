#!/usr/bin/env bash
# Expands a sweep, submits it as a Slurm job array of TASKS tasks, and the merge to run after
# every task succeeded. Run from the folder that should hold the results.
#
#   TASKS=16 bash examples/slurm/submit.sh examples/cube_a.json \
#       --vary 'fingers[*].friction.mu=0.2:1.0:9' --vary 'object.weight=1:10:10'
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
GRASP="${GRASP:-grasp}"
TASKS="${TASKS:-16}"
export SCENES="${SCENES:-sweep.jsonl}" OUTDIR="${OUTDIR:-results}" OUT="${OUT:-results.jsonl}" GRASP
[ $# -ge 1 ] || { echo "usage: $0 SCENE --vary PATH=A:B:N [--vary ...]" >&2; exit 2; }
"$GRASP" sweep "$@" --out "$SCENES"
array=$(sbatch --parsable --export=ALL --array=0-$((TASKS - 1)) "$here/sweep.sbatch")
sbatch --parsable --export=ALL --dependency=afterok:"$array" "$here/merge.sbatch"
echo "submitted array $array ($TASKS tasks) and its merge; results in $OUT"
