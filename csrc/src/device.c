/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Real units, paper Section IV: delta = b T / m, alpha = K T^2 / m, beta = B T / m. */
#include "zwidth/device.h"

#include <stddef.h>

#include "internal.h"

static bool is_normal_positive(zw_real x)
{
    return x >= ZW_REAL_MIN && x <= ZW_REAL_MAX;
}

static zw_status device_init(zw_device *out, zw_real m, zw_real b, zw_real T)
{
    zw_device d;
    zw_status st;
    zw_real T_over_m, delta;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if (ZW_IS_NAN(m) || ZW_IS_NAN(b) || ZW_IS_NAN(T)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(m) || !ZW_IS_FINITE(b) || !ZW_IS_FINITE(T)) {
        return ZW_ERR_INF;
    }
    if (!(m > ZW_R(0.0))) {
        return ZW_ERR_MASS;
    }
    if (!(T > ZW_R(0.0))) {
        return ZW_ERR_PERIOD;
    }
    if (b < ZW_R(0.0)) {
        return ZW_ERR_DAMPING;
    }
    /* Every quantity the error budget counts in relative terms must be a normal number:
     * a subnormal input or intermediate carries an unbounded relative error. */
    if (!is_normal_positive(m) || !is_normal_positive(T) || (b > ZW_R(0.0) && !is_normal_positive(b))) {
        return ZW_ERR_RANGE;
    }
    d.m = m;
    d.b = b;
    d.T = T;
    d.b_scale = m / T;
    d.k_scale = d.b_scale / T;
    T_over_m = T / m;
    delta = b * T_over_m; /* b (T/m): no overflow of b T where delta itself is fine */
    if (!is_normal_positive(d.b_scale) || !is_normal_positive(d.k_scale) ||
        !is_normal_positive(T_over_m)) {
        return ZW_ERR_RANGE;
    }
    if (b > ZW_R(0.0) && !is_normal_positive(delta)) {
        return ZW_ERR_RANGE;
    }
    st = zw_coeffs_init(&d.co, delta);
    if (st != ZW_OK) {
        return st;
    }
    if (!ZW_IS_FINITE(d.co.hs)) {
        return ZW_ERR_RANGE;
    }
    d.co.delta_relerr = ZW_DELTA_RELERR;
    *out = d;
    return ZW_OK;
}

zw_status zw_device_init(zw_device *out, zw_real m, zw_real b, zw_real T)
{
    zw_status st = device_init(out, m, b, T);
    if (st != ZW_OK && out != NULL) {
        out->m = ZW_NAN;
        out->b = ZW_NAN;
        out->T = ZW_NAN;
        out->k_scale = ZW_NAN;
        out->b_scale = ZW_NAN;
        zw_fail_coeffs(&out->co);
    }
    return st;
}

