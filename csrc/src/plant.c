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

#include "zwidth/portable_math.h"

#include "internal.h"

/* ---- small polynomial helpers (degree <= ZW_PLANT_MAX_ORDER, highest power first) ---- */


/* x exactly times 2^k (k small): no rounding unless it underflows. */
static zw_eb eb_scale2(zw_eb a, zw_real two_pow)
{
    return zw_eb_make(a.v * two_pow, a.e * two_pow + ZW_ETA);
}

static void set_eb(zw_real *v, zw_real *e, zw_eb x)
{
    *v = x.v;
    *e = x.e;
}

static bool finite_bounded(const zw_real v[], const zw_real e[], unsigned n)
{
    unsigned i;
    for (i = 0u; i < n; ++i) {
        /* a bound of ZW_REAL_MAX is zw_eb_div's "unbounded" */
        if (!ZW_IS_FINITE(v[i]) || !ZW_IS_FINITE(e[i]) || !(e[i] < ZW_REAL_MAX)) {
            return false;
        }
    }
    return true;
}

static bool plant_finite(const zw_plant *p)
{
    const unsigned n = p->order;
    return finite_bounded(p->den, p->den_err, n + 1u) && finite_bounded(p->num, p->num_err, n) &&
           finite_bounded(p->den_s, p->den_s_err, n + 1u) &&
           finite_bounded(p->num_s, p->num_s_err, n) && finite_bounded(p->den_w, p->den_w_err, n + 1u);
}

/* The fail-safe plant: order 0 (refused by every consumer), every number NaN (internal.h). */
void zw_plant_fail(zw_plant *out)
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

/* Built in place in *out (no second zw_plant on the stack); *c is copied first, since it may
 * be &out->c (zw_plant_init). */
zw_status zw_plant_from_coeffs(zw_plant *out, const zw_coeffs *c)
{
    zw_status st;
    zw_coeffs cc;
    zw_eb f1, f0, t, two = zw_eb_exact(ZW_R(2.0));
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
        zw_plant_fail(out);
        return st;
    }
    cc = *c;
    zw_plant_fail(out); /* every unused entry NaN */
    out->c = cc;
    out->spec.delta = cc.delta;
    out->spec.kappa = ZW_R(0.0);
    out->spec.lambda = ZW_R(0.0);
    out->spec.delta_relerr = cc.delta_relerr;
    out->spec.kappa_relerr = ZW_R(0.0);
    out->spec.lambda_relerr = ZW_R(0.0);
    out->order = 2u;

    /* N = c1 z + c2,  N_s = d12 s + (c1 + c2) */
    t = zw_coef_field(&cc, cc.c1);
    set_eb(&out->num[0], &out->num_err[0], t);
    t = zw_coef_field(&cc, cc.c2);
    set_eb(&out->num[1], &out->num_err[1], t);
    t = zw_coef_field(&cc, cc.d12);
    set_eb(&out->num_s[0], &out->num_s_err[0], t);
    t = zw_coef_field(&cc, cc.s);
    set_eb(&out->num_s[1], &out->num_s_err[1], t);

    /* D = 2 (z - 1)(z - e) = 2 z^2 - 2 (1 + e) z + 2 e, as loop.c forms it: 2, times z - 1,
     * times z - e. */
    out->den[0] = ZW_R(2.0);
    out->den_err[0] = ZW_R(0.0);
    out->den[1] = ZW_R(-2.0);
    out->den_err[1] = ZW_R(0.0);
    zw_coef_zme(&cc, &f1, &f0);
    zw_eb_poly_mul_linear(out->den, out->den_err, 1u, f1, f0);

    /* D_s = 2 (2 s) ((1 + e) s + (1 - e)): 4 (1 + e) s^2 + 4 (1 - e) s + 0 */
    zw_coef_zme_s(&cc, &f1, &f0);
    set_eb(&out->den_s[0], &out->den_s_err[0], eb_scale2(f1, ZW_R(4.0)));
    set_eb(&out->den_s[1], &out->den_s_err[1], eb_scale2(f0, ZW_R(4.0)));
    set_eb(&out->den_s[2], &out->den_s_err[2], zw_eb_exact(ZW_R(0.0)));

    /* D in w = z - 1: 2 w (w + (1 - e)) = 2 w^2 + 2 (1 - e) w + 0 */
    set_eb(&out->den_w[0], &out->den_w_err[0], two);
    set_eb(&out->den_w[1], &out->den_w_err[1], eb_scale2(f0, ZW_R(2.0)));
    set_eb(&out->den_w[2], &out->den_w_err[2], zw_eb_exact(ZW_R(0.0)));

    if (!plant_finite(out)) {
        zw_plant_fail(out);
        return ZW_ERR_RANGE;
    }
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

/* ---- balls: zw_eb values whose bound also covers the inputs' uncertainty -------------
 *
 * The inputs enter as balls (delta +- delta_relerr delta, kappa +- kappa_relerr kappa), and
 * every operation propagates both its rounding and its inputs' bounds (zw_eb's arithmetic is
 * rigorous for that: its products keep the a.e b.e term).  The library functions below bound
 * the change of f over the whole ball (a Lipschitz bound on it) plus libm's own error, taken
 * as 1 ulp (2u relative) as coeffs.c does, and for expm1 ZW_EXPM1_PORTABLE_ULPS: the bound of
 * the portable fallback a ZW_PORTABLE_MATH build uses (portable_math.h; plant_box.c charges
 * the same).  These hold for balls of any width; a bound that overflows makes
 * zw_plant_init answer ZW_ERR_RANGE. */

/* expm1's relative error: ZW_EXPM1_PORTABLE_ULPS ulps, an ulp being at most 2u. */
#define PLANT_EXPM1_REL (ZW_R(2.0) * (zw_real)ZW_EXPM1_PORTABLE_ULPS * ZW_U)

