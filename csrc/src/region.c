/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Stability verdicts, paper eqs (10), (14)-(18), each guarded by an error bound.
 *
 * Exact region in division-free forms (x = beta + delta > 0, sigma a power of two):
 *   hyperbola  (alpha/sigma) g + (alpha/sigma) / x  <  hs - beta/sigma
 *              (alpha < f(beta) multiplied by (g + 1/x)/sigma > 0; g = c1/s, hs = 2/(c2 sigma);
 *               beta >= 2/c2 makes the right side <= 0, so the right end is included)
 *   line       d12 (alpha/2) + d12 beta  <  2 (1 + e)
 *              (p(-1) < 0; at delta = 0, d12 = 0 and it always holds, as it must)
 * Using c1 beta + 2 = c1 x + s avoids the cancellation of the paper's form near the corner
 * beta -> -delta, and sigma keeps every term finite up to delta ~ max/2.
 *
 * Each side carries a bound on its absolute error, written out operation by operation
 * (the running error analysis, unrolled in internal.h's zw_*_constraint because this is
 * the hot path of a drive and must stay small in flash and stack; batch.c shares them).
 */
#include "zwidth/region.h"

#include <stddef.h>

#include "internal.h"

/* Collects the outcome of each constraint, then decides. */
typedef struct verdict_builder {
    uint_least16_t surely;  /* constraints certainly violated */
    uint_least16_t unsure;  /* constraints within the rounding band */
} verdict_builder;

/* Record the outcome of "lhs < rhs must hold" (err bounds both sides' errors). */
static void require_less(verdict_builder *vb, zw_bound bit, zw_real lhs, zw_real rhs, zw_real err)
{
    const zw_cmp cmp = zw_compare(lhs, rhs, err);
    if (cmp == ZW_CMP_GE) {
        vb->surely = (uint_least16_t)(vb->surely | (uint_least16_t)bit);
    } else if (cmp == ZW_CMP_UNSURE) {
        vb->unsure = (uint_least16_t)(vb->unsure | (uint_least16_t)bit);
    } else {
        /* surely holds: nothing to record */
    }
}

static void finish(const verdict_builder *vb, zw_verdict *out)
{
    const uint_least16_t decisive = (vb->surely != 0u) ? vb->surely : vb->unsure;
    /* lowest set bit: the first violated constraint in the order of zw_bound */
    const uint_least16_t lowest = (uint_least16_t)(decisive & (uint_least16_t)(~decisive + 1u));
    zw_verdict v;
    v.violated = (uint_least16_t)(vb->surely | vb->unsure);
    v.stable = (v.violated == 0u);
    v.marginal = (vb->surely == 0u) && (vb->unsure != 0u);
    v.deciding = (zw_bound)lowest;
    *out = v;
}

/* 0 < alpha and alpha / 2 + sign * beta < delta, for the linear regions (14)-(18);
 * sign_abs: use |beta| (passivity). */
static void linear_region(verdict_builder *vb, zw_bound bit, const zw_coeffs *c,
                          const zw_gains *g, zw_real sign, bool sign_abs)
{
    zw_real beta_term = sign * (sign_abs ? ZW_FABS(g->beta.v) : g->beta.v);
    zw_real lhs = ZW_R(0.5) * g->alpha.v + beta_term;
    require_less(vb, ZW_BOUND_STIFFNESS, ZW_R(0.0), g->alpha.v, g->alpha.e);
    require_less(vb, bit, lhs, c->delta,
                 ZW_R(0.5) * g->alpha.e + g->beta.e + c->delta * c->delta_relerr +
                     ZW_U * ZW_FABS(lhs) + ZW_ETA);
}

