#!/usr/bin/env bash
# Usage: scripts/slurm-array.sh PLAN.toml [--shards N] [--output FILE] [--cpus C]
#                               [--impactid PROGRAM] [-- SBATCH OPTIONS...]
#
# Runs a grid or list plan as a Slurm job array of N shards (default 32), then merges them in a
# job that starts when every task has succeeded:
#
#   sbatch --array=0-(N-1) --cpus-per-task=C   impactid run PLAN --output FILE --resume
#   sbatch --dependency=afterok:<array job>    impactid merge FILE's shards --output FILE
#
# Each task computes its shard (impactid takes it from SLURM_ARRAY_TASK_ID, _MIN and _COUNT)
# into FILE's folder as <stem>.shard-K-of-N.h5, checkpointing as it goes; --resume lets a task
# that was requeued or preempted continue where it stopped, and lets you resubmit just the
# failed tasks (sbatch --array=3,17 ...) with the same command. The merge checks that the shards
# are of one plan and cover every point once, and writes FILE, identical to a single run's.
#
# FILE defaults to results/<plan stem>.h5. C (default 1) is each task's cores, used as its
# OpenMP threads. Options after `--` go to both sbatch calls (--partition, --time, --account,
# --mem...). PROGRAM defaults to the impactid on PATH, else build/study/impactid. Prints the two
# job ids. Logs: slurm-<job>_<task>.out in the current folder (sbatch's default).
set -euo pipefail

usage() { sed -n '2,3p' "$0" >&2; exit 2; }

plan="" shards=32 output="" cpus=1 impactid="" extra=()
while (($#)); do
  case "$1" in
    --shards) shards="$2"; shift 2 ;;
    --output) output="$2"; shift 2 ;;
    --cpus) cpus="$2"; shift 2 ;;
    --impactid) impactid="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) usage ;;
    -*) echo "slurm-array.sh: unknown option $1" >&2; usage ;;
    *) [ -z "$plan" ] || usage; plan="$1"; shift ;;
  esac
done
[ -n "$plan" ] || usage
[ -f "$plan" ] || { echo "slurm-array.sh: $plan: no such plan file" >&2; exit 2; }
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || { echo "slurm-array.sh: --shards $shards: a whole number >= 1" >&2; exit 2; }
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || { echo "slurm-array.sh: --cpus $cpus: a whole number >= 1" >&2; exit 2; }
if [ -z "$impactid" ]; then
  impactid="$(command -v impactid || true)"
  [ -n "$impactid" ] || impactid="$(cd "$(dirname "$0")/.." && pwd)/build/study/impactid"
fi
[ -x "$impactid" ] || { echo "slurm-array.sh: $impactid: not an executable impactid" >&2; exit 2; }
impactid="$(cd "$(dirname "$impactid")" && pwd)/$(basename "$impactid")"
plan="$(cd "$(dirname "$plan")" && pwd)/$(basename "$plan")"
[ -n "$output" ] || output="results/$(basename "${plan%.toml}").h5"
mkdir -p "$(dirname "$output")"
output="$(cd "$(dirname "$output")" && pwd)/$(basename "$output")"
stem="${output%.h5}"

q() { printf '%q' "$1"; }  # quoted for the job's shell

array_job=$(sbatch --parsable --job-name="impactid-$(basename "$stem")" \
  --array="0-$((shards - 1))" --cpus-per-task="$cpus" "${extra[@]}" \
  --wrap="OMP_NUM_THREADS=$cpus $(q "$impactid") run $(q "$plan") --output $(q "$output") --resume")
array_job="${array_job%%;*}"
merge_job=$(sbatch --parsable --job-name="impactid-merge-$(basename "$stem")" \
  --dependency="afterok:$array_job" --cpus-per-task=1 "${extra[@]}" \
  --wrap="$(q "$impactid") merge $(q "$stem").shard-*-of-$shards.h5 --output $(q "$output")")
merge_job="${merge_job%%;*}"
echo "slurm-array.sh: array job $array_job ($shards shards of $(basename "$plan")), merge job $merge_job -> $output" >&2
echo "$array_job $merge_job"
