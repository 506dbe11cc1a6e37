/* The exact-region check over many gain pairs of one plant (zwidth/batch.h).
 *
 * Validation first, so that the loop proper has no early exits; the loop evaluates every
 * constraint of internal.h unconditionally and combines the answers with &, which is what
 * makes it vectorizable.  The hyperbola is evaluated even where x = beta + delta is not
 * surely positive and is then meaningless (possibly inf or NaN, which IEEE arithmetic
 * allows), but the damping answer is false there and masks it: stable[i] equals
 * zw_check's verdict bit for bit.
 */
#include "zwidth/batch.h"

#include "internal.h"

static bool exact_stable(const zw_coeffs *c, zw_real coef_err, const zw_gains *g)
{
    const zw_eb x = zw_exact_x(c, g);
    const zw_constraint h = zw_hyperbola_constraint(c, coef_err, g, x);
    const zw_constraint l = zw_line_constraint(c, coef_err, g);
    return zw_surely_less(ZW_R(0.0), x.v, x.e) & zw_surely_less(ZW_R(0.0), g->alpha.v, g->alpha.e) &
           zw_surely_less(h.lhs, h.rhs, h.err) & zw_surely_less(l.lhs, l.rhs, l.err);
}

static zw_status invalid_at(zw_status st, size_t i, size_t *first_invalid)
{
    if (first_invalid != NULL) *first_invalid = i;
    return st;
}

zw_status zw_check_many(const zw_coeffs *c, size_t n, const zw_real *alpha, ptrdiff_t alpha_stride,
                        const zw_real *beta, ptrdiff_t beta_stride, bool *stable,
                        size_t *first_invalid)
{
    zw_status st;
    size_t i;
    zw_real coef_err;
    if (n == 0) return ZW_OK;
    if (alpha == NULL || beta == NULL || stable == NULL) return ZW_ERR_NULL;
    if ((st = zw_require_coeffs(c, true)) != ZW_OK) return invalid_at(st, 0, first_invalid);
    for (i = 0; i < n; ++i) {
        if ((st = zw_require_finite(alpha[(ptrdiff_t)i * alpha_stride])) != ZW_OK ||
            (st = zw_require_finite(beta[(ptrdiff_t)i * beta_stride])) != ZW_OK)
            return invalid_at(st, i, first_invalid);
    }
    coef_err = zw_coef_relerr(c);
    for (i = 0; i < n; ++i) {
        zw_gains g = zw_gains_exact(alpha[(ptrdiff_t)i * alpha_stride], beta[(ptrdiff_t)i * beta_stride]);
        stable[i] = exact_stable(c, coef_err, &g);
    }
    return ZW_OK;
}

zw_status zw_device_check_many(const zw_device *d, size_t n, const zw_real *K, ptrdiff_t K_stride,
                               const zw_real *B, ptrdiff_t B_stride, bool *stable,
                               size_t *first_invalid)
{
    zw_status st;
    size_t i;
    zw_real coef_err;
    if (n == 0) return ZW_OK;
    if (d == NULL || K == NULL || B == NULL || stable == NULL) return ZW_ERR_NULL;
    for (i = 0; i < n; ++i) {
        zw_real alpha, beta;
        st = zw_device_normalize(d, K[(ptrdiff_t)i * K_stride], B[(ptrdiff_t)i * B_stride], &alpha, &beta);
        if (st != ZW_OK) return invalid_at(st, i, first_invalid);
    }
    if ((st = zw_require_coeffs(&d->co, true)) != ZW_OK) return invalid_at(st, 0, first_invalid);
    coef_err = zw_coef_relerr(&d->co);
    for (i = 0; i < n; ++i) {
        /* the conversion of zw_device_normalize, with the error bounds of zw_device_check */
        zw_gains g;
        g.alpha = zw_eb_rel(K[(ptrdiff_t)i * K_stride] / d->k_scale, ZW_ALPHA_RELERR);
        g.beta = zw_eb_rel(B[(ptrdiff_t)i * B_stride] / d->b_scale, ZW_BETA_RELERR);
        stable[i] = exact_stable(&d->co, coef_err, &g);
    }
    return ZW_OK;
}