/* The constraints of eq (10) (internal.h); with_line false gives the legacy region. */
static void exact_region(verdict_builder *vb, const zw_coeffs *c, const zw_gains *g,
                         bool with_line)
{
    const zw_real coef_err = zw_coef_relerr(c);
    const zw_eb x = zw_exact_x(c, g);

    require_less(vb, ZW_BOUND_DAMPING, ZW_R(0.0), x.v, x.e);
    require_less(vb, ZW_BOUND_STIFFNESS, ZW_R(0.0), g->alpha.v, g->alpha.e);

    if (((uint_least16_t)(vb->surely | vb->unsure) & (uint_least16_t)ZW_BOUND_DAMPING) != 0u) {
        /* the hyperbola form divides by x: meaningless unless x is surely positive */
        vb->unsure = (uint_least16_t)(vb->unsure | (uint_least16_t)ZW_BOUND_HYPERBOLA);
    } else {
        zw_constraint k = zw_hyperbola_constraint(c, coef_err, g, x);
        require_less(vb, ZW_BOUND_HYPERBOLA, k.lhs, k.rhs, k.err);
    }
    if (with_line) {
        zw_constraint k = zw_line_constraint(c, coef_err, g);
        require_less(vb, ZW_BOUND_LINE, k.lhs, k.rhs, k.err);
    }
}

/* The delta = 0 coefficients, for the region of eq (17) (c1 = c2 = 1, e = 1, d12 = 0). */
static const zw_coeffs k_delta_zero = {
    .delta = ZW_R(0.0), .e = ZW_R(1.0), .c1 = ZW_R(1.0), .c2 = ZW_R(1.0), .d12 = ZW_R(0.0),
    .s = ZW_R(2.0), .g = ZW_R(0.5), .sigma = ZW_R(1.0), .hs = ZW_R(2.0), .delta_relerr = ZW_R(0.0)};

static zw_status check_bounded(zw_region region, const zw_coeffs *c, const zw_gains *g,
                               zw_verdict *out)
{
    verdict_builder vb = {0, 0};
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    /* only the exact and legacy regions use hs */
    st = zw_require_coeffs(c, (region == ZW_REGION_EXACT) || (region == ZW_REGION_LEGACY));
    if (st == ZW_OK) {
        st = zw_require_finite(g->alpha.v);
    }
    if (st == ZW_OK) {
        st = zw_require_finite(g->beta.v);
    }
    if (st != ZW_OK) {
        return st;
    }

    switch (region) {
    case ZW_REGION_EXACT: exact_region(&vb, c, g, true); break;
    case ZW_REGION_LEGACY: exact_region(&vb, c, g, false); break;
    case ZW_REGION_DELTA0: exact_region(&vb, &k_delta_zero, g, false); break;
    case ZW_REGION_PASSIVITY: /* alpha/2 + |beta| < delta */
        linear_region(&vb, ZW_BOUND_PASSIVITY, c, g, ZW_R(1.0), true);
        break;
    case ZW_REGION_DELTA_INF: /* beta > -delta, alpha/2 + beta < delta */
        require_less(&vb, ZW_BOUND_DAMPING, -g->beta.v, c->delta,
                     g->beta.e + c->delta * c->delta_relerr);
        linear_region(&vb, ZW_BOUND_LINE, c, g, ZW_R(1.0), false);
        break;
    case ZW_REGION_SMALL: /* alpha/2 - beta < delta */
        linear_region(&vb, ZW_BOUND_HYPERBOLA, c, g, ZW_R(-1.0), false);
        break;
    default: st = ZW_ERR_ARG; break;
    }
    if (st == ZW_OK) {
        finish(&vb, out);
    }
    return st;
}

/* Every public check ends here: the one place the fail-safe verdict is written. */
zw_status zw_check_bounded(zw_region region, const zw_coeffs *c, const zw_gains *g,
                           zw_verdict *out)
{
    zw_status st = check_bounded(region, c, g, out);
    if (st != ZW_OK) {
        zw_fail_verdict(out);
    }
    return st;
}

zw_status zw_check_region(zw_region region, const zw_coeffs *c, zw_real alpha, zw_real beta,
                          zw_verdict *out)
{
    zw_gains g = zw_gains_exact(alpha, beta);
    return zw_check_bounded(region, c, &g, out);
}

zw_status zw_check(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_verdict *out)
{
    zw_gains g = zw_gains_exact(alpha, beta);
    return zw_check_bounded(ZW_REGION_EXACT, c, &g, out);
}

zw_status zw_check_proportional(const zw_coeffs *c, zw_real alpha, zw_verdict *out)
{
    zw_gains g = zw_gains_exact(alpha, ZW_R(0.0));
    return zw_check_bounded(ZW_REGION_EXACT, c, &g, out);
}