static zw_eb eb_neg(zw_eb a)
{
    return zw_eb_make(-a.v, a.e);
}

/* e^(a.v + a.e), rounded up: the largest derivative of exp (and expm1) over the ball. */
static zw_real exp_top(zw_eb a)
{
    return ZW_EXP(a.v + a.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) + ZW_ETA;
}

/* e^a: |e^y - e^x| <= e^(x + e) e over the ball. */
static zw_eb eb_exp(zw_eb a)
{
    const zw_real v = ZW_EXP(a.v);
    return zw_eb_make(v, exp_top(a) * a.e + ZW_R(2.0) * ZW_U * v + ZW_ETA);
}

/* e^a - 1, same derivative. */
static zw_eb eb_expm1(zw_eb a)
{
    const zw_real v = ZW_EXPM1(a.v);
    return zw_eb_make(v, exp_top(a) * a.e + PLANT_EXPM1_REL * ZW_FABS(v) + ZW_ETA);
}

/* E0(a) = (e^a - 1) / a = int_0^1 e^(a t) dt (1 at 0), for a.v <= 0.  Its log-derivative is
 * the mean of t under the weight e^(a t): in (0, 1), at most 1/2 for a <= 0 and at most
 * 1/|a|; so over the ball E0 stays within a factor e^(a.e) of E0(a) and
 * |E0(y) - E0(a)| <= E0(a) e^(a.e) slope a.e.  Rounding: expm1's, the division's u and u of
 * slack. */
static zw_eb eb_e0(zw_eb a)
{
    zw_real v, slope;
    if (a.v == ZW_R(0.0)) {
        v = ZW_R(1.0);
    } else {
        v = ZW_EXPM1(a.v) / a.v;
    }
    if (a.v > ZW_R(0.0)) {
        return zw_eb_make(v, ZW_INF);
    }
    if (a.v + a.e < ZW_R(0.0)) {
        const zw_real inv = ZW_R(1.0) / -(a.v + a.e) * (ZW_R(1.0) + ZW_R(2.0) * ZW_U);
        slope = inv < ZW_R(0.5) ? inv : ZW_R(0.5);
    } else {
        slope = ZW_R(1.0);
    }
    return zw_eb_make(v, v * (ZW_EXP(a.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) * slope * a.e +
                           (PLANT_EXPM1_REL + ZW_R(2.0) * ZW_U)) +
                          ZW_R(2.0) * ZW_ETA);
}

/* sqrt(a) for a.v >= 0: |sqrt(y) - sqrt(x)| <= |y - x| / sqrt(x), and <= sqrt|y - x|. */
static zw_eb eb_sqrt(zw_eb a)
{
    zw_real v = ZW_SQRT(a.v), prop;
    if (a.v > ZW_R(4.0) * a.e) {
        prop = a.e / v * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    } else {
        prop = ZW_SQRT(ZW_R(2.0) * a.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U);
    }
    return zw_eb_make(v, prop + ZW_U * v + ZW_ETA);
}

/* cos, sin: Lipschitz 1. */
static zw_eb eb_cos(zw_eb a)
{
    zw_real v = ZW_COS(a.v);
    return zw_eb_make(v, a.e + ZW_R(2.0) * ZW_U * ZW_FABS(v) + ZW_ETA);
}

static zw_eb eb_sin(zw_eb a)
{
    zw_real v = ZW_SIN(a.v);
    return zw_eb_make(v, a.e + ZW_R(2.0) * ZW_U * ZW_FABS(v) + ZW_ETA);
}

static zw_eb eb_half(zw_eb a)
{
    return zw_eb_make(ZW_R(0.5) * a.v, ZW_R(0.5) * a.e + ZW_ETA);
}

static zw_eb eb_twice(zw_eb a)
{
    return zw_eb_make(ZW_R(2.0) * a.v, ZW_R(2.0) * a.e);
}

/* h^2 - k with the product exact (Dekker's two-product, Veltkamp's split; no fma needed),
 * so that near critical damping w2 keeps its relative accuracy.  h >= 0 below 2^(emax/2). */
static zw_eb eb_square_minus(zw_eb h, zw_eb k)
{
#ifdef ZW_REAL_FLOAT
    const zw_real split = ZW_R(4097.0); /* 2^12 + 1 */
#else
    const zw_real split = ZW_R(134217729.0); /* 2^27 + 1 */
#endif
    const zw_real x = h.v;
    const zw_real hi_sq = x * x;
    const zw_real c = split * x;
    const zw_real xh = c - (c - x);
    const zw_real xl = x - xh;
    const zw_real lo = ((xh * xh - hi_sq) + ZW_R(2.0) * xh * xl) + xl * xl; /* x^2 = hi + lo */
    const zw_real t = hi_sq - k.v;
    const zw_real w = t + lo;
    zw_eb r;
    r.v = w;
    r.e = ZW_U * (ZW_FABS(t) + ZW_FABS(w)) + ZW_R(4.0) * ZW_ETA /* the two roundings */
          + h.e * (ZW_R(2.0) * x + h.e) + k.e;                    /* the inputs' balls */
    if (!ZW_IS_FINITE(c) || !ZW_IS_FINITE(hi_sq)) {
        r.e = ZW_INF;
    }
    return r;
}

/* ---- series of the entire functions of w = r^2 ------------------------------------------
 * C(w) = cosh sqrt(w) = sum w^k / (2k)!,  S(w) = sinh sqrt(w) / sqrt(w) = sum w^k / (2k+1)!
 * (cos and sin for w < 0), and their divided differences over [a, b]:
 * C[a, b] = sum_{k>=1} h_{k-1}(a, b) / (2k)!, S[a, b] = sum_{k>=1} h_{k-1}(a, b) / (2k+1)!,
 * h_m(a, b) = sum_j a^j b^(m-j) (|h_m| <= (m+1) 4^m for |a|, |b| <= 4).  Used for
 * |a|, |b| <= 4 only: PLANT_TERMS terms leave a tail below PLANT_TAIL (21 4^20 / 42! < 2e-38,
 * and the tail of the single series is smaller still). */
