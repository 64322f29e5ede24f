#!/usr/bin/env bash
# Submits a render split into N pieces to Slurm: an array job of N tasks,
# task I rendering `jaderender render --job JOB --piece I/N`, and a merge job
# that starts when every piece has succeeded. The merged image is
# bit-identical to one render of the job (README: "Rendering on a cluster").
#
#   scripts/slurm/split-render.sh --job JOB --pieces N [--out OUT.exr] [--retries R] [-- SBATCH-OPTIONS...]
#
# --out       the merged image (default: the job's output); the pieces are
#             written beside it as <name>.part-sA-B.exr
# --retries   how often a failed piece is given back to Slurm (default 2)
# Options after -- go to both sbatch calls (e.g. --partition, --time,
# --cpus-per-task: each piece uses the CPUs Slurm gives its task).
# Prints the two job ids: the pieces' array job and the merge job.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
job="" pieces="" out="" retries=2
while [ $# -gt 0 ]; do
  case "$1" in
    --job) job=$2; shift 2 ;;
    --pieces) pieces=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --retries) retries=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "split-render: unknown option '$1' (see the comment at the top of $0)" >&2; exit 2 ;;
  esac
done
[ -n "$job" ] && [ -n "$pieces" ] || { echo "split-render: give --job JOB and --pieces N" >&2; exit 2; }
[ -f "$job" ] || { echo "split-render: $job: no such job file" >&2; exit 2; }
[[ "$pieces" =~ ^[1-9][0-9]*$ ]] || { echo "split-render: --pieces must be a whole number >= 1" >&2; exit 2; }
export JADERENDER=${JADERENDER:-$("$here/jaderender-path.sh")}

array=$(sbatch --parsable --job-name=jade-piece --array="0-$((pieces - 1))" --requeue "$@" \
  "$here/render-piece.sbatch" "$job" "$pieces" "$out" "$retries")
array=${array%%;*}
merge=$(sbatch --parsable --job-name=jade-merge --dependency="afterok:$array" --kill-on-invalid-dep=yes "$@" \
  "$here/merge.sbatch" "$job" "$pieces" "$out")
merge=${merge%%;*}
echo "pieces: job $array (array of $pieces tasks); merge: job $merge (after all pieces succeed)"
