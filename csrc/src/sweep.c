/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* The exact-region check with a plant per point (zwidth/sweep.h).
 *
 * Only the fields the check reads are evaluated, each within a proved relative bound
 * below the checks' budget of 2 ZW_COEF_ULPS u = 8 u per field (docs/numerics.md,
 * "Per-plant sweeps"):
 *   [0, 2):   sigma = 1; E = e, G = g, W = 2/c2 = hs and Q = d12/delta from Taylor polynomials around the
 *             centre of delta's interval of width 1/32 (sweep_tables.h); h = delta - centre
 *             is exact (Sterbenz) except in the first interval, where the bound counts its
 *             rounding.  Every field within 3.1 u.
 *   [2, 64):  e = exp(-delta) (one ulp), then sums of non-negative terms and quotients:
 *             hs within 6.3 u, g 5.3 u, d12 7 u, e 2 u.
 *   [64, inf): zw_coeffs_init (rare in sweeps; it also carries the overflow cases).
 * The constraints are those of internal.h, as in batch.c, so a verdict is as safe as
 * zw_check's.
 */
#include "zwidth/sweep.h"

#include <stddef.h>

#include "internal.h"
#include "sweep_tables.h"

#define ZW_SWEEP_TABLE_END ZW_R(2.0)   /* tables below, closed forms above */
#define ZW_SWEEP_CLOSED_END ZW_R(64.0) /* zw_coeffs_init from here */
#define ZW_SWEEP_PER_UNIT ZW_R(32.0)   /* intervals per unit of delta */
#define ZW_SWEEP_BLOCK 16u             /* points whose fields wait on the stack */

/* Horner's rule, lowest power first in a[0 .. terms-1] (terms a constant at each call:
 * the compiler unrolls it). */
static inline zw_real sweep_poly(const zw_real *a, int terms, zw_real h)
{
    int k;
    zw_real acc = a[terms - 1];
    for (k = terms - 2; k >= 0; --k) {
        acc = acc * h + a[k];
    }
    return acc;
}

/* Below 2 sigma = 1: any power of two scales the hyperbola's form (region.c), and 1 lets
 * the compiler drop the division by it. */
static inline void sweep_from_tables(zw_sweep_fields *f, zw_real delta)
{
    /* delta * 32 is exact and below 64: the interval's index */
    const size_t j = (size_t)(delta * ZW_SWEEP_PER_UNIT);
    const zw_real centre = ((zw_real)j + ZW_R(0.5)) / ZW_SWEEP_PER_UNIT;
    const zw_real h = delta - centre;
    f->sigma = ZW_R(1.0);
    f->e = sweep_poly(zw_sweep_e[j], ZW_SWEEP_TERMS_E, h);
    f->g = sweep_poly(zw_sweep_g[j], ZW_SWEEP_TERMS_G, h);
    f->hs = sweep_poly(zw_sweep_w[j], ZW_SWEEP_TERMS_W, h);
    f->d12 = delta * sweep_poly(zw_sweep_q[j], ZW_SWEEP_TERMS_Q, h);
}

static inline void sweep_closed_form(zw_sweep_fields *f, zw_real delta)
{
    const zw_real e = ZW_EXP(-delta);
    const zw_real one_minus_e = ZW_R(1.0) - e;                 /* in (0.86, 1) */
    const zw_real n2 = one_minus_e - delta * e;                /* delta^2 c2 / 2, in (0.59, 1) */
    const zw_real t1 = delta - one_minus_e;                    /* delta^2 c1 / 2, >= 1.13 */
    const zw_real n12 = (delta + ZW_R(2.0)) * e + (delta - ZW_R(2.0)); /* delta^2 d12 / 2 */
    zw_real sigma = ZW_R(2.0);
    while (sigma < delta) { /* at most five doublings below 64 */
        sigma += sigma;
    }
    f->sigma = sigma;
    f->e = e;
    f->g = t1 / (delta * one_minus_e);                         /* c1 / (c1 + c2) */
    f->hs = (delta / sigma) * (delta / n2);                    /* 2 / c2 / sigma */
    f->d12 = ((n12 + n12) / delta) / delta;
}

