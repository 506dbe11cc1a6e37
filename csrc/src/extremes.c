/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Achievable extremes in the normalized space, paper eqs (19)-(32).  Every formula is
 * rearranged so that nothing cancels where it is used and nothing overflows before the
 * result does:
 *   top of the hyperbola (19), (20), rationalized (c1+c2 - sqrt(.) has no cancellation
 *   after multiplying by its conjugate; sqrt(1+y) - 1 = y / (sqrt(1+y) + 1)):
 *     alpha1 = h [(c1 + (2 - e) c2) / (c1 + c2 + sqrt(c2 (e c1 + c2)))]^2,  h = 2/c2
 *     beta1  = e h / (sqrt(1 + e c1 / c2) + 1)
 *   corner (21), (22) in delta itself, with n3 = delta^2 d12 / 2 = (delta+2) e + delta - 2:
 *     alpha2 = 4 (delta/n3)^2 [(delta - 3) + (1 + delta) e (2 + e)]
 *     beta2  = (delta/n3)^2 [(4 - delta) - e (4 + 2 delta + delta e)]
 *   f(beta) = x (h - beta) / (g x + 1), x = beta + delta; L(beta) = 2 (lambda - beta),
 *   lambda = 2 (1 + e) / d12 (where the line meets alpha = 0).
 */
#include "zwidth/extremes.h"

#include <stddef.h>

#include "internal.h"

/* Does the line bind anywhere, and where does it cross alpha = 0 (lambda)?  Absent when
 * d12 is so small that lambda would exceed every representable beta of interest. */
static bool line_crossing(const zw_coeffs *c, zw_real *lambda)
{
    if (!(c->d12 > ZW_R(8.0) * ZW_REAL_MIN)) {
        return false;
    }
    *lambda = ZW_R(2.0) * (ZW_R(1.0) + c->e) / c->d12;
    return true;
}

/* f(beta) / sigma for -delta < beta < 2/c2 (the hyperbola, eq (10)). */
static zw_real hyperbola_scaled(const zw_coeffs *c, zw_real beta)
{
    zw_real x = beta + c->delta;
    zw_real room = c->hs - beta / c->sigma; /* (h - beta) / sigma */
    if (x < ZW_R(1.0)) {
        return x * room / (c->g * x + ZW_R(1.0));
    }
    return room / (c->g + ZW_R(1.0) / x);
}

/* Each function below first writes its fail-safe outputs (status.h: limits 0, ranges
 * empty), which every error return leaves and success overwrites. */

zw_status zw_hyperbola_top(const zw_coeffs *c, zw_real *alpha1, zw_real *beta1)
{
    zw_real h, q, ratio, y, a1, b1;
    zw_status st;
    zw_fail_interval(alpha1, beta1, NULL);
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return st;
    }
    if (alpha1 == NULL || beta1 == NULL) {
        return ZW_ERR_NULL;
    }
    h = c->hs * c->sigma;
    q = ZW_SQRT(c->c2) * ZW_SQRT(c->e * c->c1 + c->c2);
    ratio = (c->c1 + (ZW_R(2.0) - c->e) * c->c2) / (c->s + q);
    a1 = h * ratio * ratio;
    y = c->e == ZW_R(0.0) ? ZW_R(0.0) : c->e * c->c1 * (ZW_R(0.5) * h);
    b1 = (c->e * c->hs) * c->sigma / (ZW_SQRT(ZW_R(1.0) + y) + ZW_R(1.0));
    if (!ZW_IS_FINITE(a1) || !ZW_IS_FINITE(b1)) {
        return ZW_ERR_RANGE;
    }
    *alpha1 = a1;
    *beta1 = b1;
    return ZW_OK;
}

zw_status zw_corner(const zw_coeffs *c, zw_real *alpha2, zw_real *beta2)
{
    zw_real d, e, r, a2, b2;
    zw_status st;
    zw_fail_interval(alpha2, beta2, NULL);
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return st;
    }
    if (alpha2 == NULL || beta2 == NULL) {
        return ZW_ERR_NULL;
    }
    d = c->delta;
    e = c->e;
    if (!(d > ZW_DELTA0)) {
        return ZW_ERR_DOMAIN;
    }
    r = d / ((d + ZW_R(2.0)) * e + (d - ZW_R(2.0)));
    a2 = ZW_R(4.0) * r * (r * ((d - ZW_R(3.0)) + (ZW_R(1.0) + d) * e * (ZW_R(2.0) + e)));
    b2 = r * (r * ((ZW_R(4.0) - d) - e * (ZW_R(4.0) + ZW_R(2.0) * d + d * e)));
    if (!ZW_IS_FINITE(a2) || !ZW_IS_FINITE(b2)) {
        return ZW_ERR_RANGE;
    }
    *alpha2 = a2;
    *beta2 = b2;
    return ZW_OK;
}

