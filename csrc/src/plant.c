/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The sampled plant with its plant-side parts (plant.h).
 *
 * Every coefficient is a zw_eb: a value with a bound on its absolute error against the
 * exact coefficient at the exact inputs.  The ideal plant (kappa = lambda = 0) reuses the
 * fields of zw_coeffs and the factor bounds loop.c has always used (internal.h).
 */
#include "zwidth/plant.h"

#include <stddef.h>

#include "internal.h"

/* ---- small polynomial helpers (degree <= ZW_PLANT_MAX_ORDER, highest power first) ---- */

static zw_eb eb_make(zw_real v, zw_real e)
{
    zw_eb r;
    r.v = v;
    r.e = e;
    return r;
}

/* x exactly times 2^k (k small): no rounding unless it underflows. */
static zw_eb eb_scale2(zw_eb a, zw_real two_pow)
{
    return eb_make(a.v * two_pow, a.e * two_pow + ZW_ETA);
}

/* Product whose error is exactly zero when both are exact and one of them is 0, +-1 or
 * +-2 (as loop.c's, so that the ideal plant's bounds are the loop's). */
static zw_eb eb_mul_exactish(zw_eb a, zw_eb b)
{
    if ((a.e == ZW_R(0.0)) && (b.e == ZW_R(0.0))) {
        zw_real m = ZW_FABS(a.v) < ZW_FABS(b.v) ? ZW_FABS(a.v) : ZW_FABS(b.v);
        if ((m == ZW_R(0.0)) || (m == ZW_R(1.0)) || (m == ZW_R(2.0))) {
            return zw_eb_exact(a.v * b.v);
        }
    }
    return zw_eb_mul(a, b);
}

/* Sum whose error is the inputs' when one of them is an exact zero. */
static zw_eb eb_add_exactish(zw_eb a, zw_eb b)
{
    if ((a.v == ZW_R(0.0)) && (a.e == ZW_R(0.0))) {
        return b;
    }
    if ((b.v == ZW_R(0.0)) && (b.e == ZW_R(0.0))) {
        return a;
    }
    return zw_eb_add(a, b);
}

/* v (degree deg) *= f1 x + f0, in place (v holds deg + 2 entries). */
static void poly_mul_linear(zw_real v[], zw_real e[], unsigned deg, zw_eb f1, zw_eb f0)
{
    unsigned i;
    for (i = deg + 1u; i > 0u; --i) {
        zw_eb lo = eb_mul_exactish(f0, eb_make(v[i - 1u], e[i - 1u]));
        if (i <= deg) {
            lo = eb_add_exactish(eb_mul_exactish(f1, eb_make(v[i], e[i])), lo);
        }
        v[i] = lo.v;
        e[i] = lo.e;
    }
    {
        zw_eb top = eb_mul_exactish(f1, eb_make(v[0], e[0]));
        v[0] = top.v;
        e[0] = top.e;
    }
}

static void set_eb(zw_real *v, zw_real *e, zw_eb x)
{
    *v = x.v;
    *e = x.e;
}

static bool all_finite(const zw_real v[], const zw_real e[], unsigned n)
{
    unsigned i;
    for (i = 0u; i < n; ++i) {
        if (!ZW_IS_FINITE(v[i]) || !ZW_IS_FINITE(e[i])) {
            return false;
        }
    }
    return true;
}

static bool plant_finite(const zw_plant *p)
{
    const unsigned n = p->order;
    return all_finite(p->den, p->den_err, n + 1u) && all_finite(p->num, p->num_err, n) &&
           all_finite(p->den_s, p->den_s_err, n + 1u) &&
           all_finite(p->num_s, p->num_s_err, n) && all_finite(p->den_w, p->den_w_err, n + 1u);
}

/* The fail-safe plant: order 0 (refused by every consumer), every number NaN. */
static void fail_plant(zw_plant *out)
{
    unsigned i;
    if (out == NULL) {
        return;
    }
    out->spec.delta = ZW_NAN;
    out->spec.kappa = ZW_NAN;
    out->spec.lambda = ZW_NAN;
    out->spec.delta_relerr = ZW_NAN;
    out->spec.kappa_relerr = ZW_NAN;
    out->spec.lambda_relerr = ZW_NAN;
    out->order = 0u;
    for (i = 0u; i <= ZW_PLANT_MAX_ORDER; ++i) {
        out->den[i] = ZW_NAN;
        out->den_err[i] = ZW_NAN;
        out->den_s[i] = ZW_NAN;
        out->den_s_err[i] = ZW_NAN;
        out->den_w[i] = ZW_NAN;
        out->den_w_err[i] = ZW_NAN;
    }
    for (i = 0u; i < ZW_PLANT_MAX_ORDER; ++i) {
        out->num[i] = ZW_NAN;
        out->num_err[i] = ZW_NAN;
        out->num_s[i] = ZW_NAN;
        out->num_s_err[i] = ZW_NAN;
    }
    zw_fail_coeffs(&out->c);
}

