/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/region.h - stability verdicts in the normalized space (delta, alpha, beta).
 *
 * alpha = K T^2 / m (NVS), beta = B T / m (NVD).  The exact region, paper eq (10):
 *     beta > -delta,   0 < alpha < f(beta),   alpha < L(beta) = 4 (1 + e) / d12 - 2 beta
 * evaluated in the division-free forms
 *     hyperbola:  alpha g + alpha / (beta + delta) < 2 / c2 - beta
 *     line:       d12 alpha / 2 + d12 beta < 2 (1 + e)
 * with a running error bound (Wilkinson) carried through every operation.
 *
 * Safety: a verdict says stable only if the point is stable for every value within the
 * rounding error bound, so an unstable point is never called stable.  A stable point is
 * called unstable only inside that bound (a few ulps of the inputs); such verdicts carry
 * marginal = true.
 */
#ifndef ZWIDTH_REGION_H
#define ZWIDTH_REGION_H

#include <stdbool.h>
#include <stdint.h>

#include "zwidth/coeffs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The constraints a point can violate; bits of zw_verdict.violated. */
typedef enum zw_bound {
    ZW_BOUND_NONE = 0,
    ZW_BOUND_DAMPING = 1,    /* beta <= -delta (B <= -b): add damping */
    ZW_BOUND_STIFFNESS = 2,  /* alpha <= 0 (K <= 0) */
    ZW_BOUND_HYPERBOLA = 4,  /* alpha >= f(beta), including beta >= 2/c2 */
    ZW_BOUND_LINE = 8,       /* alpha >= L(beta), the bound the legacy region lacks */
    ZW_BOUND_PASSIVITY = 16, /* K T / 2 >= b - |B| (passivity region only) */
    ZW_BOUND_INVALID = 32    /* no verdict: the call failed (never set with ZW_OK) */
} zw_bound;

typedef struct zw_verdict {
    bool stable;
    bool marginal;            /* within the rounding band of a boundary: could not prove stable */
    zw_bound deciding;        /* first violated constraint in the order of the enum; NONE if stable */
    uint_least16_t violated;  /* every violated (or unprovable) constraint, as zw_bound bits */
} zw_verdict;

/* Fail-safe verdict (status.h): on every error, *out (when not NULL, whichever other
 * argument is NULL) is written as stable = false, marginal = false, deciding = violated =
 * ZW_BOUND_INVALID, so that neither "stable" nor "violated == 0" reads as stable and no
 * real constraint is blamed. */

/* The regions zw_check_region can evaluate. */
typedef enum zw_region {
    ZW_REGION_EXACT = 0,      /* eq (10), all delta >= 0 */
    ZW_REGION_LEGACY = 1,     /* Gil et al.: (10) without the line; wrong for delta > delta0 */
    ZW_REGION_PASSIVITY = 2,  /* eq (16): 0 < alpha / 2 < delta - |beta| */
    ZW_REGION_DELTA0 = 3,     /* eq (17): the delta = 0 region, ignoring delta */
    ZW_REGION_DELTA_INF = 4,  /* eqs (14), (15): beta > -delta, 0 < alpha / 2 < delta - beta */
    ZW_REGION_SMALL = 5       /* eq (18): small delta and beta: 0 < alpha / 2 < delta + beta */
} zw_region;

/* Exact verdict, eq (10).  Errors: ZW_ERR_NULL (c or out), ZW_ERR_NAN (alpha, beta or
 * c->delta, e.g. coefficients of a failed zw_coeffs_init), ZW_ERR_INF (alpha, beta or
 * c->delta infinite), ZW_ERR_ARG (c->delta_relerr negative or not finite), ZW_ERR_RANGE
 * (delta so large that hs = +inf, above ~max/2); on each, the fail-safe verdict above. */
zw_status zw_check(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_verdict *out);

/* Verdict of one of the regions above (each guarded against its own boundary; errors as
 * zw_check, and ZW_ERR_ARG for an unknown region; fail-safe verdict on each).  For every
 * region but EXACT, "stable" means "inside that region": the legacy, delta = 0, delta ->
 * inf and small-delta regions are the paper's comparisons and approximations, and the
 * legacy one contains unstable points for delta > delta0.  Only EXACT (and PASSIVITY,
 * which lies inside it) certify. */
zw_status zw_check_region(zw_region region, const zw_coeffs *c, zw_real alpha, zw_real beta,
                          zw_verdict *out);

/* Proportional (stiffness-only) control, beta = 0, eqs (27), (29) (errors as zw_check). */
zw_status zw_check_proportional(const zw_coeffs *c, zw_real alpha, zw_verdict *out);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REGION_H */