/* sup beta (alpha -> 0+), eq (32): min{2/c2, lambda}; also whether the line decides. */
static zw_real beta_sup(const zw_coeffs *c)
{
    zw_real lambda;
    /* lambda < h  <=>  2 (1 + e) < hs (sigma d12); sigma d12 <= 4, so nothing overflows. */
    if (line_crossing(c, &lambda) && ZW_R(2.0) * (ZW_R(1.0) + c->e) < c->hs * (c->sigma * c->d12)) {
        return lambda;
    }
    return c->hs * c->sigma;
}

zw_status zw_alpha_max(const zw_coeffs *c, zw_real beta, zw_real *alpha_max)
{
    zw_real lambda, f;
    zw_status st;
    zw_fail_real(alpha_max, ZW_R(0.0)); /* also the answer outside (-delta, beta_mmax) */
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return st;
    }
    if (alpha_max == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_require_finite(beta);
    if (st != ZW_OK) {
        return st;
    }
    if (!(beta + c->delta > ZW_R(0.0)) || !(beta < beta_sup(c))) {
        return ZW_OK;
    }
    f = hyperbola_scaled(c, beta);
    if (line_crossing(c, &lambda)) {
        zw_real line_scaled = ZW_R(2.0) * (lambda / c->sigma - beta / c->sigma);
        if (line_scaled < f) {
            f = line_scaled;
        }
    }
    f *= c->sigma;
    if (!ZW_IS_FINITE(f)) {
        return ZW_ERR_RANGE;
    }
    *alpha_max = f;
    return ZW_OK;
}

zw_status zw_beta_interval(const zw_coeffs *c, zw_real alpha, zw_real *lo, zw_real *hi,
                           bool *nonempty)
{
    zw_real half_p, a_s2, disc, x_plus_s, x_plus, x_minus, blo, bhi, lambda;
    zw_status st;
    zw_fail_interval(lo, hi, nonempty); /* also the answer when no beta is stable */
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return st;
    }
    if (lo == NULL || hi == NULL || nonempty == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_require_finite(alpha);
    if (st != ZW_OK) {
        return st;
    }
    if (!(alpha > ZW_R(0.0))) {
        return ZW_OK;
    }
    /* Hyperbola in x = beta + delta: x^2 - P x + alpha < 0 with P = h + delta - alpha g;
     * everything divided by sigma (x by sigma, alpha by sigma^2). */
    half_p = ZW_R(0.5) * (c->hs + c->delta / c->sigma - (alpha / c->sigma) * c->g);
    a_s2 = (alpha / c->sigma) / c->sigma;
    if (!(half_p > ZW_R(0.0))) {
        return ZW_OK;
    }
    disc = (half_p - ZW_SQRT(a_s2)) * (half_p + ZW_SQRT(a_s2));
    if (!(disc > ZW_R(0.0))) {
        return ZW_OK;
    }
    x_plus_s = half_p + ZW_SQRT(disc);
    x_plus = x_plus_s * c->sigma;
    x_minus = (alpha / x_plus_s) / c->sigma; /* product of the roots is alpha: no cancellation */
    blo = x_minus - c->delta;
    bhi = x_plus - c->delta;
    if (line_crossing(c, &lambda) && lambda - ZW_R(0.5) * alpha < bhi) {
        bhi = lambda - ZW_R(0.5) * alpha;
    }
    if (!(blo < bhi)) {
        return ZW_OK;
    }
    *lo = blo;
    *hi = bhi;
    *nonempty = true;
    return ZW_OK;
}

zw_status zw_extremes_compute(const zw_coeffs *c, zw_extremes *out)
{
    zw_extremes x;
    zw_status st;
    if (out != NULL) {
        out->alpha_mmax = ZW_R(0.0);
        out->beta_at_alpha_mmax = ZW_R(0.0);
        out->alpha_p_max = ZW_R(0.0);
        out->beta_mmax = ZW_R(0.0);
        out->beta_mmin = ZW_R(0.0);
        out->alpha_mmin = ZW_R(0.0);
        out->at_corner = false;
    }
    st = zw_require_coeffs(c, true);
    if (st != ZW_OK) {
        return st;
    }
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    x.at_corner = c->delta > ZW_DELTA1;
    st = x.at_corner ? zw_corner(c, &x.alpha_mmax, &x.beta_at_alpha_mmax)
                     : zw_hyperbola_top(c, &x.alpha_mmax, &x.beta_at_alpha_mmax);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_alpha_max(c, ZW_R(0.0), &x.alpha_p_max);
    if (st != ZW_OK) {
        return st;
    }
    x.beta_mmax = beta_sup(c);
    if (!ZW_IS_FINITE(x.beta_mmax)) {
        return ZW_ERR_RANGE;
    }
    x.beta_mmin = -c->delta;
    x.alpha_mmin = ZW_R(0.0);
    *out = x;
    return ZW_OK;
}
