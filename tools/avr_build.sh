#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# The firmware part on a 16-bit-int target: every module of ZW_CORE_SOURCES (CMakeLists.txt)
# compiled with avr-gcc for the ATmega2560 (16-bit int, 16-bit size_t, 32-bit double, as
# on TI C28x under COFF), float build, with ZW_PORTABLE_MATH (avr-libc has no expm1f,
# nextafterf nor HUGE_VAL: docs/fp-environment.md section 5), and warnings as errors,
# conversions included.  A module that does not compile fails the run.
# Usage: tools/avr_build.sh   (needs gcc-avr and avr-libc)
set -euo pipefail
cd "$(dirname "$0")/.."
AVR_CC=${AVR_CC:-avr-gcc}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# the core's source list, as CMake builds it (one place decides what the firmware part is)
mapfile -t sources < <(tools/core_modules.sh | tr ' ' '\n' | sed 's|.*|csrc/src/&.c|')
[ "${#sources[@]}" -gt 0 ] || { echo "FAIL: no ZW_CORE_SOURCES in CMakeLists.txt"; exit 1; }
failed=0
for src in "${sources[@]}"; do
    name=$(basename "$src" .c)
    if ! "$AVR_CC" -mmcu=atmega2560 -std=c99 -Wall -Wextra -Wpedantic -Werror -Wconversion \
            -Wsign-conversion -ffp-contract=off -Os -DZW_REAL_FLOAT -DZW_PORTABLE_MATH \
            -Icsrc/include -Icsrc/src -c "$src" -o "$out/$name.o"; then
        echo "FAIL: $src does not build for the ATmega2560"
        failed=$((failed + 1))
    fi
done
[ "$failed" = 0 ] || exit 1
echo "avr-gcc $("$AVR_CC" -dumpversion), ATmega2560 (int 16 bits, double 32 bits): ${#sources[@]} modules build, float + ZW_PORTABLE_MATH, -Werror -Wconversion -Wsign-conversion"
