#!/usr/bin/env bash
# Side-by-side benchmark against Mitsuba 3 on the reference scenes A, B, C
# (README, "Benchmarks"): seconds of rendering each renderer needs to reach
# RMSE 0.05 and 0.02, interleaved in one run, 2 threads each.
#   bash scripts/bench-race.sh [repeats] [scenes]     (default: 3 ABC)
# Installs what it needs (Mitsuba 3.9.1 and numpy in bench-work/venv, LLVM 19
# for Mitsuba's LLVM back end), builds jaderender, and writes
# bench/mitsuba/race_raw.jsonl, race_runs.csv, race_summary.csv and a table.
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=${1:-3}
scenes=${2:-ABC}

bash scripts/setup.sh
source scripts/bench-venv.sh
# A copy of the binary, so a rebuild during the run cannot change it.
cp build/jaderender "$work/jaderender"
export JADERENDER=$work/jaderender PERF_WORK=$work
"$work/venv/bin/python" bench/mitsuba/race.py "$repeats" "$scenes"
"$work/venv/bin/python" bench/mitsuba/race_summary.py
