#!/usr/bin/env bash

# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# zw_selftest on a Cortex-M4F under QEMU (mps2-an386): the float core's start-up check run
# on the target's own FPU and newlib libm, for the build modes an integrator may use.
#   c99       the project's flags (footprint.sh): expect ZW_OK; FZ and RZ refused
#   gnu99     GCC's GNU mode, no -ffp-contract (an IDE default): expect the contraction bit
#   portable  the project's flags + -DZW_PORTABLE_MATH (the fallbacks on newlib): as c99
# Round toward zero fails rounding (0x01) and, as IEEE directed rounding does, keeps
# FLT_MAX * 2 finite, so overflow (0x08), NaN from inf - inf (0x04) and newlib's expf /
# expm1f at the known points (0x40) fail too: 0x4d.
# Needs arm-none-eabi-gcc with newlib and qemu-system-arm; prints what it ran.
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
CROSS=arm-none-eabi-gcc
MCU=bench/report/mcu
T="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -DZW_REAL_FLOAT"
WARN="-Wall -Wextra -Wpedantic -Werror"
B=$(mktemp -d)
trap 'rm -rf "$B"' EXIT

run() { # name, flags, expected output lines
    local name=$1 flags=$2 expect=$3 out
    $CROSS $flags $WARN $T -Os -Icsrc/include -I$MCU -nostartfiles -specs=nano.specs \
        -specs=nosys.specs -Wl,--gc-sections -T $MCU/mps2_an386.ld $MCU/startup.c \
        tests/mcu/fpenv_main.c csrc/src/selftest.c csrc/src/status.c csrc/src/portable_math.c \
        -lm -o "$B/$name.elf"
    out=$(timeout 60 qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
        -semihosting-config enable=on,target=native -kernel "$B/$name.elf" 2>&1)
    printf '%-9s %s\n' "$name" "$flags"
    out=$(printf '%s\n' "$out" | tr -d '\r')
    printf '%s\n' "$out" | sed 's/^/    /'
    if [ "$out" != "$expect" ]; then
        printf 'fpenv_m4f: %s: expected\n%s\n' "$name" "$expect" >&2
        exit 1
    fi
}

OK="default (FLT_MIN/2 kept) ZW_OK 0x0000
flush-to-zero (FLT_MIN/2 -> 0) ZW_ERR_FPENV 0x0010
round-to-zero (FLT_MIN/2 kept) ZW_ERR_FPENV 0x004d
fpenv done"
run c99 "-std=c99 -ffp-contract=off" "$OK"
run portable "-std=c99 -ffp-contract=off -DZW_PORTABLE_MATH" "$OK"
run gnu99 "-std=gnu99" "default (FLT_MIN/2 kept) ZW_ERR_FPENV 0x0020
flush-to-zero (FLT_MIN/2 -> 0) ZW_ERR_FPENV 0x0030
round-to-zero (FLT_MIN/2 kept) ZW_ERR_FPENV 0x006d
fpenv done"
echo "fpenv_m4f: zw_selftest behaves as documented on the Cortex-M4F"
