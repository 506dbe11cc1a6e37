/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Included before every file of eva_sweep.c's analysis (its "eva-defines:" line): the
 * sweep's ZW_SWEEP_GATHER, 0 in the default build and 1 in the AVX-512 bindings'
 * (bindings/sweep_avx*.c), becomes a volatile read, so one analysis takes both the
 * point-by-point field loop and the branch-free vector ones (docs/eva.md). */
#ifndef ZW_EVA_SWEEP_GATHER_H
#define ZW_EVA_SWEEP_GATHER_H

extern volatile int zw_eva_sweep_gather;
#define ZW_SWEEP_GATHER (zw_eva_sweep_gather != 0)

#endif
