/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The ideal plant enclosed over a delta interval (plant_box.h; proofs in docs/box.md). */
#include "zwidth/plant_box.h"

#include <stddef.h>
#include <string.h>

#include "box_interval.h"

/* d12 peaks at delta* = 2.68799934549949... with 0.27870311291437160... (the root of
 * 4 - delta = (delta^2 + 3 delta + 4) e^-delta; tests/py/test_box_loop_reference.py and
 * test_box_reference.py check the bracket's signs and the peak at 40+ digits); the bracket
 * and the peak are rounded outward (as box.c). */
#define PB_D12_PEAK_LO ZW_R(2.6875)
#define PB_D12_PEAK_HI ZW_R(2.6885)
#define PB_D12_MAX_UP ZW_R(0.2787032)
/* relative error bound of a coefficient field (ZW_COEF_ULPS ulps, an ulp <= 2u), plus u */
#define PB_COEF_REL ((ZW_R(2.0) * (zw_real)ZW_COEF_ULPS + ZW_R(1.0)) * ZW_U)

static zw_real pb_coef_down(zw_real v)
{
    return bx_down(v - (PB_COEF_REL * ZW_FABS(v) + ZW_COEF_ABSERR));
}

static zw_real pb_coef_up(zw_real v)
{
    return bx_up(v + (PB_COEF_REL * ZW_FABS(v) + ZW_COEF_ABSERR));
}

/* mid +- rad covering [iv.lo, iv.hi] */
static void pb_store(bx_iv iv, zw_real *v, zw_real *err)
{
    zw_real mid = ZW_R(0.5) * iv.lo + ZW_R(0.5) * iv.hi;
    *v = mid;
    *err = bx_up(bx_max(iv.hi - mid, mid - iv.lo));
}


static zw_status pb_validate(zw_real delta_lo, zw_real delta_hi)
{
    if (ZW_IS_NAN(delta_lo) || ZW_IS_NAN(delta_hi)) {
        return ZW_ERR_NAN;
    }
    if (!ZW_IS_FINITE(delta_lo) || !ZW_IS_FINITE(delta_hi)) {
        return ZW_ERR_INF;
    }
    if (delta_lo < ZW_R(0.0)) {
        return ZW_ERR_DELTA;
    }
    if (delta_lo > delta_hi) {
        return ZW_ERR_BOX;
    }
    return ZW_OK;
}

static bool pb_finite(const zw_real v[], const zw_real e[], unsigned n)
{
    unsigned i;
    for (i = 0u; i < n; ++i) {
        if (!ZW_IS_FINITE(v[i]) || !ZW_IS_FINITE(e[i])) {
            return false;
        }
    }
    return true;
}

static bool pb_all_finite(const zw_plant *p)
{
    return pb_finite(p->den, p->den_err, 3u) && pb_finite(p->den_s, p->den_s_err, 3u) &&
           pb_finite(p->den_w, p->den_w_err, 3u) && pb_finite(p->num, p->num_err, 2u) &&
           pb_finite(p->num_s, p->num_s_err, 2u);
}

/* The ranges over [delta_lo, delta_hi] from the coefficients at one end at a time (one
 * zw_coeffs on the stack: the footprint target). */
typedef struct pb_ranges {
    bx_iv e, one_plus_e, one_minus_e, c1, c2, s, d12;
} pb_ranges;