#define PLANT_SERIES_LIMIT ZW_R(4.0)

/* Is the whole ball within [-limit, limit]?  (The truncation bounds hold for all of it.) */
static bool eb_within(zw_eb a, zw_real limit)
{
    return (ZW_FABS(a.v) + a.e) <= limit;
}
#define PLANT_TERMS 21u
#define PLANT_TAIL ZW_R(2e-38)

/* 1 / n! for n = 0 .. 2 PLANT_TERMS + 1 (n roundings: within n (u 1/n! + eta), eta covering
 * the float build's underflow of the last ones). */
static zw_real inv_factorial(unsigned n)
{
    unsigned i;
    zw_real f = ZW_R(1.0);
    for (i = 2u; i <= n; ++i) {
        f = f / (zw_real)i;
    }
    return f;
}

/* sum_{k} w^k / (2k + odd)!, by Horner, with the coefficient roundings (n divisions each:
 * n u relative, at most (2 PLANT_TERMS + 1) u) and the tail. */
static zw_eb series_single(zw_eb w, unsigned odd)
{
    unsigned k;
    zw_eb acc = zw_eb_exact(ZW_R(0.0));
    for (k = PLANT_TERMS; k > 0u; --k) {
        const unsigned n = 2u * (k - 1u) + odd;
        const unsigned roundings = n + 1u;
        const zw_real cf = inv_factorial(n);
        acc = zw_eb_mul(acc, w);
        acc = zw_eb_add(acc, zw_eb_make(cf, (zw_real)roundings * (ZW_U * cf + ZW_ETA)));
    }
    acc.e += PLANT_TAIL;
    return acc;
}

/* C[a, b] (odd = 0) and S[a, b] (odd = 1) by the forward sum over h_m. */
static void series_divided(zw_eb a, zw_eb b, zw_eb *cd, zw_eb *sd)
{
    unsigned k;
    zw_eb apow = zw_eb_exact(ZW_R(1.0)); /* a^(k-1) */
    zw_eb hm = zw_eb_exact(ZW_R(1.0));   /* h_{k-1}(a, b) */
    zw_eb sc = zw_eb_exact(ZW_R(0.0)), ss = zw_eb_exact(ZW_R(0.0));
    zw_eb t;
    for (k = 1u; k <= PLANT_TERMS; ++k) {
        if (k > 1u) {
            apow = zw_eb_mul(apow, a);
            hm = zw_eb_mul(hm, b);
            hm = zw_eb_add(hm, apow);
        }
        {
            const unsigned n = 2u * k;
            const unsigned nc = n + 1u;
            const unsigned ns = n + 2u;
            const zw_real fc = inv_factorial(n);
            const zw_real fs = inv_factorial(n + 1u);
            t = zw_eb_mul(hm, zw_eb_make(fc, (zw_real)nc * (ZW_U * fc + ZW_ETA)));
            sc = zw_eb_add(sc, t);
            t = zw_eb_mul(hm, zw_eb_make(fs, (zw_real)ns * (ZW_U * fs + ZW_ETA)));
            ss = zw_eb_add(ss, t);
        }
    }
    sc.e += PLANT_TAIL;
    ss.e += PLANT_TAIL;
    *cd = sc;
    *sd = ss;
}

/* ---- the order-2 plant with stiffness ---------------------------------------------------
 *
 * A = [[0, 1], [-kappa, -delta]], poles p1, p2 = -h +- r, h = delta / 2, r^2 = w2 = h^2 - kappa.
 * With z1, z2 = e^p1, e^p2 (the sampled poles) and b1 z + b0 = N / 2:
 *   D / 2 = z^2 - tr z + det,  tr = 2 e^-h C(w2),  det = e^-delta,
 *   b1 = exp[0, p1, p2] = G / 2 + h H,  b0 = e^-delta exp[0, -p1, -p2] = G / 2 - h H,
 *   G = b1 + b0 = 2 e^-h C[w2, h^2] = P / kappa,  H = (b1 - b0) / delta = e^-h S[w2, h^2],
 *   P = 1 - tr + det = (1 - z1)(1 - z2),  Q = 1 + tr + det = (1 + z1)(1 + z2),
 *   R = 1 - det = -expm1(-delta),  2 - tr = P + R,
 *   D_s = 2 Q s^2 + 4 R s + 2 P,  N_s = 2 (b1 - b0) s + 2 (b1 + b0),
 *   D(1 + w) = 2 w^2 + 2 (P + R) w + 2 P.
 * (kappa = 0: b1 = c1 / 2, b0 = c2 / 2.)  Three regimes, each free of 0/0 and of all but a
 * bounded cancellation:
 *   series    h <= 2 and |w2| <= 4: the series above (critical damping is w2 = 0, inside);
 *   separated real poles, w2 >= h^2 / 2 (h > 2): p2 = -(h + r), p1 = -kappa / (h + r),
 *             P = expm1(p1) expm1(p2), b1 = (E0(p1) - S^) / |p2|,
 *             b0 = (S^ - z2 E0(p1)) / |p2|, S^ = (z1 - z2) / (2 r) (r >= 1.4);
 *   the rest  (kappa >= h^2 / 2 > 2, or complex with |w2| > 4): G = P / kappa,
 *             H = (E0(-delta) - S^) / kappa with S^ = e^-h S(w2), C(w2) from the series,
 *             cosh or cos; P, Q as sums of squares for complex poles:
 *             |1 -+ z1|^2 = expm1(-h)^2 + 4 e^-h sin^2(omega/2) (cos^2 for +). */