/* Also refuses a device a failed zw_device_init left NaN (ZW_ERR_NAN from its delta). */
static zw_status normalize(const zw_device *d, zw_real K, zw_real B, zw_real *alpha,
                           zw_real *beta)
{
    zw_status st;
    zw_real a, bb;
    if (d == NULL || alpha == NULL || beta == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_require_coeffs(&d->co, false);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(K);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_require_finite(B);
    if (st != ZW_OK) {
        return st;
    }
    a = K / d->k_scale;
    bb = B / d->b_scale;
    if (!ZW_IS_FINITE(a) || !ZW_IS_FINITE(bb)) {
        return ZW_ERR_RANGE;
    }
    *alpha = a;
    *beta = bb;
    return ZW_OK;
}

zw_status zw_device_normalize(const zw_device *d, zw_real K, zw_real B, zw_real *alpha,
                              zw_real *beta)
{
    zw_status st = normalize(d, K, B, alpha, beta);
    if (st != ZW_OK) {
        zw_fail_real(alpha, ZW_NAN);
        zw_fail_real(beta, ZW_NAN);
    }
    return st;
}

/* Normalized gains with the error bounds of their conversion. */
static zw_status normalize_bounded(const zw_device *d, zw_real K, zw_real B, zw_gains *g)
{
    zw_real a, bb;
    zw_status st = zw_device_normalize(d, K, B, &a, &bb);
    if (st != ZW_OK) {
        return st;
    }
    g->alpha = zw_eb_rel(a, ZW_ALPHA_RELERR);
    g->beta = zw_eb_rel(bb, ZW_BETA_RELERR);
    return ZW_OK;
}

zw_status zw_device_check_region(zw_region region, const zw_device *d, zw_real K, zw_real B,
                                 zw_verdict *out)
{
    zw_gains g;
    zw_status st = normalize_bounded(d, K, B, &g);
    if (st != ZW_OK) {
        zw_fail_verdict(out);
        return st;
    }
    return zw_check_bounded(region, &d->co, &g, out); /* fail-safe itself */
}

zw_status zw_device_check(const zw_device *d, zw_real K, zw_real B, zw_verdict *out)
{
    return zw_device_check_region(ZW_REGION_EXACT, d, K, B, out);
}

zw_status zw_device_spectral_radius(const zw_device *d, zw_real K, zw_real B, zw_real *rho)
{
    zw_real alpha, beta;
    zw_status st = zw_device_normalize(d, K, B, &alpha, &beta);
    if (st != ZW_OK) {
        zw_fail_real(rho, ZW_INF);
        return st;
    }
    return zw_spectral_radius(&d->co, alpha, beta, rho); /* fail-safe itself */
}

zw_status zw_device_radius_within(const zw_device *d, zw_real K, zw_real B, zw_real r,
                                  bool *within)
{
    zw_gains g;
    zw_status st = normalize_bounded(d, K, B, &g);
    if (st != ZW_OK) {
        zw_fail_bool(within);
        return st;
    }
    return zw_radius_within_bounded(&d->co, &g, r, within); /* fail-safe itself */
}

static zw_status device_extremes(const zw_device *d, zw_device_extremes *out)
{
    zw_extremes x;
    zw_real K_mmax, K_p_max, B_mmax, B_at;
    zw_status st;
    if (d == NULL || out == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_extremes_compute(&d->co, &x);
    if (st != ZW_OK) {
        return st;
    }
    K_mmax = x.alpha_mmax * d->k_scale;
    K_p_max = x.alpha_p_max * d->k_scale;
    B_mmax = x.beta_mmax * d->b_scale;
    B_at = x.beta_at_alpha_mmax * d->b_scale;
    if (!ZW_IS_FINITE(K_mmax) || !ZW_IS_FINITE(K_p_max) || !ZW_IS_FINITE(B_mmax) ||
        !ZW_IS_FINITE(B_at)) {
        return ZW_ERR_RANGE;
    }
    out->K_mmax = K_mmax;
    out->B_at_K_mmax = B_at;
    out->at_corner = x.at_corner;
    out->K_p_max = K_p_max;
    out->B_mmax = B_mmax;
    out->B_mmin = -d->b;
    out->K_mmin = ZW_R(0.0);
    return ZW_OK;
}

zw_status zw_device_extremes_compute(const zw_device *d, zw_device_extremes *out)
{
    zw_status st = device_extremes(d, out);
    if (st != ZW_OK && out != NULL) {
        out->K_mmax = ZW_R(0.0);
        out->B_at_K_mmax = ZW_R(0.0);
        out->K_p_max = ZW_R(0.0);
        out->B_mmax = ZW_R(0.0);
        out->B_mmin = ZW_R(0.0);
        out->K_mmin = ZW_R(0.0);
        out->at_corner = false;
    }
    return st;
}

static zw_status k_max_at(const zw_device *d, zw_real B, zw_real *K_max)
{
    zw_real alpha, beta, a_max;
    zw_status st;
    if (K_max == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_device_normalize(d, ZW_R(0.0), B, &alpha, &beta);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_alpha_max(&d->co, beta, &a_max);
    if (st != ZW_OK) {
        return st;
    }
    a_max *= d->k_scale;
    if (!ZW_IS_FINITE(a_max)) {
        return ZW_ERR_RANGE;
    }
    *K_max = a_max;
    return ZW_OK;
}

zw_status zw_device_k_max(const zw_device *d, zw_real B, zw_real *K_max)
{
    zw_status st = k_max_at(d, B, K_max);
    if (st != ZW_OK) {
        zw_fail_real(K_max, ZW_R(0.0));
    }
    return st;
}

static zw_status b_range(const zw_device *d, zw_real K, zw_real *B_lo, zw_real *B_hi,
                         bool *nonempty)
{
    zw_real alpha, beta, lo, hi;
    bool any;
    zw_status st;
    if (B_lo == NULL || B_hi == NULL || nonempty == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_device_normalize(d, K, ZW_R(0.0), &alpha, &beta);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_beta_interval(&d->co, alpha, &lo, &hi, &any);
    if (st != ZW_OK) {
        return st;
    }
    lo *= d->b_scale;
    hi *= d->b_scale;
    if (!ZW_IS_FINITE(lo) || !ZW_IS_FINITE(hi)) {
        return ZW_ERR_RANGE;
    }
    *B_lo = lo;
    *B_hi = hi;
    *nonempty = any;
    return ZW_OK;
}

zw_status zw_device_b_range(const zw_device *d, zw_real K, zw_real *B_lo, zw_real *B_hi,
                            bool *nonempty)
{
    zw_status st = b_range(d, K, B_lo, B_hi, nonempty);
    if (st != ZW_OK) {
        zw_fail_interval(B_lo, B_hi, nonempty);
    }
    return st;
}

/* Sign of the slope on a curve that falls, rises, falls... across the given breakpoints:
 * first_trend holds below breaks[0] and alternates at each one. */
static zw_trend piecewise_trend(zw_real delta, const zw_real *breaks, int n, zw_trend first_trend)
{
    int i;
    zw_trend t = first_trend;
    for (i = 0; i < n; ++i) {
        if (delta == breaks[i]) {
            return ZW_FLAT;
        }
        if (delta < breaks[i]) {
            return t;
        }
        t = (zw_trend)(-(int)t);
    }
    return t;
}

static zw_trend opposite(zw_trend t)
{
    return (zw_trend)(-(int)t);
}

static zw_status influence(const zw_device *d, zw_influence *out)
{
    static const zw_real k_breaks[2] = {ZW_DELTA_K1, ZW_DELTA_K2};
    static const zw_real b_breaks[2] = {ZW_DELTA_B, ZW_DELTA0};
    static const zw_real beta_breaks[2] = {ZW_DELTA0, ZW_DELTA_BB};
    zw_extremes x;
    zw_real bT, b_over_T, m_over_b, K_mmax, B_mmax;
    zw_status st;
    if (d == NULL || out == NULL) {
        return ZW_ERR_NULL;
    }
    /* the normalized extremes directly, not zw_device_extremes_compute: one frame less */
    st = zw_extremes_compute(&d->co, &x);
    if (st != ZW_OK) {
        return st;
    }
    K_mmax = x.alpha_mmax * d->k_scale;
    B_mmax = x.beta_mmax * d->b_scale;
    /* Every critical value is one of these times a constant below 5. */
    bT = d->b * d->T;
    b_over_T = d->b / d->T;
    m_over_b = d->b > ZW_R(0.0) ? d->m / d->b : ZW_R(0.0);
    if (!ZW_IS_FINITE(K_mmax) || !ZW_IS_FINITE(B_mmax) || !ZW_IS_FINITE(ZW_R(5.0) * bT) ||
        !ZW_IS_FINITE(ZW_R(5.0) * b_over_T) || !ZW_IS_FINITE(ZW_R(5.0) * m_over_b) ||
        !ZW_IS_FINITE(ZW_R(5.0) * d->b_scale)) {
        return ZW_ERR_RANGE;
    }
    /* Nothing below can fail, so *out is filled in place (no second copy on the stack). */
    out->delta = d->co.delta;
    out->K_mmax = K_mmax;
    out->B_mmax = B_mmax;
    out->m_K1 = bT / ZW_DELTA_K1;
    out->m_K2 = bT / ZW_DELTA_K2;
    out->m_K_match = bT / ZW_DELTA_KM;
    out->m_0 = bT / ZW_DELTA0;
    out->m_B = bT / ZW_DELTA_B;
    out->K_mmax_at_m_K2 = ZW_KMAX_LOCAL_MAX * b_over_T;
    out->K_mmax_at_m_K1 = ZW_KMAX_LOCAL_MIN * b_over_T;
    out->b_0 = ZW_DELTA0 * d->b_scale;
    out->b_BB = ZW_DELTA_BB * d->b_scale;
    if (d->b > ZW_R(0.0)) {
        out->T_B = ZW_DELTA_B * m_over_b;
        out->T_0 = ZW_DELTA0 * m_over_b;
    } else {
        out->T_B = ZW_HUGE_VAL; /* documented: no turning point in T */
        out->T_0 = ZW_HUGE_VAL;
    }
    /* K_mmax = (b/T) alpha_mmax(delta)/delta: alpha_mmax/delta falls, rises, falls across
     * delta_K1, delta_K2, and delta = bT/m moves against m. */
    out->K_vs_m = opposite(piecewise_trend(d->co.delta, k_breaks, 2, ZW_FALLS));
    out->K_vs_b = ZW_RISES; /* (m/T^2) alpha_mmax(delta), alpha_mmax increasing */
    out->K_vs_T = ZW_FALLS; /* (b^2/m) alpha_mmax/delta^2, decreasing (paper eq (36)) */
    /* B_mmax = b beta_mmax(delta)/delta against delta (b fixed): falls, rises, falls
     * across delta_B, delta_0; T moves delta with it, m against it. */
    out->B_vs_T = piecewise_trend(d->co.delta, b_breaks, 2, ZW_FALLS);
    out->B_vs_m = opposite(out->B_vs_T);
    /* (m/T) beta_mmax(delta): beta_mmax rises, falls on (delta_0, delta_BB), rises */
    out->B_vs_b = piecewise_trend(d->co.delta, beta_breaks, 2, ZW_RISES);
    out->best_m_for_K = out->K_vs_m == ZW_FALLS ? out->m_K2 : d->m;
    return ZW_OK;
}

zw_status zw_device_influence(const zw_device *d, zw_influence *out)
{
    zw_status st = influence(d, out);
    if (st != ZW_OK && out != NULL) {
        out->K_mmax = ZW_R(0.0);
        out->B_mmax = ZW_R(0.0);
        out->K_mmax_at_m_K2 = ZW_R(0.0);
        out->K_mmax_at_m_K1 = ZW_R(0.0);
        out->delta = ZW_NAN;
        out->m_K1 = ZW_NAN;
        out->m_K2 = ZW_NAN;
        out->m_K_match = ZW_NAN;
        out->T_B = ZW_NAN;
        out->T_0 = ZW_NAN;
        out->m_0 = ZW_NAN;
        out->m_B = ZW_NAN;
        out->b_0 = ZW_NAN;
        out->b_BB = ZW_NAN;
        out->best_m_for_K = ZW_NAN;
        out->K_vs_m = ZW_TREND_UNKNOWN;
        out->K_vs_b = ZW_TREND_UNKNOWN;
        out->K_vs_T = ZW_TREND_UNKNOWN;
        out->B_vs_m = ZW_TREND_UNKNOWN;
        out->B_vs_b = ZW_TREND_UNKNOWN;
        out->B_vs_T = ZW_TREND_UNKNOWN;
    }
    return st;
}
