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
sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
llvm=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
if [ ! -e "$llvm" ]; then
    sudo_if_needed apt-get update -qq
    DEBIAN_FRONTEND=noninteractive sudo_if_needed apt-get install -y -qq libllvm19 python3-venv < /dev/null
fi
work=$PWD/bench-work
if [ ! -x "$work/venv/bin/python" ]; then
    python3 -m venv "$work/venv"
    "$work/venv/bin/pip" install -q mitsuba==3.9.1 numpy
fi
# Without it drjit picks an older LLVM and aborts.
export DRJIT_LIBLLVM_PATH=$llvm
# A copy of the binary, so a rebuild during the run cannot change it.
cp build/jaderender "$work/jaderender"
export JADERENDER=$work/jaderender PERF_WORK=$work
"$work/venv/bin/python" bench/mitsuba/race.py "$repeats" "$scenes"
"$work/venv/bin/python" bench/mitsuba/race_summary.py