typedef struct order2 {
    zw_eb tr, det, P, Q, R, b1, b0, bdiff, bsum;
    zw_eb h, w2;     /* the inputs as used */
    zw_eb ch, sh;    /* e^-h C(w2) = tr / 2 and e^-h S(w2) = exp[p1, p2] = Phi01 */
} order2;

/* Every result of an out-of-line call goes to a named variable of a block that ends where
 * it is no longer needed (or to *o): a call nested in an argument leaves an unnamed
 * temporary that GCC keeps in the frame for the whole function (the stack,
 * tools/footprint.sh).  The same operations on the same operands as the nested form. */
static void order2_compute(zw_eb h, zw_eb kappa, order2 *o)
{
    const zw_eb w2 = eb_square_minus(h, kappa);
    const zw_eb delta = eb_twice(h);
    zw_eb eh, t, u, C, S, G, H;
    t = eb_neg(h);
    eh = eb_exp(t);
    t = eb_neg(delta);
    o->det = eb_exp(t);
    t = eb_expm1(t);
    o->R = eb_neg(t);
    o->h = h;
    o->w2 = w2;

    if (eb_within(h, ZW_R(2.0)) && eb_within(w2, PLANT_SERIES_LIMIT)) {
        zw_eb cd, sd;
        t = zw_eb_mul(h, h);
        series_divided(w2, t, &cd, &sd);
        t = series_single(w2, 0u);
        C = zw_eb_mul(eh, t);
        o->ch = C;
        t = series_single(w2, 1u);
        o->sh = zw_eb_mul(eh, t);
        t = zw_eb_mul(eh, cd);
        G = eb_twice(t);
        H = zw_eb_mul(eh, sd);
        o->tr = eb_twice(C);
        o->P = zw_eb_mul(kappa, G);
        t = zw_eb_exact(ZW_R(1.0));
        t = zw_eb_add(t, o->det);
        o->Q = zw_eb_add(t, o->tr);
        o->bsum = G;
        o->bdiff = zw_eb_mul(delta, H);
        u = zw_eb_mul(h, H);
        t = eb_half(G);
        o->b1 = zw_eb_add(t, u);
        o->b0 = zw_eb_sub(t, u);
        return;
    }
    if (w2.v >= ZW_R(0.5) * (h.v * h.v)) {
        zw_eb r, hr, p1, p2, z1, z2, e01;
        r = eb_sqrt(w2);
        hr = zw_eb_add(h, r);
        p2 = eb_neg(hr);
        t = zw_eb_div(kappa, hr);
        p1 = eb_neg(t);
        z1 = eb_exp(p1);
        z2 = eb_exp(p2);
        e01 = eb_e0(p1);
        t = zw_eb_sub(z1, z2);
        u = eb_twice(r);
        o->sh = zw_eb_div(t, u);
        o->tr = zw_eb_add(z1, z2);
        t = eb_expm1(p1);
        u = eb_expm1(p2);
        o->P = zw_eb_mul(t, u);
        t = zw_eb_exact(ZW_R(1.0));
        u = zw_eb_add(t, z2);
        t = zw_eb_add(t, z1);
        o->Q = zw_eb_mul(t, u);
        t = zw_eb_sub(e01, o->sh);
        o->b1 = zw_eb_div(t, hr);
        t = zw_eb_mul(z2, e01);
        t = zw_eb_sub(o->sh, t);
        o->b0 = zw_eb_div(t, hr);
        t = eb_e0(p2);
        o->bsum = zw_eb_mul(e01, t);
        o->ch = eb_half(o->tr);
        o->bdiff = zw_eb_sub(o->b1, o->b0);
        return;
    }
    if (eb_within(w2, PLANT_SERIES_LIMIT)) {
        t = series_single(w2, 0u);
        C = zw_eb_mul(eh, t);
        t = series_single(w2, 1u);
        S = zw_eb_mul(eh, t);
    } else if (w2.v > ZW_R(0.0)) {
        zw_eb r, hr, z1, z2;
        r = eb_sqrt(w2);
        hr = zw_eb_add(h, r);
        t = zw_eb_div(kappa, hr);
        t = eb_neg(t);
        z1 = eb_exp(t);
        t = eb_neg(hr);
        z2 = eb_exp(t);
        t = zw_eb_add(z1, z2);
        C = eb_half(t);
        t = zw_eb_sub(z1, z2);
        u = eb_twice(r);
        S = zw_eb_div(t, u);
    } else {
        zw_eb om;
        t = eb_neg(w2);
        om = eb_sqrt(t);
        t = eb_cos(om);
        C = zw_eb_mul(eh, t);
        t = eb_sin(om);
        t = zw_eb_mul(eh, t);
        S = zw_eb_div(t, om);
    }
    o->tr = eb_twice(C);
    o->ch = C;
    o->sh = S;
    if ((w2.v < ZW_R(0.0)) && (h.v <= ZW_R(2.0))) {
        /* complex poles far from critical, light damping: the sums of squares */
        zw_eb om, sn, cs, em2, four_eh;
        t = eb_neg(w2);
        om = eb_sqrt(t);
        sn = eb_sin(eb_half(om));
        cs = eb_cos(eb_half(om));
        t = eb_neg(h);
        t = eb_expm1(t);
        em2 = zw_eb_mul(t, t);
        four_eh = eb_twice(eb_twice(eh));
        t = zw_eb_mul(sn, sn);
        t = zw_eb_mul(four_eh, t);
        o->P = zw_eb_add(em2, t);
        t = zw_eb_mul(cs, cs);
        t = zw_eb_mul(four_eh, t);
        o->Q = zw_eb_add(em2, t);
    } else {
        /* h > 2: 1 + det - tr >= (1 - e^-h)^2 > 3/4 for complex poles, and for real ones
         * with w2 < h^2 / 2 tr < e^(-0.29 h) + e^-h: a bounded cancellation */
        t = zw_eb_exact(ZW_R(1.0));
        t = zw_eb_add(t, o->det);
        o->P = zw_eb_sub(t, o->tr);
        o->Q = zw_eb_add(t, o->tr);
    }
    G = zw_eb_div(o->P, kappa);
    t = eb_neg(delta);
    t = eb_e0(t);
    t = zw_eb_sub(t, S);
    H = zw_eb_div(t, kappa);
    o->bsum = G;
    o->bdiff = zw_eb_mul(delta, H);
    u = zw_eb_mul(h, H);
    t = eb_half(G);
    o->b1 = zw_eb_add(t, u);
    o->b0 = zw_eb_sub(t, u);
}

