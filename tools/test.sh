#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Every test: C unit tests (double and float) plain and under ASan/UBSan, the MCU
# footprint targets, the Python package (pip install ., mypy and stubtest, pytest: the
# bindings bit for bit against the C core, hypothesis properties, the CLI and the plots),
# the high-precision reference tests against mpmath, the Modbus drive
# over real sockets and a pseudo-terminal (zwidth-tune, the Python client, mbpoll), a
# bounded libFuzzer run on the request handler (ZW_FUZZ_SECONDS, default 30), and the
# release checks (reuse lint, the firmware tarball on the Cortex-M4F, sdist and wheel), the
# file lists of docs/firmware.md built from the doc's text (tools/firmware_files.sh), the
# firmware part built for a 16-bit-int AVR (tools/avr_build.sh), its MISRA C:2012 check (tools/misra.sh) and Eva analysis (tools/eva.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/bootstrap.sh

# Each step says how long the one before it took (wall seconds), and the run ends with a
# summary, so a slow step shows in the CI log.
timings=()
step_name="" step_start=$SECONDS
end_step() {
    if [ -n "$step_name" ]; then
        timings+=("$(printf '%5d s  %s' $((SECONDS - step_start)) "$step_name")")
        printf '(%d s)\n' $((SECONDS - step_start))
    fi
}
step() {
    end_step
    step_name=$*
    step_start=$SECONDS
    printf '\n==== %s\n' "$*"
}

step "build (Release, double + float, shared libraries for the reference tests)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build

step "build with -fsanitize=address,undefined"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DZW_SANITIZE=ON -DZW_BUILD_SHARED=OFF >/dev/null
cmake --build build-asan

step "C unit tests (ctest)"
ctest --test-dir build --output-on-failure -LE tsan

step "register map across threads under ThreadSanitizer (regmap.c as C11 atomics; ctest -L tsan)"
ctest --test-dir build --output-on-failure -L tsan

step "use from another project: cmake --install, find_package and pkg-config, C and C++, precision mismatch"
tools/consumer_test.sh build

step "C unit tests under ASan/UBSan (ctest)"
ctest --test-dir build-asan --output-on-failure

step "portable-math build (-DZW_PORTABLE_MATH): C tests and the coefficient ulp test on the fallbacks"
cmake -S . -B build-portable -G Ninja -DCMAKE_BUILD_TYPE=Release -DZW_PORTABLE_MATH=ON -DZW_BUILD_HOST=OFF >/dev/null
cmake --build build-portable
ctest --test-dir build-portable --output-on-failure
ZW_LIB_DIR="$PWD/build-portable" .venv/bin/python -m pytest tests/py/test_coeffs.py -q

step "MISRA C:2012 on the firmware part (cppcheck addon, double + float; deviations: docs/misra.md)"
tools/misra.sh

step "run-time errors of the gated core modules, every input unconstrained (Frama-C Eva; docs/eva.md)"
tools/eva.sh

step "MCU footprint (Cortex-M4F, Cortex-M0): targets, and docs/footprint.md + README table current"
tools/footprint.sh --check >/dev/null
echo "footprint within targets; docs/footprint.md and the README table match the source"

step "firmware uses of docs/firmware.md link for the Cortex-M4F (tools/firmware_uses.sh)"
tools/firmware_uses.sh >/dev/null
echo "every firmware use links (check, extremes, units, loop, regmap)"

step "file lists of docs/firmware.md and README.md's C example build from the docs' text (tools/firmware_files.sh)"
tools/firmware_files.sh >/dev/null
echo "every use's files build alone (M4F, host float + double); the README C example is warning-free; the checker fails on broken copies"

step "the firmware part on a 16-bit-int target: every module builds with avr-gcc (tools/avr_build.sh)"
tools/avr_build.sh

step "zw_selftest on the Cortex-M4F (QEMU): c99 passes, GNU-mode contraction and round-to-zero refused"
tools/fpenv_m4f.sh

step "box certificates on the Cortex-M4F (QEMU): verification and the register map within their targets (tools/m4f_box_cert.sh)"
tools/m4f_box_cert.sh | tail -n 3

step "fuzzing the request handler (libFuzzer, ASan/UBSan, ${ZW_FUZZ_SECONDS:-30} s)"
tools/fuzz.sh "${ZW_FUZZ_SECONDS:-30}" 2>&1 | tail -n 4

step "Python package: pip install . (scikit-build-core, pybind11), then mypy --strict and stubtest"
.venv/bin/python -m pip install -q --disable-pip-version-check .
.venv/bin/zwidth limits --m 0.1 --b 30 --T 0.01 --delay 0 >/dev/null
.venv/bin/python -m mypy
.venv/bin/python -m mypy.stubtest zwidth._core

step "Python tests and high-precision reference tests (pytest: bindings, CLI, plots, mpmath)"
# two workers (pytest-xdist): the longest step, and the tests share nothing but read-only files
MPLBACKEND=Agg ZW_LIB_DIR="$PWD/build" .venv/bin/python -m pytest tests/py -q -n 2

step "benchmark smoke run (bench/python/bench_check.py --quick)"
.venv/bin/python bench/python/bench_check.py --quick >/dev/null
echo "benchmark runs (full table: .venv/bin/python bench/python/bench_check.py)"

step "simulation benchmark smoke run (bench/sim/bench_sim.py --quick)"
.venv/bin/python bench/sim/bench_sim.py --quick >/dev/null
echo "simulation benchmark runs (full table: .venv/bin/python bench/sim/bench_sim.py --markdown)"

step "benchmark report, reduced size: fails if a method's error exceeds the report's claims"
.venv/bin/python bench/report/generate.py --quick | tail -n 3

step "Modbus drive: zwidth-tune, mbpoll, RTU over socat, robustness (pytest)"
ZW_BUILD_DIR="$PWD/build" .venv/bin/python -m pytest tests/integration -q

step "Modbus drive under ASan/UBSan (same tests)"
ZW_BUILD_DIR="$PWD/build-asan" .venv/bin/python -m pytest tests/integration -q

step "Python client zwidth.modbus against the drive, and pymodbus interop (pytest)"
ZW_BUILD_DIR="$PWD/build" .venv/bin/python -m pytest tests/modbus_py -q

step "release: every file tagged (reuse lint), the firmware source tarball built alone for the Cortex-M4F, sdist and wheel"
tools/spdx.sh --check | tail -n 1
tools/firmware_release.sh --check build/release
tools/dist_check.sh build/dist
end_step
printf '\n==== every test passed; wall time per step:\n'
printf '%s\n' "${timings[@]}"
printf '%5d s  in all\n' "$SECONDS"