/* A relative uncertainty the bounds can carry: finite, >= 0, < 1/16. */
static bool relerr_ok(zw_real r)
{
    return (r >= ZW_R(0.0)) && (r < ZW_R(0.0625));
}

/* ---- the ideal plant ------------------------------------------------------------------ */

zw_status zw_plant_from_coeffs(zw_plant *out, const zw_coeffs *c)
{
    zw_status st;
    zw_plant p;
    zw_eb f1, f0, two = zw_eb_exact(ZW_R(2.0));
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_require_coeffs(c, false);
    if ((st == ZW_OK) && (c->delta < ZW_R(0.0))) {
        st = ZW_ERR_DELTA;
    }
    if ((st == ZW_OK) && !relerr_ok(c->delta_relerr)) {
        st = ZW_ERR_ARG;
    }
    if (st != ZW_OK) {
        fail_plant(out);
        return st;
    }
    fail_plant(&p); /* every unused entry NaN */
    p.c = *c;
    p.spec.delta = c->delta;
    p.spec.kappa = ZW_R(0.0);
    p.spec.lambda = ZW_R(0.0);
    p.spec.delta_relerr = c->delta_relerr;
    p.spec.kappa_relerr = ZW_R(0.0);
    p.spec.lambda_relerr = ZW_R(0.0);
    p.order = 2u;

    /* N = c1 z + c2,  N_s = d12 s + (c1 + c2) */
    set_eb(&p.num[0], &p.num_err[0], zw_coef_field(c, c->c1));
    set_eb(&p.num[1], &p.num_err[1], zw_coef_field(c, c->c2));
    set_eb(&p.num_s[0], &p.num_s_err[0], zw_coef_field(c, c->d12));
    set_eb(&p.num_s[1], &p.num_s_err[1], zw_coef_field(c, c->s));

    /* D = 2 (z - 1)(z - e) = 2 z^2 - 2 (1 + e) z + 2 e, as loop.c forms it: 2, times z - 1,
     * times z - e. */
    p.den[0] = ZW_R(2.0);
    p.den_err[0] = ZW_R(0.0);
    p.den[1] = ZW_R(-2.0);
    p.den_err[1] = ZW_R(0.0);
    zw_coef_zme(c, &f1, &f0);
    poly_mul_linear(p.den, p.den_err, 1u, f1, f0);

    /* D_s = 2 (2 s) ((1 + e) s + (1 - e)): 4 (1 + e) s^2 + 4 (1 - e) s + 0 */
    zw_coef_zme_s(c, &f1, &f0);
    set_eb(&p.den_s[0], &p.den_s_err[0], eb_scale2(f1, ZW_R(4.0)));
    set_eb(&p.den_s[1], &p.den_s_err[1], eb_scale2(f0, ZW_R(4.0)));
    set_eb(&p.den_s[2], &p.den_s_err[2], zw_eb_exact(ZW_R(0.0)));

    /* D in w = z - 1: 2 w (w + (1 - e)) = 2 w^2 + 2 (1 - e) w + 0 */
    set_eb(&p.den_w[0], &p.den_w_err[0], two);
    set_eb(&p.den_w[1], &p.den_w_err[1], eb_scale2(f0, ZW_R(2.0)));
    set_eb(&p.den_w[2], &p.den_w_err[2], zw_eb_exact(ZW_R(0.0)));

    if (!plant_finite(&p)) {
        fail_plant(out);
        return ZW_ERR_RANGE;
    }
    *out = p;
    return ZW_OK;
}

/* ---- evaluation at a complex point ---------------------------------------------------- */

/* sum a_k x^k (a highest first, degree deg) at the complex x = (xr, xi), whose own error is
 * at most xe in modulus; *err bounds the error from the coefficients' bounds, x's error and
 * the roundings of Horner's rule (complex multiply-add: under 4u of the running magnitude
 * per step, so (4 deg + 2) u of sum |a_k| M^k, M >= |x| + xe). */
static void horner_complex(const zw_real a[], const zw_real ae[], unsigned deg, zw_real xr,
                           zw_real xi, zw_real xe, zw_real *vr, zw_real *vi, zw_real *err)
{
    unsigned k;
    zw_real r = a[0], i = ZW_R(0.0);
    const zw_real ax = ZW_SQRT(xr * xr + xi * xi) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) + ZW_ETA;
    const zw_real m = ax + xe;
    zw_real mag = ZW_FABS(a[0]) + ae[0]; /* sum (|a_k| + e_k) M^k, Horner in M */
    zw_real dmag = ZW_R(0.0);            /* its derivative in M (for x's own error) */
    zw_real cerr = ae[0];                /* sum e_k M^k */
    for (k = 1u; k <= deg; ++k) {
        const zw_real nr = r * xr - i * xi + a[k];
        const zw_real ni = r * xi + i * xr;
        r = nr;
        i = ni;
        dmag = dmag * m + mag;
        mag = mag * m + ZW_FABS(a[k]) + ae[k];
        cerr = cerr * m + ae[k];
    }
    *vr = r;
    *vi = i;
    *err = (cerr + dmag * xe + (ZW_R(4.0) * (zw_real)deg + ZW_R(2.0)) * ZW_U * mag) *
               (ZW_R(1.0) + ZW_R(16.0) * ZW_U) +
           ZW_R(8.0) * ZW_ETA;
}