static void plant_from_order2(zw_plant *p, const order2 *o)
{
    set_eb(&p->den[0], &p->den_err[0], zw_eb_exact(ZW_R(2.0)));
    set_eb(&p->den[1], &p->den_err[1], eb_neg(eb_twice(o->tr)));
    set_eb(&p->den[2], &p->den_err[2], eb_twice(o->det));
    set_eb(&p->num[0], &p->num_err[0], eb_twice(o->b1));
    set_eb(&p->num[1], &p->num_err[1], eb_twice(o->b0));
    set_eb(&p->den_s[0], &p->den_s_err[0], eb_twice(o->Q));
    set_eb(&p->den_s[1], &p->den_s_err[1], eb_twice(eb_twice(o->R)));
    set_eb(&p->den_s[2], &p->den_s_err[2], eb_twice(o->P));
    set_eb(&p->num_s[0], &p->num_s_err[0], eb_twice(o->bdiff));
    set_eb(&p->num_s[1], &p->num_s_err[1], eb_twice(o->bsum));
    set_eb(&p->den_w[0], &p->den_w_err[0], zw_eb_exact(ZW_R(2.0)));
    {
        const zw_eb pr = zw_eb_add(o->P, o->R);
        set_eb(&p->den_w[1], &p->den_w_err[1], eb_twice(pr));
    }
    set_eb(&p->den_w[2], &p->den_w_err[2], eb_twice(o->P));
}

/* ---- the actuator lag: order 3 ----------------------------------------------------------
 *
 * The lag's state y (y' = nu (F - y), nu = 1 / lambda) appended to the plant's makes Phi3
 * block triangular, and with a = e^-nu (the lag's sampled pole, p3 = -nu)
 *   D3 = D2 (z - a),   N3 / 2 = (z - a) X(z) + (1 - a) Y(z),
 *   X, Y = C adj(zI - Phi2) Gx, Gy  (= x1 z + x0, y1 z + y0),
 * Gy = the plant's state at t = 1 driven by e^(-nu t):  (T, U) = (exp[p1, p2, p3],
 * (x e^x)[p1, p2, p3]),  Gx = Gamma2 - Gy = its state driven by 1 - e^(-nu t):
 * (b1 - T, nu T).  So y1 = T, y0 = Phi01 U - Phi11 T, x1 = b1 - T, x0 = b0 - y0.
 * T by whichever of three forms has the smallest bound (all rigorous):
 *   series   e^-h (C[w2, h'^2] + h' S[w2, h'^2]), h' = h - nu (|w2|, h'^2 <= 4);
 *   far pair (exp[p3, p1] - exp[p3, p2]) / (p1 - p2) for real poles with r >= 1;
 *   direct   (a - L(p3)) / kappa', L(x) = C^ + (x + h) S^ the line through (p_i, e^p_i),
 *            kappa' = (nu + p1)(nu + p2) = h'^2 - w2.
 * The lag meeting a pole (kappa' = 0) is then no 0/0 (the direct form's bound is infinite
 * there and another is taken); lambda -> 0 gives a -> 0, T, U ~ 1 / nu (N3 -> z N2);
 * lambda >> 1 keeps D3's factor 1 - a = -expm1(-nu) and N3(1) = 2 (1 - a) G exactly. */

static zw_eb eb_better(zw_eb a, zw_eb b)
{
    return (b.e < a.e) ? b : a;
}

/* exp[x, y] = e^max(x, y) E0(-|x - y|) */
static zw_eb eb_exp_dd(zw_eb x, zw_eb y)
{
    const bool x_above = x.v >= y.v;
    const zw_eb hi = x_above ? x : y;
    const zw_eb lo = x_above ? y : x;
    return zw_eb_mul(eb_exp(hi), eb_e0(zw_eb_sub(lo, hi)));
}

/* sum_k H_k / (k + 3)! for |h|, |h'| <= 2, |w2| <= 4 (|H_k| <= (k + 1)^2 2^k: with
 * PLANT_TERMS4 terms the tail is below 1e-42). */
#define PLANT_TERMS4 44u

static zw_eb series_shifted4(zw_eb h, zw_eb hp, zw_eb w2)
{
    unsigned k;
    zw_eb hpow = zw_eb_exact(ZW_R(1.0));                  /* h^k */
    zw_eb A = zw_eb_exact(ZW_R(1.0));                     /* A_k */
    zw_eb H2 = zw_eb_exact(ZW_R(0.0)), H1 = zw_eb_exact(ZW_R(0.0)); /* H_{k-2}, H_{k-1} */
    zw_eb sum = zw_eb_exact(ZW_R(0.0));
    zw_real f = ZW_R(1.0) / ZW_R(6.0);                    /* 1 / (k + 3)!, rounded */
    for (k = 0u; k < PLANT_TERMS4; ++k) {
        zw_eb H, t;
        const unsigned kf = k + 3u;      /* (k + 3)! = (k + 2)! kf */
        const unsigned roundings = k + 4u;
        if (k > 0u) {
            hpow = zw_eb_mul(hpow, h);
            A = zw_eb_mul(hp, A);
            A = zw_eb_add(A, hpow);
            f = f / (zw_real)kf;
        }
        t = zw_eb_mul(w2, H2);
        H = zw_eb_add(A, t);
        t = zw_eb_mul(H, zw_eb_make(f, (zw_real)roundings * (ZW_U * f + ZW_ETA)));
        sum = zw_eb_add(sum, t);
        H2 = H1;
        H1 = H;
    }
    sum.e += PLANT_TAIL;
    return sum;
}

