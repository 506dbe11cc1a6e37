#!/usr/bin/env bash
# Install what zwidth needs on a Debian machine (idempotent; quiet when all is there).
#   system: C toolchain, CMake, Ninja, cmocka (C unit tests), the arm-none-eabi
#           cross-compiler (MCU footprint), libmodbus (drive and tuning tool), socat
#           (RTU over a pseudo-terminal pair), mbpoll (a Modbus client nobody here wrote),
#           clang (libFuzzer), python3 with venv and headers, g++ (the Python extension)
#   python: a virtualenv in .venv with the test requirements (tools/requirements-test.txt);
#           the zwidth package itself is installed by tools/test.sh (pip install .)
set -euo pipefail
cd "$(dirname "$0")/.."

need_apt=()
have() { command -v "$1" >/dev/null 2>&1; }
have cc || need_apt+=(gcc)
have g++ || need_apt+=(g++)
have cmake || need_apt+=(cmake)
have ninja || need_apt+=(ninja-build)
have pkg-config || need_apt+=(pkg-config)
have arm-none-eabi-gcc || need_apt+=(gcc-arm-none-eabi libnewlib-arm-none-eabi)
[ -f /usr/include/cmocka.h ] || need_apt+=(libcmocka-dev)
[ -f /usr/include/modbus/modbus.h ] || need_apt+=(libmodbus-dev)
have socat || need_apt+=(socat)
have mbpoll || need_apt+=(mbpoll)
have clang || need_apt+=(clang)
# bench/report: instruction counts (callgrind) and the emulated Cortex-M4 (qemu)
have valgrind || need_apt+=(valgrind)
have qemu-system-arm || need_apt+=(qemu-system-arm)
have python3 || need_apt+=(python3)
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || need_apt+=(python3-venv)
# Python.h, for building zwidth._core against the interpreter the venv is made from
python3 -c 'import os, sysconfig; assert os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h"))' \
    >/dev/null 2>&1 || need_apt+=(python3-dev)

if [ ${#need_apt[@]} -gt 0 ]; then
    echo "bootstrap: installing ${need_apt[*]}" >&2
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need_apt[@]}" >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
    echo "bootstrap: creating .venv" >&2
    python3 -m venv .venv
fi
if ! .venv/bin/python -c 'import mpmath, numpy, pytest, pymodbus, hypothesis, mypy, matplotlib, scipy, control, pybind11, scikit_build_core' >/dev/null 2>&1; then
    echo "bootstrap: installing Python test requirements into .venv" >&2
    .venv/bin/python -m pip install -q --disable-pip-version-check -r tools/requirements-test.txt
fi
