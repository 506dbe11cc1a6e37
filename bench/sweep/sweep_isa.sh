#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
#
# bench/sweep/sweep_isa.sh [BASE_REV] - where the per-plant sweep's time goes by build:
# csrc/src/sweep.c of BASE_REV (default 4b4ab1b, before the vector work), and of the
# checkout built portable (-O3), for AVX2 and for AVX-512 (as bindings/sweep_avx*.c), all
# linked into one program and timed interleaved on three delta ranges (mixed, tables only,
# closed forms only).  Needs the core library built in build/ (cmake --build build).
# x86-64 with AVX-512 only; about 30 s.
set -euo pipefail
cd "$(dirname "$0")/../.."
base=${1:-4b4ab1b}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git show "$base:csrc/src/sweep.c" > "$tmp/sweep_base.c"
git show "$base:csrc/src/internal.h" > "$tmp/internal.h"
flags=(-std=c99 -O3 -DNDEBUG -ffp-contract=off -Icsrc/include -Icsrc/src)
rename() { echo "-Dzw_sweep_check_many=$1 -Dzw_sweep_fields_init=$1_fields"; }
cc "${flags[@]}" $(rename v_base) -c "$tmp/sweep_base.c" -o "$tmp/base.o"
cc "${flags[@]}" $(rename v_portable) -c csrc/src/sweep.c -o "$tmp/portable.o"
cc "${flags[@]}" -mavx2 $(rename v_avx2) -c csrc/src/sweep.c -o "$tmp/avx2.o"
cc "${flags[@]}" -DZW_SWEEP_GATHER=1 -DZW_SWEEP_BLOCK=32u -mavx512f -mavx512dq -mavx512vl -mfma -ffp-contract=fast $(rename v_avx512) \
    -c csrc/src/sweep.c -o "$tmp/avx512.o"
cc -O2 bench/sweep/sweep_isa.c "$tmp"/*.o build/libzwidth_d.a -lm -o "$tmp/sweep_isa"
for range in "1e-3 20" "1e-3 1.999" "2 20"; do
    "$tmp/sweep_isa" $range
done