static zw_status pb_ranges_init(pb_ranges *r, zw_real delta_lo, zw_real delta_hi)
{
    zw_coeffs at;
    zw_real d12_lo_end;
    zw_status st = zw_coeffs_init(&at, delta_hi);
    if (st != ZW_OK) {
        return st;
    }
    /* the high end: lower bounds of the falling fields, the upper of 1 - e */
    r->e.lo = bx_max(pb_coef_down(at.e), ZW_R(0.0));
    r->c1.lo = bx_max(pb_coef_down(at.c1), ZW_R(0.0));
    r->c2.lo = bx_max(pb_coef_down(at.c2), ZW_R(0.0));
    r->s.lo = bx_max(pb_coef_down(at.s), ZW_R(0.0));
    r->one_minus_e.hi = bx_min(bx_up(ZW_R(0.5) * bx_up(delta_hi * pb_coef_up(at.s))), ZW_R(1.0));
    r->d12 = bx_make(pb_coef_down(at.d12), pb_coef_up(at.d12));
    st = zw_coeffs_init(&at, delta_lo);
    if (st != ZW_OK) {
        return st;
    }
    r->e.hi = bx_min(pb_coef_up(at.e), ZW_R(1.0));
    r->c1.hi = pb_coef_up(at.c1);
    r->c2.hi = pb_coef_up(at.c2);
    r->s.hi = pb_coef_up(at.s);
    /* 1 - e = delta s / 2 rises with delta: from the ends without cancellation */
    r->one_minus_e.lo = bx_max(bx_down(ZW_R(0.5) * bx_down(delta_lo * pb_coef_down(at.s))), ZW_R(0.0));
    r->one_plus_e = bx_make(bx_down(ZW_R(1.0) + r->e.lo), bx_up(ZW_R(1.0) + r->e.hi));
    /* d12: rising below the peak (range [low end, high end]), falling above it, else the
     * least end up to the peak value */
    d12_lo_end = pb_coef_down(at.d12);
    if (delta_hi <= PB_D12_PEAK_LO) {
        r->d12.lo = d12_lo_end;
    } else if (delta_lo >= PB_D12_PEAK_HI) {
        r->d12.hi = pb_coef_up(at.d12);
    } else {
        r->d12 = bx_make(bx_min(d12_lo_end, r->d12.lo), PB_D12_MAX_UP);
    }
    r->d12.lo = bx_max(r->d12.lo, ZW_R(0.0));
    return ZW_OK;
}

/* An order-2 plant with every coefficient and bound 0 (the enclosures fill theirs in). */
static void pb_order2_zero(zw_plant *out)
{
    unsigned i;
    out->order = 2u;
    for (i = 0u; i <= ZW_PLANT_MAX_ORDER; ++i) {
        out->den[i] = ZW_R(0.0);
        out->den_err[i] = ZW_R(0.0);
        out->den_s[i] = ZW_R(0.0);
        out->den_s_err[i] = ZW_R(0.0);
        out->den_w[i] = ZW_R(0.0);
        out->den_w_err[i] = ZW_R(0.0);
    }
    for (i = 0u; i < ZW_PLANT_MAX_ORDER; ++i) {
        out->num[i] = ZW_R(0.0);
        out->num_err[i] = ZW_R(0.0);
        out->num_s[i] = ZW_R(0.0);
        out->num_s_err[i] = ZW_R(0.0);
    }
}