zw_status zw_plant_eval(const zw_plant *plant, zw_real re, zw_real im, zw_real *num_re,
                        zw_real *num_im, zw_real *num_err, zw_real *den_re, zw_real *den_im,
                        zw_real *den_err)
{
    zw_real wr, we;
    zw_status st = ZW_OK;
    if ((num_re == NULL) || (num_im == NULL) || (num_err == NULL) || (den_re == NULL) ||
        (den_im == NULL) || (den_err == NULL) || (plant == NULL)) {
        st = ZW_ERR_NULL;
    } else if ((plant->order < 2u) || (plant->order > ZW_PLANT_MAX_ORDER)) {
        st = ZW_ERR_ARG;
    } else if (ZW_IS_NAN(re) || ZW_IS_NAN(im)) {
        st = ZW_ERR_NAN;
    } else if (!ZW_IS_FINITE(re) || !ZW_IS_FINITE(im)) {
        st = ZW_ERR_INF;
    } else {
        /* valid */
    }
    if (st != ZW_OK) {
        zw_fail_real(num_re, ZW_NAN);
        zw_fail_real(num_im, ZW_NAN);
        zw_fail_real(num_err, ZW_NAN);
        zw_fail_real(den_re, ZW_NAN);
        zw_fail_real(den_im, ZW_NAN);
        zw_fail_real(den_err, ZW_NAN);
        return st;
    }
    horner_complex(plant->num, plant->num_err, plant->order - 1u, re, im, ZW_R(0.0), num_re,
                   num_im, num_err);
    wr = re - ZW_R(1.0); /* exact for re in [1/2, 2] (Sterbenz), else one rounding */
    we = ZW_U * ZW_FABS(wr);
    horner_complex(plant->den_w, plant->den_w_err, plant->order, wr, im, we, den_re, den_im,
                   den_err);
    if (!ZW_IS_FINITE(*num_err) || !ZW_IS_FINITE(*den_err)) {
        zw_fail_real(num_re, ZW_NAN);
        zw_fail_real(num_im, ZW_NAN);
        zw_fail_real(num_err, ZW_NAN);
        zw_fail_real(den_re, ZW_NAN);
        zw_fail_real(den_im, ZW_NAN);
        zw_fail_real(den_err, ZW_NAN);
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

/* ---- the general plant ---------------------------------------------------------------- */

static zw_status check_spec(const zw_plant_spec *spec)
{
    const zw_real in[6] = {spec->delta, spec->kappa, spec->lambda, spec->delta_relerr,
                           spec->kappa_relerr, spec->lambda_relerr};
    unsigned i;
    for (i = 0u; i < 6u; ++i) {
        const zw_status st = zw_require_finite(in[i]);
        if (st != ZW_OK) {
            return st;
        }
    }
    if (spec->delta < ZW_R(0.0)) {
        return ZW_ERR_DELTA;
    }
    if ((spec->kappa < ZW_R(0.0)) || (spec->lambda < ZW_R(0.0)) ||
        !relerr_ok(spec->delta_relerr) || !relerr_ok(spec->kappa_relerr) ||
        !relerr_ok(spec->lambda_relerr)) {
        return ZW_ERR_ARG;
    }
    return ZW_OK;
}

zw_status zw_plant_init(zw_plant *out, const zw_plant_spec *spec)
{
    zw_status st;
    zw_coeffs c;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if (spec == NULL) {
        fail_plant(out);
        return ZW_ERR_NULL;
    }
    st = check_spec(spec);
    if (st != ZW_OK) {
        fail_plant(out);
        return st;
    }
    st = zw_coeffs_init(&c, spec->delta);
    if (st != ZW_OK) {
        fail_plant(out);
        return st;
    }
    c.delta_relerr = spec->delta_relerr;
    if ((spec->kappa == ZW_R(0.0)) && (spec->lambda == ZW_R(0.0))) {
        return zw_plant_from_coeffs(out, &c);
    }
    /* stiffness and lag: not yet implemented */
    fail_plant(out);
    return ZW_ERR_ARG;
}

zw_status zw_plant_spec_from_device(zw_real m, zw_real b, zw_real T, zw_real k_p, zw_real tau,
                                    zw_real m_h, zw_real b_h, zw_real k_h, zw_plant_spec *spec,
                                    zw_real *mass)
{
    (void)m;
    (void)b;
    (void)T;
    (void)k_p;
    (void)tau;
    (void)m_h;
    (void)b_h;
    (void)k_h;
    if (spec != NULL) {
        spec->delta = ZW_NAN;
        spec->kappa = ZW_NAN;
        spec->lambda = ZW_NAN;
        spec->delta_relerr = ZW_NAN;
        spec->kappa_relerr = ZW_NAN;
        spec->lambda_relerr = ZW_NAN;
    }
    zw_fail_real(mass, ZW_NAN);
    return ZW_ERR_ARG; /* not yet implemented */
}
