/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The ideal plant enclosed over a delta interval (plant_box.h; proofs in docs/box.md). */
#include "zwidth/plant_box.h"

#include <stddef.h>

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

static zw_status pb_enclose(zw_plant *out, zw_real delta_lo, zw_real delta_hi)
{
    pb_ranges r;
    zw_real mid;
    zw_status st = pb_validate(delta_lo, delta_hi);
    unsigned i;
    if (st != ZW_OK) {
        return st;
    }
    st = pb_ranges_init(&r, delta_lo, delta_hi);
    if (st != ZW_OK) {
        return st;
    }
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
