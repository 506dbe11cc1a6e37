/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* The per-plant sweep (csrc/src/sweep.c) compiled a second time for AVX2, for the Python
 * bindings only: the fields point by point (ZW_SWEEP_GATHER 0: AVX2 has no packed
 * double-to-int64 conversion, so the branch-free field loops' table index does not
 * vectorize and they cost more than they save), the constraints four points at once.
 * Same source, same operations in the same order, no contraction (-ffp-contract=off): the
 * results are bit for bit those of the portable build.  zwidth_core.cpp calls it when the
 * CPU has AVX2. */
#define ZW_SWEEP_GATHER 0
#define zw_sweep_check_many zw_sweep_check_many_avx2
#define zw_sweep_fields_init zw_sweep_fields_init_avx2
#include "../csrc/src/sweep.c"
