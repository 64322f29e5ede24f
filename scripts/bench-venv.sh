# Sourced by the benchmark scripts: a venv with Mitsuba 3.9.1 and numpy in
# bench-work/venv (Mitsuba also reads and writes EXR for them), and LLVM 19
# for Mitsuba's LLVM back end. Sets $work and DRJIT_LIBLLVM_PATH.
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
