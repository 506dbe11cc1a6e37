/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* The per-plant sweep (csrc/src/sweep.c) compiled again for AVX-512 (F, DQ, VL), for the
 * Python bindings only: every loop runs on eight points at once, the fields' too
 * (ZW_SWEEP_GATHER 1: masked selects of the piece coefficients, the exponential's table
 * index by a packed conversion to int64, AVX-512DQ), in blocks of 32 points; about 3x
 * faster than AVX2 on a mixed sweep.  Same source, with fma contraction (-mfma
 * -ffp-contract=fast, 9.3 against 10.6 ns a mixed point): an fma rounds once where the
 * proofs (docs/numerics.md section 7, internal.h) count a rounding of the product and one
 * of the sum, so every bound holds as proved (the product's rounding error is then 0,
 * within its bound u); verdicts equal the portable build's except possibly inside the
 * rounding band, where both are guarded.  zwidth_core.cpp calls it when the CPU has these
 * extensions (and FMA, which every AVX-512 CPU has). */
#define ZW_SWEEP_GATHER 1
#define ZW_SWEEP_BLOCK 32u /* four vectors a loop: 10.6 ns a mixed point against 12.4 with 16 */
#define zw_sweep_check_many zw_sweep_check_many_avx512
#define zw_sweep_fields_init zw_sweep_fields_init_avx512
#include "../csrc/src/sweep.c"
