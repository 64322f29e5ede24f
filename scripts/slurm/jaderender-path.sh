#!/usr/bin/env bash
# The jaderender the Slurm scripts run: $JADERENDER when set, else this
# checkout's build/jaderender, else the one on PATH. An absolute path, since
# jobs may start in another folder.
set -euo pipefail
if [ -n "${JADERENDER:-}" ]; then echo "$JADERENDER"; exit 0; fi
root=$(cd "$(dirname "$0")/../.." && pwd)
if [ -x "$root/build/jaderender" ]; then echo "$root/build/jaderender"; exit 0; fi
command -v jaderender || { echo "jaderender-path: no jaderender (build it, or set JADERENDER)" >&2; exit 2; }