static zw_status pb_enclose(zw_plant *out, zw_real delta_lo, zw_real delta_hi)
{
    pb_ranges r;
    zw_real mid;
    zw_status st = pb_validate(delta_lo, delta_hi);
    /* pb_ranges_init fills every field when it succeeds; cleared first all the same, for
     * compilers that cannot see it (avr-gcc 5.4's -Wmaybe-uninitialized) */
    (void)memset(&r, 0, sizeof r);
    if (st != ZW_OK) {
        return st;
    }
    st = pb_ranges_init(&r, delta_lo, delta_hi);
    if (st != ZW_OK) {
        return st;
    }
    pb_order2_zero(out);
    /* D = 2 z^2 - 2 (1 + e) z + 2 e;  N = c1 z + c2 (doubling and negation are exact) */
    out->den[0] = ZW_R(2.0);
    pb_store(bx_make(-ZW_R(2.0) * r.one_plus_e.hi, -ZW_R(2.0) * r.one_plus_e.lo), &out->den[1],
             &out->den_err[1]);
    pb_store(bx_make(ZW_R(2.0) * r.e.lo, ZW_R(2.0) * r.e.hi), &out->den[2], &out->den_err[2]);
    pb_store(r.c1, &out->num[0], &out->num_err[0]);
    pb_store(r.c2, &out->num[1], &out->num_err[1]);
    /* den_s = 4 (1 + e) s^2 + 4 (1 - e) s;  num_s = d12 s + (c1 + c2) (x4 exact) */
    pb_store(bx_make(ZW_R(4.0) * r.one_plus_e.lo, ZW_R(4.0) * r.one_plus_e.hi), &out->den_s[0],
             &out->den_s_err[0]);
    pb_store(bx_make(ZW_R(4.0) * r.one_minus_e.lo, ZW_R(4.0) * r.one_minus_e.hi), &out->den_s[1],
             &out->den_s_err[1]);
    pb_store(r.d12, &out->num_s[0], &out->num_s_err[0]);
    pb_store(r.s, &out->num_s[1], &out->num_s_err[1]);
    /* D in w = z - 1: 2 w^2 + 2 (1 - e) w */
    out->den_w[0] = ZW_R(2.0);
    pb_store(bx_make(ZW_R(2.0) * r.one_minus_e.lo, ZW_R(2.0) * r.one_minus_e.hi), &out->den_w[1],
             &out->den_w_err[1]);

    /* the midpoint, informational */
    mid = ZW_R(0.5) * delta_lo + ZW_R(0.5) * delta_hi;
    st = zw_coeffs_init(&out->c, mid);
    if (st != ZW_OK) {
        return st;
    }
    out->c.delta_relerr = (mid > ZW_R(0.0)) ? bx_up((delta_hi - delta_lo) / (mid + mid)) : ZW_R(0.0);
    out->spec.delta = mid;
    out->spec.kappa = ZW_R(0.0);
    out->spec.lambda = ZW_R(0.0);
    out->spec.delta_relerr = out->c.delta_relerr;
    out->spec.kappa_relerr = ZW_R(0.0);
    out->spec.lambda_relerr = ZW_R(0.0);
    if (!pb_all_finite(out)) {
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

/* ---- with stiffness: midpoint-radius evaluation of plant.c's series regime ------------
 *
 * zw_eb (internal.h) is a midpoint-radius arithmetic: add, sub, mul (with the a.e b.e term)
 * and div (radius of the divisor below its modulus) each enclose the exact result for every
 * pair of points of the operands' balls, with their own rounding.  The functions below
 * extend it to exp and expm1 (bounds over the whole ball, libm within 1 ulp as coeffs.c
 * assumes) and to the series of the entire functions (plant.c), whose truncation is bounded
 * for every point with |w| <= PB_SERIES_LIMIT. */

/* The ball covering [lo, hi] (rounded outward). */
static zw_eb pb_ball(zw_real lo, zw_real hi)
{
    bx_iv iv = bx_make(lo, hi);
    zw_eb r;
    pb_store(iv, &r.v, &r.e);
    return r;
}

/* e^(a.v + a.e) rounded up: the largest derivative of exp and expm1 over the ball. */
static zw_real pb_exp_top(zw_eb a)
{
    return ZW_EXP(a.v + a.e) * (ZW_R(1.0) + ZW_R(4.0) * ZW_U) + ZW_ETA;
}

static zw_eb pb_exp(zw_eb a)
{
    const zw_real v = ZW_EXP(a.v);
    return zw_eb_make(v, pb_exp_top(a) * a.e + ZW_R(2.0) * ZW_U * v + ZW_ETA);
}

/* expm1: 2 ulps (4u), the portable fallback's documented bound (portable_math.h). */
static zw_eb pb_expm1(zw_eb a)
{
    const zw_real v = ZW_EXPM1(a.v);
    return zw_eb_make(v, pb_exp_top(a) * a.e + ZW_R(4.0) * ZW_U * ZW_FABS(v) + ZW_ETA);
}

static zw_eb pb_neg(zw_eb a)
{
    return zw_eb_make(-a.v, a.e);
}

static zw_eb pb_twice(zw_eb a)
{
    return zw_eb_make(ZW_R(2.0) * a.v, ZW_R(2.0) * a.e);
}

static zw_eb pb_half(zw_eb a)
{
    return zw_eb_make(ZW_R(0.5) * a.v, ZW_R(0.5) * a.e + ZW_ETA);
}

/* Truncation after PB_TERMS terms, for |w|, |a|, |b| <= PB_SERIES_LIMIT = 4 (1 + 1/64)
 * (the balls' outward rounding may pass 4 by a few ulps): successive terms shrink by a
 * factor below 1/2, so the single series' tail is below 2 (4.0625^21 / 42!) < 1e-38 and the
 * divided ones' below 2 (22 4.0625^21 / 44!) < 2e-40 (|h_m(a, b)| <= (m + 1) 4.0625^m);
 * PB_TAIL covers both. */
#define PB_TERMS 21u
#define PB_TAIL ZW_R(2e-38)
#define PB_SERIES_LIMIT ZW_R(4.0625)

static bool pb_within(zw_eb a, zw_real limit)
{
    return (ZW_FABS(a.v) + a.e) <= limit;
}

/* 1 / n! (n roundings: within n (u / n! + eta)). */
static zw_real pb_inv_factorial(unsigned n)
{
    unsigned i;
    zw_real f = ZW_R(1.0);
    for (i = 2u; i <= n; ++i) {
        f = f / (zw_real)i;
    }
    return f;
}

static zw_eb pb_inv_factorial_eb(unsigned n)
{
    const zw_real f = pb_inv_factorial(n);
    const zw_real roundings = (zw_real)n + ZW_R(1.0);
    return zw_eb_make(f, roundings * (ZW_U * f + ZW_ETA));
}

/* C(w) = sum w^k / (2k)! (odd = 0), S(w) = sum w^k / (2k + 1)! (odd = 1), by Horner. */
static zw_eb pb_series(zw_eb w, unsigned odd)
{
    unsigned k;
    zw_eb acc = zw_eb_exact(ZW_R(0.0));
    for (k = PB_TERMS; k > 0u; --k) {
        acc = zw_eb_add(zw_eb_mul(acc, w), pb_inv_factorial_eb(2u * (k - 1u) + odd));
    }
    acc.e += PB_TAIL;
    return acc;
}

/* The divided differences C[a, b] = sum_{k>=1} h_{k-1}(a, b) / (2k)! and
 * S[a, b] = sum_{k>=1} h_{k-1}(a, b) / (2k + 1)!, h_m(a, b) = sum_j a^j b^(m - j). */
static void pb_series_divided(zw_eb a, zw_eb b, zw_eb *cd, zw_eb *sd)
{
    unsigned k;
    zw_eb apow = zw_eb_exact(ZW_R(1.0));
    zw_eb hm = zw_eb_exact(ZW_R(1.0));
    zw_eb sc = zw_eb_exact(ZW_R(0.0)), ss = zw_eb_exact(ZW_R(0.0));
    for (k = 1u; k <= PB_TERMS; ++k) {
        if (k > 1u) {
            apow = zw_eb_mul(apow, a);
            hm = zw_eb_add(zw_eb_mul(hm, b), apow);
        }
        sc = zw_eb_add(sc, zw_eb_mul(hm, pb_inv_factorial_eb(2u * k)));
        ss = zw_eb_add(ss, zw_eb_mul(hm, pb_inv_factorial_eb(2u * k + 1u)));
    }
    sc.e += PB_TAIL;
    ss.e += PB_TAIL;
    *cd = sc;
    *sd = ss;
}

static void pb_set(zw_real *v, zw_real *e, zw_eb x)
{
    *v = x.v;
    *e = bx_up(x.e);
}

/* plant.c's series regime (its comment has the formulas):
 *   tr = 2 e^-h C(w2), det = e^-delta, R = -expm1(-delta), G = 2 e^-h C[w2, h^2],
 *   H = e^-h S[w2, h^2], P = kappa G, Q = 1 + det + tr, b1, b0 = G / 2 +- h H,
 *   D = 2 z^2 - 2 tr z + 2 det, N = 2 b1 z + 2 b0, D_s = 2 Q s^2 + 4 R s + 2 P,
 *   N_s = 2 delta H s + 2 G, D(1 + w) = 2 w^2 + 2 (P + R) w + 2 P.
 * P >= 0 (kappa >= 0 and G > 0: C' > 0 on w >= -pi^2, so C[w2, h^2] > 0), so its ball's
 * part below 0 is dropped. */
static zw_status pb_enclose2(zw_plant *out, zw_real delta_lo, zw_real delta_hi, zw_real kappa_lo,
                             zw_real kappa_hi)
{
    const zw_eb one = zw_eb_exact(ZW_R(1.0));
    const zw_real h_lo = ZW_R(0.5) * delta_lo, h_hi = ZW_R(0.5) * delta_hi; /* exact or tiny */
    zw_eb h, kappa, h2, w2, delta, eh, det, R, C, cd, sd, G, H, P, Q, b1, b0;
    zw_real mid;
    bx_iv p_iv;
    zw_status st;
    if (!(delta_hi <= ZW_PLANT_ENCLOSE_MAX) || !(kappa_hi <= ZW_PLANT_ENCLOSE_MAX)) {
        return ZW_ERR_RANGE;
    }
    h = pb_ball(bx_down(h_lo), bx_up(h_hi));
    kappa = pb_ball(kappa_lo, kappa_hi);
    h2 = pb_ball(bx_max(ZW_R(0.0), bx_down(bx_down(h_lo) * bx_down(h_lo))), bx_up(bx_up(h_hi) * bx_up(h_hi)));
    /* one rounding per bx_down / bx_up (box_interval.h): near critical damping the second
     * subtraction cancels, so the first one's rounding must be covered on its own */
    w2 = pb_ball(bx_down(bx_down(h2.v - h2.e) - kappa_hi), bx_up(bx_up(h2.v + h2.e) - kappa_lo));
    if (!pb_within(w2, PB_SERIES_LIMIT) || !pb_within(h2, PB_SERIES_LIMIT)) {
        return ZW_ERR_RANGE;
    }
    delta = pb_twice(h);
    eh = pb_exp(pb_neg(h));
    det = pb_exp(pb_neg(delta));
    R = pb_neg(pb_expm1(pb_neg(delta)));
    C = zw_eb_mul(eh, pb_series(w2, 0u));
    pb_series_divided(w2, h2, &cd, &sd);
    G = pb_twice(zw_eb_mul(eh, cd));
    H = zw_eb_mul(eh, sd);
    P = zw_eb_mul(kappa, G);
    p_iv = bx_make(bx_max(ZW_R(0.0), bx_down(P.v - P.e)), bx_up(P.v + P.e));
    pb_store(p_iv, &P.v, &P.e);
    Q = zw_eb_add(zw_eb_add(one, det), pb_twice(C));
    b1 = zw_eb_add(pb_half(G), zw_eb_mul(h, H));
    b0 = zw_eb_sub(pb_half(G), zw_eb_mul(h, H));

    pb_order2_zero(out);
    out->den[0] = ZW_R(2.0);
    pb_set(&out->den[1], &out->den_err[1], pb_neg(pb_twice(pb_twice(C))));
    pb_set(&out->den[2], &out->den_err[2], pb_twice(det));
    pb_set(&out->num[0], &out->num_err[0], pb_twice(b1));
    pb_set(&out->num[1], &out->num_err[1], pb_twice(b0));
    pb_set(&out->den_s[0], &out->den_s_err[0], pb_twice(Q));
    pb_set(&out->den_s[1], &out->den_s_err[1], pb_twice(pb_twice(R)));
    pb_set(&out->den_s[2], &out->den_s_err[2], pb_twice(P));
    pb_set(&out->num_s[0], &out->num_s_err[0], pb_twice(zw_eb_mul(delta, H)));
    pb_set(&out->num_s[1], &out->num_s_err[1], pb_twice(G));
    out->den_w[0] = ZW_R(2.0);
    pb_set(&out->den_w[1], &out->den_w_err[1], pb_twice(zw_eb_add(P, R)));
    pb_set(&out->den_w[2], &out->den_w_err[2], pb_twice(P));

    /* the midpoint, informational */
    mid = ZW_R(0.5) * delta_lo + ZW_R(0.5) * delta_hi;
    st = zw_coeffs_init(&out->c, mid);
    if (st != ZW_OK) {
        return st;
    }
    out->c.delta_relerr = (mid > ZW_R(0.0)) ? bx_up((delta_hi - delta_lo) / (mid + mid)) : ZW_R(0.0);
    out->spec.delta = mid;
    out->spec.kappa = kappa.v;
    out->spec.lambda = ZW_R(0.0);
    out->spec.delta_relerr = out->c.delta_relerr;
    out->spec.kappa_relerr = (kappa.v > ZW_R(0.0)) ? bx_up(kappa.e / kappa.v) : ZW_R(0.0);
    out->spec.lambda_relerr = ZW_R(0.0);
    if (!pb_all_finite(out)) {
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

zw_status zw_plant_enclose2(zw_plant *out, zw_real delta_lo, zw_real delta_hi, zw_real kappa_lo,
                            zw_real kappa_hi)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = pb_validate(delta_lo, delta_hi);
    if (st == ZW_OK) {
        if (ZW_IS_NAN(kappa_lo) || ZW_IS_NAN(kappa_hi)) {
            st = ZW_ERR_NAN;
        } else if (!ZW_IS_FINITE(kappa_lo) || !ZW_IS_FINITE(kappa_hi)) {
            st = ZW_ERR_INF;
        } else if (kappa_lo < ZW_R(0.0)) {
            st = ZW_ERR_ARG;
        } else if (kappa_lo > kappa_hi) {
            st = ZW_ERR_BOX;
        } else if (kappa_hi == ZW_R(0.0)) {
            st = pb_enclose(out, delta_lo, delta_hi); /* zw_plant_enclose's */
        } else {
            st = pb_enclose2(out, delta_lo, delta_hi, kappa_lo, kappa_hi);
        }
    }
    if (st != ZW_OK) {
        zw_plant_fail(out);
    }
    return st;
}

zw_status zw_plant_enclose(zw_plant *out, zw_real delta_lo, zw_real delta_hi)
{
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = pb_enclose(out, delta_lo, delta_hi);
    if (st != ZW_OK) {
        zw_plant_fail(out);
    }
    return st;
}