/* The order-3 plant's intermediate values (order3_build), kept in one place so that each
 * step's own temporaries end with it (see order2_compute). */
typedef struct order3 {
    zw_eb h, kappa, nu, w2; /* the inputs (w2 = order2's) */
    zw_eb hp, kp, a, oma, opa, phi11;
    zw_eb T, y0, x1, x0;
    zw_eb y0_series, T_far, x1_far;
    bool series_ok;
} order3;

/* hp, kp, a, 1 -+ a, Phi11; T from the direct form, the series and the far pair
 * (order3_far, before); the series' y0 (an infinite bound when not computed). */
static void order3_poles(const order2 *o, order3 *q)
{
    zw_eb t, u, hp2;
    q->hp = zw_eb_sub(q->h, q->nu);
    hp2 = zw_eb_mul(q->hp, q->hp);
    q->kp = zw_eb_sub(hp2, q->w2);
    u = eb_neg(q->nu);
    q->a = eb_exp(u);
    t = eb_expm1(u);
    q->oma = eb_neg(t);
    t = zw_eb_exact(ZW_R(1.0));
    q->opa = zw_eb_add(t, q->a);
    t = zw_eb_mul(q->h, o->sh);
    q->phi11 = zw_eb_sub(o->ch, t);
    q->series_ok = eb_within(q->w2, PLANT_SERIES_LIMIT) && eb_within(hp2, PLANT_SERIES_LIMIT);
    q->y0_series = zw_eb_make(ZW_R(0.0), ZW_INF); /* never taken unless computed */

    t = zw_eb_sub(q->a, o->ch);
    u = zw_eb_mul(q->hp, o->sh);
    t = zw_eb_sub(t, u);
    q->T = zw_eb_div(t, q->kp);
    if (q->series_ok) {
        zw_eb cd, sd, eh;
        t = eb_neg(q->h);
        eh = eb_exp(t);
        series_divided(q->w2, hp2, &cd, &sd);
        u = zw_eb_mul(q->hp, sd);
        t = zw_eb_add(cd, u);
        t = zw_eb_mul(eh, t);
        q->T = eb_better(q->T, t);
        /* y0 = det a exp[-p1, -p2, -p3]: the same series with h' -> -h' */
        t = zw_eb_mul(q->a, eh);
        u = zw_eb_sub(cd, u);
        q->y0_series = zw_eb_mul(t, u);
    }
    q->T = eb_better(q->T, q->T_far);
}

/* The far pair (w2 >= 1): T as a difference of divided differences, and
 * x1 / nu = exp[0, p3, p1, p2] = (exp[0, p3, p1] - exp[0, p3, p2]) / (p1 - p2), each the b1
 * of the real pole pair {p3, p_i} (no cancellation for nu -> 0).  Only h, w2 of the plant's
 * order2: done before that is computed, so that the two are not on the stack at once. */
static void order3_far(order3 *q)
{
    zw_eb r2, hr, p1, p2, p3, t, u, b1_first;
    order2 pair;
    t = eb_sqrt(q->w2);
    hr = zw_eb_add(q->h, t);
    r2 = eb_twice(t);
    t = zw_eb_div(q->kappa, hr);
    p1 = eb_neg(t);
    p2 = eb_neg(hr);
    p3 = eb_neg(q->nu);
    t = eb_exp_dd(p3, p1);
    u = eb_exp_dd(p3, p2);
    t = zw_eb_sub(t, u);
    q->T_far = zw_eb_div(t, r2);
    t = zw_eb_sub(q->nu, p1);
    t = eb_half(t);
    u = eb_neg(p1);
    u = zw_eb_mul(q->nu, u);
    order2_compute(t, u, &pair);
    b1_first = pair.b1;
    t = zw_eb_sub(q->nu, p2);
    t = eb_half(t);
    u = eb_neg(p2);
    u = zw_eb_mul(q->nu, u);
    order2_compute(t, u, &pair);
    t = zw_eb_sub(b1_first, pair.b1);
    t = zw_eb_div(t, r2);
    q->x1_far = zw_eb_mul(q->nu, t);
}

