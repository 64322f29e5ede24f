#!/usr/bin/env bash
# Submits a manifest of fits to Slurm: an array job with one task per entry
# (`jaderender batch MANIFEST --index I`), and a summary job that runs when
# every task has ended, succeeded or not, and gathers the reports into
# summary.csv and contact-sheet.png beside the manifest.
#
#   scripts/slurm/batch.sh MANIFEST [--retries R] [-- SBATCH-OPTIONS...]
#
# --retries   how often a failed entry is given back to Slurm (default 1)
# Options after -- go to both sbatch calls. Prints the two job ids.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
manifest="" retries=1
while [ $# -gt 0 ]; do
  case "$1" in
    --retries) retries=$2; shift 2 ;;
    --) shift; break ;;
    -*) echo "batch: unknown option '$1' (see the comment at the top of $0)" >&2; exit 2 ;;
    *) manifest=$1; shift ;;
  esac
done
[ -n "$manifest" ] || { echo "batch: give the manifest" >&2; exit 2; }
export JADERENDER=${JADERENDER:-$("$here/jaderender-path.sh")}
count=$("$JADERENDER" batch "$manifest" --count)  # also checks the manifest before anything is submitted

array=$(sbatch --parsable --job-name=jade-fit --array="0-$((count - 1))" --requeue "$@" \
  "$here/fit-entry.sbatch" "$manifest" "$retries")
array=${array%%;*}
folder=$(dirname "$manifest")
summary=$(sbatch --parsable --job-name=jade-summary --dependency="afterany:$array" "$@" \
  --wrap "\"$JADERENDER\" summary \"$manifest\" --out \"$folder/summary.csv\" --sheet \"$folder/contact-sheet.png\"" \
  --output="jade-summary-%j.log" --open-mode=append)
summary=${summary%%;*}
echo "fits: job $array (array of $count tasks); summary: job $summary (after all fits end)"