static zw_status sweep_general(zw_sweep_fields *f, zw_real delta)
{
    zw_coeffs c;
    zw_status st = zw_coeffs_init(&c, delta);
    if (st == ZW_OK) {
        st = zw_require_coeffs(&c, true);
    }
    f->e = c.e;
    f->g = c.g;
    f->hs = c.hs;
    f->d12 = c.d12;
    f->sigma = c.sigma;
    return st;
}

/* The status zw_check gives for this delta before it looks at the gains, or ZW_OK. */
static zw_status sweep_delta_status(zw_real delta)
{
    zw_status st = ZW_OK;
    if (ZW_IS_NAN(delta)) {
        st = ZW_ERR_NAN;
    } else if (delta < ZW_R(0.0)) {
        st = ZW_ERR_DELTA;
    } else if (!ZW_IS_FINITE(delta)) {
        st = ZW_ERR_INF;
    } else {
        st = ZW_OK;
    }
    return st;
}

/* The fields at a valid delta (sweep_delta_status ZW_OK). */
static zw_status sweep_fields(zw_sweep_fields *f, zw_real delta)
{
    zw_status st = ZW_OK;
    if (delta < ZW_SWEEP_TABLE_END) {
        sweep_from_tables(f, delta);
    } else if (delta < ZW_SWEEP_CLOSED_END) {
        sweep_closed_form(f, delta);
    } else {
        st = sweep_general(f, delta);
    }
    return st;
}

static void sweep_fail_fields(zw_sweep_fields *out)
{
    out->e = ZW_NAN;
    out->g = ZW_NAN;
    out->hs = ZW_NAN;
    out->d12 = ZW_NAN;
    out->sigma = ZW_NAN;
}

zw_status zw_sweep_fields_init(zw_sweep_fields *out, zw_real delta)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = sweep_delta_status(delta);
    if (st == ZW_OK) {
        st = sweep_fields(out, delta);
    }
    if (st != ZW_OK) {
        sweep_fail_fields(out);
    }
    return st;
}

/* zw_check's stable bit on these fields (batch.c's exact_stable01; constraints of
 * internal.h, the coefficient budget of zw_coef_relerr with an exact delta).  Scalars in
 * and out, branch-free: the block loop below vectorizes like batch.c's. */
static inline zw_real sweep_stable01(zw_real delta, zw_real e, zw_real g_c, zw_real hs, zw_real d12,
                                     zw_real sigma, zw_real alpha, zw_real beta)
{
    zw_coeffs c;
    zw_gains g;
    zw_eb x;
    zw_constraint h, l;
    zw_real coef_err;
    c.delta = delta;
    c.delta_relerr = ZW_R(0.0);
    c.e = e;
    c.g = g_c;
    c.hs = hs;
    c.d12 = d12;
    c.sigma = sigma;
    c.c1 = ZW_R(0.0); /* not read by the exact-region constraints */
    c.c2 = ZW_R(0.0);
    c.s = ZW_R(0.0);
    coef_err = zw_coef_relerr(&c);
    g = zw_gains_exact(alpha, beta);
    x = zw_exact_x(&c, &g);
    h = zw_hyperbola_constraint(&c, coef_err, &g, x);
    l = zw_line_constraint(&c, coef_err, &g);
    return zw_surely_less01(ZW_R(0.0), x.v, x.e) * zw_surely_less01(ZW_R(0.0), alpha, g.alpha.e) *
           zw_surely_less01(h.lhs, h.rhs, h.err) * zw_surely_less01(l.lhs, l.rhs, l.err);
}

static zw_status sweep_invalid_at(zw_status st, size_t i, size_t *first_invalid)
{
    if (first_invalid != NULL) {
        *first_invalid = i;
    }
    return st;
}

