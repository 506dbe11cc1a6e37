/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The exact-region check over many gain pairs of one plant (zwidth/batch.h).
 *
 * Validation first, so that the loop proper has no early exits; the loop evaluates every
 * constraint of internal.h unconditionally and multiplies their 1/0 answers, in zw_real
 * so that no integer conversion stops the compiler from vectorizing it (the bools are
 * written by a second short loop per block).  The hyperbola is evaluated even where x = beta + delta is not
 * surely positive and is then meaningless (possibly inf or NaN, which IEEE arithmetic
 * allows), but the damping answer is false there and masks it: stable[i] equals
 * zw_check's verdict bit for bit.
 */
#include "zwidth/batch.h"

#include "internal.h"

/* Pairs per block: the 1/0 answers of a block wait in a zw_real array on the stack. */
#define ZW_BATCH_BLOCK 16u

static zw_real exact_stable01(const zw_coeffs *c, zw_real coef_err, const zw_gains *g)
{
    const zw_eb x = zw_exact_x(c, g);
    const zw_constraint h = zw_hyperbola_constraint(c, coef_err, g, x);
    const zw_constraint l = zw_line_constraint(c, coef_err, g);
    return zw_surely_less01(ZW_R(0.0), x.v, x.e) * zw_surely_less01(ZW_R(0.0), g->alpha.v, g->alpha.e) *
           zw_surely_less01(h.lhs, h.rhs, h.err) * zw_surely_less01(l.lhs, l.rhs, l.err);
}

static void store_block(bool *stable, const zw_real *ok, size_t count)
{
    size_t j;
    for (j = 0; j < count; ++j) {
        stable[j] = ok[j] != ZW_R(0.0);
    }
}

static zw_status invalid_at(zw_status st, size_t i, size_t *first_invalid)
{
    if (first_invalid != NULL) {
        *first_invalid = i;
    }
    return st;
}

/* On an error no pair has a verdict: every flag the call was asked for is false. */
static zw_status fail_all(zw_status st, bool *stable, size_t n)
{
    size_t i;
    if ((st != ZW_OK) && (stable != NULL)) {
        for (i = 0; i < n; ++i) {
            stable[i] = false;
        }
    }
    return st;
}

static zw_status check_many(const zw_coeffs *c, size_t n, const zw_real *alpha, ptrdiff_t alpha_stride,
                            const zw_real *beta, ptrdiff_t beta_stride, bool *stable,
                            size_t *first_invalid)
{
    zw_status st;
    size_t i;
    zw_real coef_err;
    if (n == 0u) {
        return ZW_OK;
    }
    if (c == NULL || alpha == NULL || beta == NULL || stable == NULL) {
        return invalid_at(ZW_ERR_NULL, 0, first_invalid);
    }
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return invalid_at(st, 0, first_invalid);
    }
    for (i = 0; i < n; ++i) {
        st = zw_require_finite(alpha[(ptrdiff_t)i * alpha_stride]);
        if (st == ZW_OK) {
            st = zw_require_finite(beta[(ptrdiff_t)i * beta_stride]);
        }
        if (st != ZW_OK) {
            return invalid_at(st, i, first_invalid);
        }
    }
    coef_err = zw_coef_relerr(c);
    for (i = 0u; i < n; i += ZW_BATCH_BLOCK) {
        zw_real ok[ZW_BATCH_BLOCK];
        size_t j, count = ((n - i) < ZW_BATCH_BLOCK) ? (n - i) : ZW_BATCH_BLOCK;
        for (j = 0; j < count; ++j) {
            const ptrdiff_t k = (ptrdiff_t)i + (ptrdiff_t)j;
            zw_gains g = zw_gains_exact(alpha[k * alpha_stride], beta[k * beta_stride]);
            ok[j] = exact_stable01(c, coef_err, &g);
        }
        store_block(&stable[i], ok, count);
    }
    return ZW_OK;
}

zw_status zw_check_many(const zw_coeffs *c, size_t n, const zw_real *alpha, ptrdiff_t alpha_stride,
                        const zw_real *beta, ptrdiff_t beta_stride, bool *stable,
                        size_t *first_invalid)
{
    return fail_all(check_many(c, n, alpha, alpha_stride, beta, beta_stride, stable, first_invalid),
                    stable, n);
}

static zw_status device_check_many(const zw_device *d, size_t n, const zw_real *K, ptrdiff_t K_stride,
                                   const zw_real *B, ptrdiff_t B_stride, bool *stable,
                                   size_t *first_invalid)
{
    zw_status st;
    size_t i;
    zw_real coef_err;
    if (n == 0u) {
        return ZW_OK;
    }
    if (d == NULL || K == NULL || B == NULL || stable == NULL) {
        return invalid_at(ZW_ERR_NULL, 0, first_invalid);
    }
    for (i = 0; i < n; ++i) {
        zw_real alpha, beta;
        st = zw_device_normalize(d, K[(ptrdiff_t)i * K_stride], B[(ptrdiff_t)i * B_stride], &alpha, &beta);
        if (st != ZW_OK) {
            return invalid_at(st, i, first_invalid);
        }
    }
    st = zw_require_coeffs(&d->co, true);
    if (st != ZW_OK) {
        return invalid_at(st, 0, first_invalid);
    }
    coef_err = zw_coef_relerr(&d->co);
    for (i = 0u; i < n; i += ZW_BATCH_BLOCK) {
        zw_real ok[ZW_BATCH_BLOCK];
        size_t j, count = ((n - i) < ZW_BATCH_BLOCK) ? (n - i) : ZW_BATCH_BLOCK;
        for (j = 0; j < count; ++j) {
            /* the conversion of zw_device_normalize, with the error bounds of zw_device_check */
            const ptrdiff_t k = (ptrdiff_t)i + (ptrdiff_t)j;
            zw_gains g;
            g.alpha = zw_eb_rel(K[k * K_stride] / d->k_scale, ZW_ALPHA_RELERR);
            g.beta = zw_eb_rel(B[k * B_stride] / d->b_scale, ZW_BETA_RELERR);
            ok[j] = exact_stable01(&d->co, coef_err, &g);
        }
        store_block(&stable[i], ok, count);
    }
    return ZW_OK;
}

zw_status zw_device_check_many(const zw_device *d, size_t n, const zw_real *K, ptrdiff_t K_stride,
                               const zw_real *B, ptrdiff_t B_stride, bool *stable,
                               size_t *first_invalid)
{
    return fail_all(device_check_many(d, n, K, K_stride, B, B_stride, stable, first_invalid),
                    stable, n);
}
