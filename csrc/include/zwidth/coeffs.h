/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/coeffs.h - the coefficient functions of the sampled plant, paper eqs (3), (4).
 *
 * This is the only place the coefficient series live.  Computed once per plant (a drive
 * checks many gain pairs against one plant) and passed by pointer to every check.
 *
 *   e   = exp(-delta)
 *   c1  = 2 (delta - 1 + e) / delta^2
 *   c2  = 2 (1 - e - delta e) / delta^2
 *   d12 = c1 - c2
 *
 * The literal formulas cancel catastrophically for small delta and overflow delta^2 for
 * large delta.  Below delta = 2 zwidth evaluates c1 = e P1(delta), c2 = e P2(delta),
 * d12 = e delta P12(delta), where P1, P2, P12 are power series with positive coefficients
 * (2(k+1)/(k+2)!, 2/(k+2)!, 2(k+1)/(k+3)!: no cancellation at all); above it the literal
 * numerators, divided by delta twice instead of by delta^2.
 * Accuracy against a 50-digit reference is stated by ZW_COEF_ULPS and tested.
 */
#ifndef ZWIDTH_COEFFS_H
#define ZWIDTH_COEFFS_H

#include "zwidth/real.h"
#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Worst error of every coefficient field below against the exact value of the
 * function at the given delta, in units of the field's own ulp (measured over a
 * dense log grid and every hard case, both precisions; see tests/py/test_coeffs.py).
 * The stability checks budget for this error, so it is part of the safety argument. */
#define ZW_COEF_ULPS 4

typedef struct zw_coeffs {
    zw_real delta;        /* NPD: b T / m, in [0, +inf] */
    zw_real e;            /* exp(-delta) */
    zw_real c1;           /* in (0, 1], ~2/delta for large delta */
    zw_real c2;           /* in (0, 1], ~2/delta^2 for large delta (may underflow) */
    zw_real d12;          /* c1 - c2, 0 at delta = 0 */
    zw_real s;            /* c1 + c2 = 2 (1 - e) / delta, 2 at delta = 0 */
    zw_real g;            /* c1 / s: 1/2 at delta = 0, -> 1 as delta -> inf */
    zw_real sigma;        /* power-of-two scale: 1 for delta <= 1, else the least 2^k >= delta
                             (capped at the largest finite power of two) */
    zw_real hs;           /* (2 / c2) / sigma, ~delta for large delta: finite up to delta ~ max/2
                             (beyond, +inf, and the checks answer ZW_ERR_RANGE) */
    /* Relative uncertainty of delta itself: 0 when delta was given exactly, a few unit
     * roundoffs when it was computed from (m, b, T).  Checks widen their guard by it. */
    zw_real delta_relerr;
} zw_coeffs;

/* Fill *out for delta in [0, +inf].  delta = +inf gives the limits (e = c1 = c2 = d12 =
 * s = 0, g = 1, sigma = hs = +inf); the checks reject it with ZW_ERR_INF.
 * Errors: ZW_ERR_NULL (out), ZW_ERR_NAN, ZW_ERR_DELTA (delta < 0).  Fail-safe: on
 * ZW_ERR_NAN / ZW_ERR_DELTA every field of *out is NaN, so a check on it (status
 * ignored) answers ZW_ERR_NAN and a not-stable verdict instead of using an older plant. */
zw_status zw_coeffs_init(zw_coeffs *out, zw_real delta);

/* The literal (cancelling) formulas of eqs (3), (4), kept only so that tests and
 * benchmarks can show what the careful ones buy.  Never used by the checks.
 * Errors: ZW_ERR_NULL (any output; the others are still written), ZW_ERR_NAN,
 * ZW_ERR_DELTA; on each, every non-NULL output is NaN. */
zw_status zw_coeffs_literal(zw_real delta, zw_real *c1, zw_real *c2, zw_real *d12);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_COEFFS_H */
