/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* zwidth/sweep.h - the exact-region check when every point is its own plant.
 *
 * A design sweep varies m, b or T along the array, so delta changes at every point and
 * zw_coeffs_init (two exponentials, three 24-term series) dominates.  This module
 * evaluates only the coefficient fields the exact-region check reads (e, g, hs, d12,
 * sigma), each with a proved relative error bound inside the checks' budget, and loads
 * one table value a point:
 *   e on [0, 64): exp(-(k + 1/2)/16) from a 1024-entry table times a fixed 8-term
 *     polynomial (within 2.1 u);
 *   g, hs, d12 on [0, 2): fixed 12-term polynomials on [0, 1) and [1, 2) (within 2.4 u,
 *     4.8 u, 5.3 u);
 *   g, hs, d12 on [2, 64): closed forms without cancellation (within 5.4 u, 6.5 u, 7.2 u);
 *   delta >= 64: zw_coeffs_init itself.
 * (Tables generated and every bound proved by tools/gen_sweep_tables.py; docs/numerics.md
 * section 7.)
 * The checks budget 2 ZW_COEF_ULPS u = 8 u for each field, so a verdict here is as safe
 * as zw_check's: never stable for an unstable point, and stable ones called unstable only
 * within the rounding band (marginal points may come out differently, never "stable"
 * for an unstable one).  Host code; no heap, no I/O, reentrant.
 */
#ifndef ZWIDTH_SWEEP_H
#define ZWIDTH_SWEEP_H

#include <stdbool.h>
#include <stddef.h>

#include "zwidth/real.h"
#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The coefficient fields the exact-region check reads, at one delta (coeffs.h). */
typedef struct zw_sweep_fields {
    zw_real e;      /* exp(-delta) */
    zw_real g;      /* c1 / (c1 + c2) */
    zw_real hs;     /* (2 / c2) / sigma */
    zw_real d12;    /* c1 - c2 */
    zw_real sigma;  /* power of two scale, as in zw_coeffs */
} zw_sweep_fields;

/* The fields at delta, by the sweep's evaluation (for tests and for callers that keep
 * them).  Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_DELTA (delta < 0), ZW_ERR_INF, and
 * ZW_ERR_RANGE where hs overflows (delta ~ 1e308), as zw_check; fail-safe: on every error
 * each field of *out is NaN. */
zw_status zw_sweep_fields_init(zw_sweep_fields *out, zw_real delta);

/* stable[i] = the guarded exact-region verdict of (delta[i], alpha[i], beta[i]) (element
 * i at index i * stride of each input; stride 0 repeats one value).  Errors as
 * zw_check_many (batch.h), with *first_invalid the first refused point; fail-safe: on any
 * error stable[0 .. n-1] are all false.  n = 0 reads and writes nothing. */
zw_status zw_sweep_check_many(size_t n, const zw_real *delta, ptrdiff_t delta_stride,
                              const zw_real *alpha, ptrdiff_t alpha_stride, const zw_real *beta,
                              ptrdiff_t beta_stride, bool *stable, size_t *first_invalid);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_SWEEP_H */