/* U, y0, x1, x0 from T, each by the form with the smallest bound. */
static void order3_numerators(const order2 *o, order3 *q)
{
    zw_eb t, u, U;
    /* U = S^ - nu T, or (nu Phi11 + kappa S^ - nu a) / kappa' (no cancellation for nu >> 1) */
    t = zw_eb_mul(q->nu, q->T);
    U = zw_eb_sub(o->sh, t);
    t = zw_eb_mul(q->nu, q->phi11);
    u = zw_eb_mul(q->kappa, o->sh);
    t = zw_eb_add(t, u);
    u = zw_eb_mul(q->nu, q->a);
    t = zw_eb_sub(t, u);
    t = zw_eb_div(t, q->kp);
    U = eb_better(U, t);
    t = zw_eb_mul(o->sh, U);
    u = zw_eb_mul(q->phi11, q->T);
    q->y0 = zw_eb_sub(t, u);
    q->y0 = eb_better(q->y0, q->y0_series);
    /* x1 = nu exp[0, p1, p2, p3] = b1 - T (cancels for nu -> 0), or
     * nu (E0(-nu) - S^ + (nu - 2 h) b1) / kappa' (no cancellation for large kappa), or for
     * a small plant nu e^-h sum_k H_k / (k + 3)!, H the complete symmetric polynomials of the
     * nodes shifted by h: (h, r, -r, h'), H_k = A_k + w2 H_{k-2}, A_k = h' A_{k-1} + h^k */
    q->x1 = zw_eb_sub(o->b1, q->T);
    t = eb_neg(q->nu);
    t = eb_e0(t);
    t = zw_eb_sub(t, o->sh);
    u = eb_twice(q->h);
    u = zw_eb_sub(q->nu, u);
    u = zw_eb_mul(u, o->b1);
    t = zw_eb_add(t, u);
    t = zw_eb_mul(q->nu, t);
    t = zw_eb_div(t, q->kp);
    q->x1 = eb_better(q->x1, t);
    q->x1 = eb_better(q->x1, q->x1_far);
    if (q->series_ok && eb_within(q->h, ZW_R(2.0))) {
        t = eb_neg(q->h);
        t = eb_exp(t);
        t = zw_eb_mul(q->nu, t);
        u = series_shifted4(q->h, q->hp, o->w2);
        t = zw_eb_mul(t, u);
        q->x1 = eb_better(q->x1, t);
    }
    /* x0 = b0 - y0, or nu Phi01 T - Phi11 x1 (small for nu -> 0 without cancelling) */
    q->x0 = zw_eb_sub(o->b0, q->y0);
    t = zw_eb_mul(q->nu, o->sh);
    t = zw_eb_mul(t, q->T);
    u = zw_eb_mul(q->phi11, q->x1);
    t = zw_eb_sub(t, u);
    q->x0 = eb_better(q->x0, t);
}

/* The order-3 polynomials from X, Y and a. */
static void order3_polys(const order2 *o, const order3 *q, zw_plant *p)
{
    zw_eb t, u, xd;
    p->order = 3u;
    /* N3 / 2 = x1 z^2 + (x0 - a x1 + (1 - a) y1) z + ((1 - a) y0 - a x0) */
    set_eb(&p->num[0], &p->num_err[0], eb_twice(q->x1));
    t = zw_eb_mul(q->a, q->x1);
    t = zw_eb_sub(q->x0, t);
    u = zw_eb_mul(q->oma, q->T);
    t = zw_eb_add(t, u);
    set_eb(&p->num[1], &p->num_err[1], eb_twice(t));
    t = zw_eb_mul(q->oma, q->y0);
    u = zw_eb_mul(q->a, q->x0);
    t = zw_eb_sub(t, u);
    set_eb(&p->num[2], &p->num_err[2], eb_twice(t));
    /* N3_s / 2 = ((1 + a) s + (1 - a)) X_s + (1 - a)(1 - s) Y_s */
    xd = zw_eb_sub(q->x1, q->x0);
    t = zw_eb_mul(q->opa, xd);
    u = zw_eb_sub(q->T, q->y0);
    u = zw_eb_mul(q->oma, u);
    t = zw_eb_sub(t, u);
    set_eb(&p->num_s[0], &p->num_s_err[0], eb_twice(t));
    t = zw_eb_add(q->x1, q->x0);
    t = zw_eb_mul(q->opa, t);
    u = zw_eb_mul(q->oma, xd);
    t = zw_eb_add(t, u);
    u = zw_eb_mul(q->oma, q->y0);
    u = eb_twice(u);
    t = zw_eb_sub(t, u);
    set_eb(&p->num_s[1], &p->num_s_err[1], eb_twice(t));
    t = zw_eb_mul(q->oma, o->bsum);
    set_eb(&p->num_s[2], &p->num_s_err[2], eb_twice(t));
    /* D3 = D2 (z - a): in s, times (1 + a) s + (1 - a); in w = z - 1, times w + (1 - a) */
    t = zw_eb_exact(ZW_R(1.0));
    u = eb_neg(q->a);
    zw_eb_poly_mul_linear(p->den, p->den_err, 2u, t, u);
    zw_eb_poly_mul_linear(p->den_s, p->den_s_err, 2u, q->opa, q->oma);
    zw_eb_poly_mul_linear(p->den_w, p->den_w_err, 2u, t, q->oma);
}

/* The order-2 plant and, with the lag (lag true), its order-3 extension, in steps, each with
 * its own temporaries: the far pair's two order-2 plants first, then the plant's own. */
static void plant_build(zw_eb h, zw_eb kappa, bool lag, zw_eb nu, zw_plant *p)
{
    order3 q;
    order2 o;
    q.h = h;
    q.kappa = kappa;
    q.nu = nu;
    q.w2 = eb_square_minus(h, kappa); /* = order2_compute's */
    /* every other field unbounded until its step computes it (the far pair's stay so when
     * it is not run: never taken) */
    q.T_far = zw_eb_make(ZW_R(0.0), ZW_INF);
    q.x1_far = q.T_far;
    q.hp = q.T_far;
    q.kp = q.T_far;
    q.a = q.T_far;
    q.oma = q.T_far;
    q.opa = q.T_far;
    q.phi11 = q.T_far;
    q.T = q.T_far;
    q.y0 = q.T_far;
    q.x1 = q.T_far;
    q.x0 = q.T_far;
    q.y0_series = q.T_far;
    q.series_ok = false;
    if (lag && (q.w2.v >= ZW_R(1.0))) {
        order3_far(&q);
    }
    order2_compute(h, kappa, &o);
    p->order = 2u;
    plant_from_order2(p, &o);
    if (lag) {
        order3_poles(&o, &q);
        order3_numerators(&o, &q);
        order3_polys(&o, &q, p);
    }
}

/* ---- the general plant ---------------------------------------------------------------- */

static zw_status check_plant_spec(const zw_plant_spec *spec)
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

/* Built in place in *out (no second zw_plant on the stack), fail-safe at every return;
 * *spec is copied first, since it may be out->spec. */