static zw_status sweep_check_many(size_t n, const zw_real *delta, ptrdiff_t delta_stride,
                                  const zw_real *alpha, ptrdiff_t alpha_stride, const zw_real *beta,
                                  ptrdiff_t beta_stride, bool *stable, size_t *first_invalid)
{
    zw_status st = ZW_OK;
    size_t i;
    if ((delta == NULL) || (alpha == NULL) || (beta == NULL) || (stable == NULL)) {
        return sweep_invalid_at(ZW_ERR_NULL, 0u, first_invalid);
    }
    for (i = 0u; (i < n) && (st == ZW_OK); ++i) { /* the statuses zw_check gives, in its order */
        const ptrdiff_t k = (ptrdiff_t)i;
        st = sweep_delta_status(delta[k * delta_stride]);
        if (st == ZW_OK) {
            st = zw_require_finite(alpha[k * alpha_stride]);
        }
        if (st == ZW_OK) {
            st = zw_require_finite(beta[k * beta_stride]);
        }
        if (st != ZW_OK) {
            return sweep_invalid_at(st, i, first_invalid);
        }
    }
    /* Blocks: first every point's fields (independent Horner chains the CPU overlaps),
     * into arrays; then the constraints over the arrays, a branch-free loop the compiler
     * vectorizes (as batch.c's); then the bools. */
    for (i = 0u; i < n; i += ZW_SWEEP_BLOCK) {
        zw_real d[ZW_SWEEP_BLOCK], a[ZW_SWEEP_BLOCK], b[ZW_SWEEP_BLOCK];
        zw_real e[ZW_SWEEP_BLOCK], g[ZW_SWEEP_BLOCK], hs[ZW_SWEEP_BLOCK], d12[ZW_SWEEP_BLOCK];
        zw_real sigma[ZW_SWEEP_BLOCK], ok[ZW_SWEEP_BLOCK];
        const size_t count = (n - i) < ZW_SWEEP_BLOCK ? (n - i) : ZW_SWEEP_BLOCK;
        size_t j;
        for (j = 0u; j < count; ++j) {
            const ptrdiff_t k = (ptrdiff_t)(i + j);
            zw_sweep_fields f;
            d[j] = delta[k * delta_stride];
            a[j] = alpha[k * alpha_stride];
            b[j] = beta[k * beta_stride];
            if (d[j] < ZW_SWEEP_TABLE_END) {
                sweep_from_tables(&f, d[j]);
            } else {
                st = sweep_fields(&f, d[j]);
                if (st != ZW_OK) {
                    return sweep_invalid_at(st, i + j, first_invalid);
                }
            }
            e[j] = f.e;
            g[j] = f.g;
            hs[j] = f.hs;
            d12[j] = f.d12;
            sigma[j] = f.sigma;
        }
        for (j = 0u; j < count; ++j) {
            ok[j] = sweep_stable01(d[j], e[j], g[j], hs[j], d12[j], sigma[j], a[j], b[j]);
        }
        for (j = 0u; j < count; ++j) {
            stable[i + j] = ok[j] != ZW_R(0.0);
        }
    }
    return ZW_OK;
}

zw_status zw_sweep_check_many(size_t n, const zw_real *delta, ptrdiff_t delta_stride,
                              const zw_real *alpha, ptrdiff_t alpha_stride, const zw_real *beta,
                              ptrdiff_t beta_stride, bool *stable, size_t *first_invalid)
{
    size_t i;
    zw_status st = ZW_OK;
    if (n > 0u) {
        st = sweep_check_many(n, delta, delta_stride, alpha, alpha_stride, beta, beta_stride, stable,
                              first_invalid);
    }
    if ((st != ZW_OK) && (stable != NULL)) {
        for (i = 0u; i < n; ++i) {
            stable[i] = false;
        }
    }
    return st;
}