zw_status zw_plant_init(zw_plant *out, const zw_plant_spec *spec)
{
    zw_status st;
    zw_plant_spec sp;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if (spec == NULL) {
        zw_plant_fail(out);
        return ZW_ERR_NULL;
    }
    sp = *spec;
    st = check_plant_spec(&sp);
    zw_plant_fail(out); /* every unused entry NaN */
    if (st != ZW_OK) {
        return st;
    }
    st = zw_coeffs_init(&out->c, sp.delta);
    if (st != ZW_OK) {
        zw_plant_fail(out);
        return st;
    }
    out->c.delta_relerr = sp.delta_relerr;
    if ((sp.kappa == ZW_R(0.0)) && (sp.lambda == ZW_R(0.0))) {
        return zw_plant_from_coeffs(out, &out->c);
    }
    {
        const zw_eb h = zw_eb_make(ZW_R(0.5) * sp.delta,
                                ZW_R(0.5) * sp.delta * sp.delta_relerr + ZW_ETA);
        const zw_eb kappa = zw_eb_make(sp.kappa, sp.kappa * sp.kappa_relerr);
        const bool lag = (sp.lambda > ZW_R(0.0));
        /* nu = 1 / lambda: one rounding, and 1 / (lambda (1 +- rho)) within
         * nu rho / (1 - rho) <= nu rho (16 / 15) of nu (lambda = 0: unused) */
        const zw_real nu = lag ? (ZW_R(1.0) / sp.lambda) : ZW_R(0.0);
        const zw_eb nub = zw_eb_make(nu, nu * (sp.lambda_relerr * ZW_R(1.0667) + ZW_U) + ZW_ETA);
        if (!ZW_IS_FINITE(nu)) {
            zw_plant_fail(out);
            return ZW_ERR_RANGE;
        }
        plant_build(h, kappa, lag, nub, out);
    }
    out->spec = sp;
    if (!plant_finite(out)) {
        zw_plant_fail(out);
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

static void fail_spec(zw_plant_spec *spec, zw_real *mass)
{
    if (spec != NULL) {
        spec->delta = ZW_NAN;
        spec->kappa = ZW_NAN;
        spec->lambda = ZW_NAN;
        spec->delta_relerr = ZW_NAN;
        spec->kappa_relerr = ZW_NAN;
        spec->lambda_relerr = ZW_NAN;
    }
    zw_fail_real(mass, ZW_NAN);
}

/* A product or quotient of positive numbers that came out subnormal (or 0) has lost its
 * relative accuracy: the relerr below would not hold. */
static bool lost(zw_real result, zw_real operand)
{
    return (operand > ZW_R(0.0)) && !(result >= ZW_REAL_MIN);
}

/* Roundings: M = m + m_h, Bp = b + b_h, Kp = k_p + k_h (one each, sums of non-negative
 * terms); delta = (Bp T) / M: 1 + 2 + 1 (M's); kappa = ((Kp T) T) / M: 1 + 3 + 1;
 * lambda = tau / T: 1.  One u of slack each. */
#define PLANT_DELTA_RELERR (ZW_R(5.0) * ZW_U)
#define PLANT_KAPPA_RELERR (ZW_R(6.0) * ZW_U)
#define PLANT_LAMBDA_RELERR (ZW_R(2.0) * ZW_U)

zw_status zw_plant_spec_from_device(zw_real m, zw_real b, zw_real T, zw_real k_p, zw_real tau,
                                    zw_real m_h, zw_real b_h, zw_real k_h, zw_plant_spec *spec,
                                    zw_real *mass)
{
    const zw_real in[8] = {m, b, T, k_p, tau, m_h, b_h, k_h};
    zw_real M, Bp, Kp, bt, kt, ktt, delta, kappa, lambda;
    unsigned i;
    zw_status st = ZW_OK;
    if ((spec == NULL) || (mass == NULL)) {
        fail_spec(spec, mass);
        return ZW_ERR_NULL;
    }
    for (i = 0u; (i < 8u) && (st == ZW_OK); ++i) {
        st = zw_require_finite(in[i]);
    }
    if (st == ZW_OK) {
        if (!(m > ZW_R(0.0))) {
            st = ZW_ERR_MASS;
        } else if (!(T > ZW_R(0.0))) {
            st = ZW_ERR_PERIOD;
        } else if ((b < ZW_R(0.0)) || (b_h < ZW_R(0.0))) {
            st = ZW_ERR_DAMPING;
        } else if ((k_p < ZW_R(0.0)) || (k_h < ZW_R(0.0)) || (tau < ZW_R(0.0)) ||
                   (m_h < ZW_R(0.0))) {
            st = ZW_ERR_ARG;
        } else {
            /* valid */
        }
    }
    if (st != ZW_OK) {
        fail_spec(spec, mass);
        return st;
    }
    M = m + m_h;
    Bp = b + b_h;
    Kp = k_p + k_h;
    bt = Bp * T;
    kt = Kp * T;
    ktt = kt * T;
    delta = bt / M;
    kappa = ktt / M;
    lambda = tau / T;
    if (!ZW_IS_FINITE(M) || !ZW_IS_FINITE(Bp) || !ZW_IS_FINITE(Kp) || !ZW_IS_FINITE(delta) ||
        !ZW_IS_FINITE(kappa) || !ZW_IS_FINITE(lambda) || lost(bt, Bp) || lost(delta, Bp) || lost(kt, Kp) ||
        lost(ktt, Kp) || lost(kappa, Kp) ||
        lost(lambda, tau)) {
        fail_spec(spec, mass);
        return ZW_ERR_RANGE;
    }
    spec->delta = delta;
    spec->kappa = kappa;
    spec->lambda = lambda;
    spec->delta_relerr = PLANT_DELTA_RELERR;
    spec->kappa_relerr = PLANT_KAPPA_RELERR;
    spec->lambda_relerr = PLANT_LAMBDA_RELERR;
    *mass = M;
    return ZW_OK;
}
