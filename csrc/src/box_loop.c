/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Certification of the general loop over a plant box (box.h, second part; docs/box.md).
 *
 * Why not the loop's own guarded check with wide coefficient bounds: its running-error
 * arithmetic (zw_eb, Routh and Schur-Cohn rows, the factored evaluation of p) keeps the
 * second-order terms and holds for any radius, but two inputs are first order only:
 * zw_coeffs' delta_relerr (the coefficients' sensitivity, linearized) and
 * zw_loop_carry_gain_rounding (widens a part by |part| rel, not by (|part| + err) rel).
 * Both are sound at rounding size, not for a sub-box.  Here instead:
 *
 *   P(s) = (1 + s)^d den_s(s) Dvs(s) + (1 - s)^(d+1) num_s(s) (alpha Dvs(s) + beta Nvs(s)),
 *
 * the bilinear image (z = (1 + s)/(1 - s)) of p = z^d D Dv + N (alpha Dv + beta Nv), with
 * den_s, num_s from zw_plant_enclose over the sub-box's delta range, alpha over
 * [K_lo, K_hi] T^2 / [m_lo, m_hi], beta over [B_lo, B_hi] T / [m_lo, m_hi], every product and sum in
 * interval arithmetic rounded outward (box_interval.h).  Every plant and gain of the sub-box
 * has its P inside the coefficient intervals [lo_k, hi_k]; Kharitonov's theorem: such an
 * interval polynomial (degree invariant) is Hurwitz iff its four Kharitonov polynomials are.
 * The constant coefficient is alpha (c1 + c2) Dv(1) (den_s(0) = Nvs(0) = 0; with stiffness
 * den_s(0) = 2 P >= 0 adds to it, bl_cell_test); for the sub-box
 * at the bottom of the K range (K_lo = 0, meaning K -> 0+) it is in (0, hi_0]:
 * the family is the union over eps > 0 of the families with q0 in [eps, hi_0], so it is
 * Hurwitz if K2, K3 (q0 = hi_0) and, for all small eps, K1, K4 with q0 = eps are; and
 * s R(s) + eps is Hurwitz for all small eps > 0 when R is (one root near -eps / R(0), the
 * others near R's).  So K1 / s and K4 / s (degree n - 1) are tested instead.
 */
#include "zwidth/box.h"
#include "zwidth/box_cert.h"

#include <float.h>
#include <stddef.h>
#include <string.h>

#include "zwidth/plant_box.h"
#include "box_interval.h"

#define BL_BISECT_STEPS 60

typedef enum bl_result { BL_STABLE = 0, BL_UNSURE = 1, BL_UNSTABLE = 2 } bl_result;

/* The loop; its velocity estimate in s (ascending powers, exact but for 1 +- a) is kept in
 * the scratch (sc->dvs, sc->nvs), with the rest of the large arrays. */
typedef struct bl_loop {
    zw_plant_box box; /* folded (zw_box_fold): M, Bp, Kp */
    zw_box_loop_scratch *sc;
    zw_device_loop_spec spec;
    zw_real pole; /* a, LOWPASS */
    unsigned delay, mv, n;
} bl_loop;

/* ---- interval polynomials (ascending) ----------------------------------------------- */

static void bl_poly_zero(bx_iv p[], unsigned len)
{
    unsigned i;
    for (i = 0u; i < len; ++i) {
        p[i] = bx_point(ZW_R(0.0));
    }
}

/* out[0..na+nb] = a[0..na] * b[0..nb]; out must not alias a or b. */
static void bl_poly_mul(const bx_iv a[], unsigned na, const bx_iv b[], unsigned nb, bx_iv out[])
{
    unsigned i, j;
    bl_poly_zero(out, na + nb + 1u);
    for (i = 0u; i <= na; ++i) {
        for (j = 0u; j <= nb; ++j) {
            out[i + j] = bx_add(out[i + j], bx_mul(a[i], b[j]));
        }
    }
}

/* p[0..n] *= (c0 + c1 s), exact integer factors (+-1), in place. */
static void bl_poly_times_linear(bx_iv p[], unsigned n, zw_real c0, zw_real c1)
{
    unsigned i;
    p[n + 1u] = bx_point(ZW_R(0.0));
    for (i = n + 1u; i > 0u; --i) {
        p[i] = bx_add(bx_mul(p[i], bx_point(c0)), bx_mul(p[i - 1u], bx_point(c1)));
    }
    p[0] = bx_mul(p[0], bx_point(c0));
}

/* ---- the loop's velocity estimate ------------------------------------------------------ */

static zw_status bl_loop_init(bl_loop *L, const zw_plant_box *box, const zw_device_loop_spec *spec,
                              zw_box_loop_scratch *sc)
{
    const bool tustin = (spec->differentiator == ZW_DIFF_TUSTIN);
    bx_iv one_minus_a, one_plus_a;
    bx_iv *dvs = sc->dvs, *nvs = sc->nvs;
    unsigned i;
    zw_status st;
    const unsigned delay = spec->delay;
    /* bl_setup's zw_device_loop_init_plant validated the spec; the degree's parts are bounded
     * again where they index the arrays (unreachable, the same errors: docs/eva.md) */
    if (delay > ZW_LOOP_MAX_DELAY) {
        return ZW_ERR_DELAY;
    }
    L->box = *box;
    L->sc = sc;
    L->spec = *spec;
    L->delay = delay;
    L->pole = spec->pole;
    if ((spec->filter == ZW_VFILTER_LOWPASS) && !(spec->cutoff_hz == ZW_R(0.0))) {
        st = zw_loop_lowpass_pole(spec->cutoff_hz, box->T, &L->pole);
        if (st != ZW_OK) {
            return st;
        }
    }
    one_minus_a = bx_make(bx_down(ZW_R(1.0) - L->pole), bx_up(ZW_R(1.0) - L->pole));
    one_plus_a = bx_make(bx_down(ZW_R(1.0) + L->pole), bx_up(ZW_R(1.0) + L->pole));
    bl_poly_zero(dvs, ZW_LOOP_MAX_AVERAGE + 1u);
    bl_poly_zero(nvs, ZW_LOOP_MAX_AVERAGE + 1u);
    switch (spec->filter) {
    case ZW_VFILTER_AVERAGE: {
        /* backward: Dv = n z^n, Nv = z^n - 1;  Tustin: Dv = n z^(n-1) (z + 1), Nv = 2 (z^n - 1) */
        const unsigned n = spec->average;
        bx_iv *plus = sc->poly[0], *minus = sc->poly[1]; /* (1 + s)^n, (1 - s)^n */
        if ((n < 1u) || (n > ZW_LOOP_MAX_AVERAGE)) {
            return ZW_ERR_FILTER;
        }
        L->mv = n;
        bl_poly_zero(plus, ZW_LOOP_MAX_AVERAGE + 2u);
        bl_poly_zero(minus, ZW_LOOP_MAX_AVERAGE + 2u);
        plus[0] = bx_point(ZW_R(1.0));
        minus[0] = bx_point(ZW_R(1.0));
        for (i = 0u; i < n; ++i) { /* (1 + s)^n, (1 - s)^n: exact binomials */
            bl_poly_times_linear(plus, i, ZW_R(1.0), ZW_R(1.0));
            bl_poly_times_linear(minus, i, ZW_R(1.0), -ZW_R(1.0));
        }
        for (i = 0u; i <= n; ++i) {
            const zw_real gain = tustin ? ZW_R(2.0) : ZW_R(1.0);
            nvs[i] = bx_mul(bx_point(gain), bx_make(plus[i].lo - minus[i].hi, plus[i].hi - minus[i].lo));
        }
        bl_poly_zero(plus, ZW_LOOP_MAX_AVERAGE + 2u);
        plus[0] = bx_point((zw_real)n);
        for (i = 0u; i < (tustin ? (n - 1u) : n); ++i) {
            bl_poly_times_linear(plus, i, ZW_R(1.0), ZW_R(1.0));
        }
        if (tustin) { /* z + 1 -> 2 */
            plus[n] = bx_point(ZW_R(0.0));
            for (i = 0u; i < n; ++i) {
                plus[i] = bx_mul(plus[i], bx_point(ZW_R(2.0)));
            }
        }
        for (i = 0u; i <= n; ++i) {
            dvs[i] = plus[i];
        }
        break;
    }
    case ZW_VFILTER_LOWPASS:
        if (tustin) { /* Dv = (z + 1)(z - a) -> 2 ((1 - a) + (1 + a) s); Nv = 2 (1 - a) z (z - 1) -> 4 (1 - a)(s + s^2) */
            L->mv = 2u;
            dvs[0] = bx_mul(bx_point(ZW_R(2.0)), one_minus_a);
            dvs[1] = bx_mul(bx_point(ZW_R(2.0)), one_plus_a);
            nvs[1] = bx_mul(bx_point(ZW_R(4.0)), one_minus_a);
            nvs[2] = nvs[1];
        } else { /* Dv = z - a -> (1 - a) + (1 + a) s;  Nv = (1 - a)(z - 1) -> 2 (1 - a) s */
            L->mv = 1u;
            dvs[0] = one_minus_a;
            dvs[1] = one_plus_a;
            nvs[1] = bx_mul(bx_point(ZW_R(2.0)), one_minus_a);
        }
        break;
    case ZW_VFILTER_NONE:
    default:
        L->mv = 1u;
        if (tustin) { /* Dv = z + 1 -> 2;  Nv = 2 (z - 1) -> 4 s */
            dvs[0] = bx_point(ZW_R(2.0));
            nvs[1] = bx_point(ZW_R(4.0));
        } else { /* Dv = z -> 1 + s;  Nv = z - 1 -> 2 s */
            dvs[0] = bx_point(ZW_R(1.0));
            dvs[1] = bx_point(ZW_R(1.0));
            nvs[1] = bx_point(ZW_R(2.0));
        }
        break;
    }
    L->n = 2u + L->delay + L->mv;
    return ZW_OK;
}

/* ---- guarded Routh test: loop.c's (internal.h) ------------------------------------------- */

static bl_result bl_routh(zw_real w[], zw_real we[], unsigned n)
{
    bl_result r;
    switch (zw_routh_hurwitz(w, we, n)) {
    case ZW_HURWITZ_STABLE:
        r = BL_STABLE;
        break;
    case ZW_HURWITZ_UNSTABLE:
        r = BL_UNSTABLE;
        break;
    case ZW_HURWITZ_UNSURE:
    default:
        r = BL_UNSURE;
        break;
    }
    return r;
}

/* Kharitonov polynomial `which` (1..4) of q[0..n] (ascending intervals): coefficient k takes
 * lo or hi by k mod 4 (K1: lo lo hi hi, K2: hi hi lo lo, K3: hi lo lo hi, K4: lo hi hi lo);
 * from index `first` (1: divided by s), then Routh. */
static bl_result bl_kharitonov(zw_box_loop_scratch *sc, const bx_iv q[], unsigned n, unsigned which,
                                unsigned first)
{
    static const unsigned char k_take_hi[4][4] = {{0u, 0u, 1u, 1u}, {1u, 1u, 0u, 0u},
                                                  {1u, 0u, 0u, 1u}, {0u, 1u, 1u, 0u}};
    zw_real *w = sc->row, *we = sc->row_err;
    const unsigned deg = n - first;
    unsigned k;
    for (k = first; k <= n; ++k) {
        const bool hi = (k_take_hi[which - 1u][k & 3u] != 0u);
        w[n - k] = hi ? q[k].hi : q[k].lo; /* highest power first */
        we[n - k] = ZW_R(0.0);
    }
    return bl_routh(w, we, deg);
}

/* ---- one sub-box ------------------------------------------------------------------------- */

static bx_iv bl_from_eb(zw_real v, zw_real e)
{
    return bx_make(bx_down(v - e), bx_up(v + e));
}

/* Is every K in the cell's range (K_lo = 0: (0, K_hi]) stable for every plant and B of the
 * cell?  STABLE proves it;
 * UNSURE otherwise (never UNSTABLE: a Kharitonov vertex is not a plant). */
ZW_NOINLINE static zw_status bl_cell_test(const bl_loop *L, const zw_box_loop_cell *c, bl_result *res)
{
    const zw_real T = L->box.T;
    const bool stiff = (L->box.k_hi > ZW_R(0.0));
    zw_plant pl;
    bx_iv den_s[3], num_s[2], m_iv, alpha, beta, gain_v[ZW_LOOP_MAX_AVERAGE + 1u];
    zw_box_loop_scratch *sc = L->sc;
    bx_iv *t1 = sc->poly[0];
    bx_iv *t2 = sc->poly[1];
    bx_iv *P = sc->poly[2];
    zw_real dlo, dhi;
    unsigned i, first = 0u;
    zw_status st;
    *res = BL_UNSURE;
    dlo = bx_max(ZW_R(0.0), bx_down(bx_down(c->b_lo * T) / c->m_hi));
    dhi = bx_up(bx_up(c->b_hi * T) / c->m_lo);
    if (stiff) {
        /* the folded box has delta, kappa <= ZW_PLANT_ENCLOSE_MAX (zw_box_fold): the
         * outward-rounded ends may pass it, the plants do not */
        const zw_real klo = bx_max(ZW_R(0.0), bx_down(bx_down(bx_down(c->k_lo * T) * T) / c->m_hi));
        const zw_real khi = bx_up(bx_up(bx_up(c->k_hi * T) * T) / c->m_lo);
        st = zw_plant_enclose2(&pl, bx_min(dlo, ZW_PLANT_ENCLOSE_MAX), bx_min(dhi, ZW_PLANT_ENCLOSE_MAX),
                               bx_min(klo, ZW_PLANT_ENCLOSE_MAX), bx_min(khi, ZW_PLANT_ENCLOSE_MAX));
    } else {
        st = zw_plant_enclose(&pl, dlo, dhi);
    }
    if (st != ZW_OK) {
        return st;
    }
    /* ascending: den_s = 2 P + 4 R s + 2 Q s^2 (ideal: 0 + 4 (1 - e) s + 4 (1 + e) s^2);
     * num_s = (c1 + c2) + d12 s, or 2 G + 2 delta H s (plant_box.h) */
    den_s[0] = stiff ? bl_from_eb(pl.den_s[2], pl.den_s_err[2]) : bx_point(ZW_R(0.0));
    den_s[1] = bl_from_eb(pl.den_s[1], pl.den_s_err[1]);
    den_s[2] = bl_from_eb(pl.den_s[0], pl.den_s_err[0]);
    num_s[0] = bl_from_eb(pl.num_s[1], pl.num_s_err[1]);
    num_s[1] = bl_from_eb(pl.num_s[0], pl.num_s_err[0]);
    m_iv = bx_make(c->m_lo, c->m_hi);
    alpha = bx_make(bx_max(ZW_R(0.0), bx_down(bx_down(bx_down(c->K_lo * T) * T) / c->m_hi)),
                    bx_up(bx_up(bx_up(c->K_hi * T) * T) / c->m_lo));
    beta = bx_div_pos(bx_make(bx_down(c->B_lo * T), bx_up(c->B_hi * T)), m_iv);
    /* first part: (1 + s)^d den_s Dvs */
    bl_poly_mul(den_s, 2u, sc->dvs, L->mv, t1);
    /* each factor's degree from i (not a running sum: Eva bounds it without relations) */
    for (i = 0u; i < L->delay; ++i) {
        bl_poly_times_linear(t1, 2u + L->mv + i, ZW_R(1.0), ZW_R(1.0));
    }
    /* second part: (1 - s)^(d+1) num_s (alpha Dvs + beta Nvs) */
    for (i = 0u; i <= L->mv; ++i) {
        gain_v[i] = bx_add(bx_mul(alpha, sc->dvs[i]), bx_mul(beta, sc->nvs[i]));
    }
    bl_poly_mul(num_s, 1u, gain_v, L->mv, t2);
    for (i = 0u; i <= L->delay; ++i) {
        bl_poly_times_linear(t2, 1u + L->mv + i, ZW_R(1.0), -ZW_R(1.0));
    }
    for (i = 0u; i <= L->n; ++i) {
        P[i] = bx_add(t1[i], t2[i]);
        if (!ZW_IS_FINITE(P[i].lo) || !ZW_IS_FINITE(P[i].hi)) {
            return ZW_ERR_RANGE;
        }
    }
    /* K_lo = 0: q0 = (2 P + alpha num_s(0)) Dvs(0) > 0 at every point (P >= 0, alpha > 0)
     * but its enclosure may reach 0: then K1 / s and K4 / s */
    if ((c->K_lo == ZW_R(0.0)) && !(P[0].lo > ZW_R(0.0))) {
        if (!(P[0].hi > ZW_R(0.0))) {
            return ZW_OK;
        }
        first = 1u;
    }
    if ((bl_kharitonov(sc, P, L->n, 2u, 0u) == BL_STABLE) && (bl_kharitonov(sc, P, L->n, 3u, 0u) == BL_STABLE) &&
        (bl_kharitonov(sc, P, L->n, 1u, first) == BL_STABLE) && (bl_kharitonov(sc, P, L->n, 4u, first) == BL_STABLE)) {
        *res = BL_STABLE;
    }
    return ZW_OK;
}

/* ---- the search -------------------------------------------------------------------------- */

static zw_real bl_mid(zw_real lo, zw_real hi)
{
    return lo + ZW_R(0.5) * (hi - lo);
}

/* The side bl_split halves (ZW_BOX_CERT_SPLIT_*), 0 when none can be split further in
 * floating point: the widest, m relative; b and B in units of m / T + |B| + b (as delta and
 * beta feel them); K relative to the K asked for (K_ref), Kp relative to K_ref + Kp. */
static unsigned bl_split_side(zw_real T, zw_real K_ref, const zw_box_loop_cell *c)
{
    const zw_real mm = bl_mid(c->m_lo, c->m_hi), bm = bl_mid(c->b_lo, c->b_hi), Bm = bl_mid(c->B_lo, c->B_hi);
    const zw_real Km = bl_mid(c->K_lo, c->K_hi), km = bl_mid(c->k_lo, c->k_hi);
    const zw_real scale = mm / T + bm + ZW_FABS(Bm);
    zw_real w[5], best = -ZW_R(1.0);
    unsigned side = 0u, i;
    w[0] = ((mm > c->m_lo) && (mm < c->m_hi)) ? (c->m_hi - c->m_lo) / c->m_hi : -ZW_R(1.0);
    w[1] = ((bm > c->b_lo) && (bm < c->b_hi)) ? (c->b_hi - c->b_lo) / scale : -ZW_R(1.0);
    w[2] = ((Km > c->K_lo) && (Km < c->K_hi)) ? (c->K_hi - c->K_lo) / K_ref : -ZW_R(1.0);
    w[3] = ((Bm > c->B_lo) && (Bm < c->B_hi)) ? (c->B_hi - c->B_lo) / scale : -ZW_R(1.0);
    /* Kp beside K (both springs: alpha + kappa is the loop's DC stiffness) */
    w[4] = ((km > c->k_lo) && (km < c->k_hi)) ? (c->k_hi - c->k_lo) / (K_ref + km) : -ZW_R(1.0);
    for (i = 0u; i < 5u; ++i) {
        if (w[i] > best) {
            best = w[i];
            side = i + 1u;
        }
    }
    return (best > ZW_R(0.0)) ? side : 0u;
}

/* Halve c along side (ZW_BOX_CERT_SPLIT_*) at its midpoint; false (halves undefined) when
 * the midpoint is not strictly inside (a certificate's bad split) or side is not a side. */
static bool bl_halve(const zw_box_loop_cell *c, unsigned side, zw_box_loop_cell *left, zw_box_loop_cell *right)
{
    zw_real lo, hi, mid;
    zw_real *left_hi, *right_lo;
    *left = *c;
    *right = *c;
    switch (side) {
    case ZW_BOX_CERT_SPLIT_M:
        lo = c->m_lo;
        hi = c->m_hi;
        left_hi = &left->m_hi;
        right_lo = &right->m_lo;
        break;
    case ZW_BOX_CERT_SPLIT_BP:
        lo = c->b_lo;
        hi = c->b_hi;
        left_hi = &left->b_hi;
        right_lo = &right->b_lo;
        break;
    case ZW_BOX_CERT_SPLIT_K:
        lo = c->K_lo;
        hi = c->K_hi;
        left_hi = &left->K_hi;
        right_lo = &right->K_lo;
        break;
    case ZW_BOX_CERT_SPLIT_B:
        lo = c->B_lo;
        hi = c->B_hi;
        left_hi = &left->B_hi;
        right_lo = &right->B_lo;
        break;
    case ZW_BOX_CERT_SPLIT_KP:
        lo = c->k_lo;
        hi = c->k_hi;
        left_hi = &left->k_hi;
        right_lo = &right->k_lo;
        break;
    default:
        return false;
    }
    mid = bl_mid(lo, hi);
    if (!(mid > lo) || !(mid < hi)) {
        return false;
    }
    *left_hi = mid;
    *right_lo = mid;
    return true;
}

/* Split along the widest side (bl_split_side); false when none can be split further. */
static bool bl_split(zw_real T, zw_real K_ref, const zw_box_loop_cell *c, zw_box_loop_cell *left,
                     zw_box_loop_cell *right)
{
    return bl_halve(c, bl_split_side(T, K_ref, c), left, right);
}

typedef enum bl_outcome { BL_OPEN = 0, BL_CERTIFIED = 1, BL_REFUTED = 2 } bl_outcome;

typedef struct bl_search {
    uint_least32_t evals;
    zw_real m_worst, b_worst, k_worst; /* refuted plant, or the last cell not certified */
} bl_search;

/* The point loop at plant (M, Bp, Kp) (Kp = 0: zw_device_loop_init's). */
static zw_status bl_point_init(const bl_loop *L, zw_device_loop *dl, zw_real m, zw_real b, zw_real k)
{
    return zw_device_loop_init_plant(dl, m, b, L->box.T, k, ZW_R(0.0), ZW_R(0.0), ZW_R(0.0), ZW_R(0.0),
                                     &L->spec);
}

/* Is (K, B) surely unstable at plant (m, b)?  (the guarded point check, not marginal) */
ZW_NOINLINE static zw_status bl_point_unstable(const bl_loop *L, zw_loop_workspace *ws, zw_real m, zw_real b,
                                   zw_real k, zw_real K, zw_real B, bool *unstable)
{
    zw_device_loop *dl = &L->sc->dl;
    zw_loop_verdict v;
    zw_status st;
    *unstable = false;
    st = bl_point_init(L, dl, m, b, k);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_loop_check(dl, ws, K, B, &v);
    if (st != ZW_OK) {
        return st;
    }
    *unstable = !v.stable && !v.marginal;
    return ZW_OK;
}

/* The whole box x (0, K] x [B_lo, B_hi]. */
static void bl_root(const zw_plant_box *box, zw_real K, zw_real B_lo, zw_real B_hi, zw_box_loop_cell *c)
{
    c->m_lo = box->m_lo;
    c->m_hi = box->m_hi;
    c->b_lo = box->b_lo;
    c->b_hi = box->b_hi;
    c->K_lo = ZW_R(0.0);
    c->K_hi = K;
    c->B_lo = B_lo;
    c->B_hi = B_hi;
    c->k_lo = box->k_lo;
    c->k_hi = box->k_hi;
}

/* Certify every K' in (0, K] at every B in [B_lo, B_hi] for the whole box, depth first. */
static zw_status bl_certify(const bl_loop *L, zw_loop_workspace *ws, zw_real K, zw_real B_lo,
                            zw_real B_hi, const zw_box_loop_work *work, bl_search *s, bl_outcome *outcome)
{
    const zw_plant_box *box = &L->box;
    zw_box_loop_cell *cells = work->cells;
    uint_least32_t live = 1u, used = 0u;
    zw_status st;
    *outcome = BL_OPEN;
    s->m_worst = ZW_NAN;
    s->b_worst = ZW_NAN;
    s->k_worst = ZW_NAN;
    if (!(K > ZW_R(0.0))) {
        return ZW_OK;
    }
    bl_root(box, K, B_lo, B_hi, &cells[0]);
    while (live > 0u) {
        zw_box_loop_cell c = cells[live - 1u];
        bl_result res;
        bool unstable;
        if (used >= work->max_evals) {
            return ZW_OK;
        }
        live -= 1u;
        used += 1u;
        s->evals += 1u;
        st = bl_cell_test(L, &c, &res);
        if (st != ZW_OK) {
            return st;
        }
        if (res == BL_STABLE) {
            continue;
        }
        s->m_worst = bl_mid(c.m_lo, c.m_hi);
        s->b_worst = bl_mid(c.b_lo, c.b_hi);
        s->k_worst = bl_mid(c.k_lo, c.k_hi);
        st = bl_point_unstable(L, ws, s->m_worst, s->b_worst, s->k_worst, c.K_hi, bl_mid(c.B_lo, c.B_hi),
                               &unstable);
        if (st != ZW_OK) {
            return st;
        }
        if (unstable) {
            *outcome = BL_REFUTED;
            return ZW_OK;
        }
        /* split straight into the stack (right below left): no halves on this frame, which
         * is on the point checks' chain (tools/footprint.sh) */
        if ((live + 2u > work->capacity) || !bl_split(box->T, K, &c, &cells[live + 1u], &cells[live])) {
            return ZW_OK;
        }
        live += 2u;
    }
    *outcome = BL_CERTIFIED;
    s->m_worst = ZW_NAN;
    s->b_worst = ZW_NAN;
    s->k_worst = ZW_NAN;
    return ZW_OK;
}

/* ---- validation -------------------------------------------------------------------------- */

static zw_status bl_validate_work(const zw_box_loop_work *work)
{
    if ((work == NULL) || (work->cells == NULL) || (work->scratch == NULL)) {
        return ZW_ERR_NULL;
    }
    /* constant returns: a sound analyser splits its callers' states by them (docs/eva.md) */
    if (bx_validate_work(work->capacity, ZW_BOX_LOOP_MIN_CELLS, work->max_evals, work->rel_tol) !=
        ZW_OK) {
        return ZW_ERR_ARG;
    }
    return ZW_OK;
}

zw_status zw_box_loop_work_init(zw_box_loop_work *work, zw_box_loop_cell *cells, uint_least32_t capacity,
                                zw_box_loop_scratch *scratch)
{
    if ((work == NULL) || (cells == NULL) || (scratch == NULL)) {
        return ZW_ERR_NULL;
    }
    if (capacity < ZW_BOX_LOOP_MIN_CELLS) {
        return ZW_ERR_ARG;
    }
    work->cells = cells;
    work->scratch = scratch;
    work->capacity = capacity;
    work->max_evals = ZW_BOX_LOOP_DEFAULT_EVALS;
    work->rel_tol = ZW_BOX_LOOP_DEFAULT_REL_TOL;
    return ZW_OK;
}

/* The loop over the folded box f with scratch sc (the spec validated by zw_device_loop_init
 * at the centre). */
static zw_status bl_setup_scratch(bl_loop *L, const zw_plant_box *f, const zw_device_loop_spec *spec,
                                  zw_box_loop_scratch *sc)
{
    /* the centre plant's loop validates the spec before bl_loop_init reads it (the caller's
     * spec itself, not a copy: Eva then knows the average it bounds, docs/eva.md) */
    zw_status st = zw_device_loop_init_plant(&sc->dl, bl_mid(f->m_lo, f->m_hi), bl_mid(f->b_lo, f->b_hi), f->T,
                                             bl_mid(f->k_lo, f->k_hi), ZW_R(0.0), ZW_R(0.0), ZW_R(0.0),
                                             ZW_R(0.0), spec);
    if (st != ZW_OK) {
        return st;
    }
    return bl_loop_init(L, f, spec, sc);
}

/* The box, the work, the spec and ws. */
static zw_status bl_setup(bl_loop *L, const zw_plant_box *box, const zw_device_loop_spec *spec,
                          zw_loop_workspace *ws, const zw_box_loop_work *work)
{
    zw_box_loop_scratch *sc;
    zw_plant_box f;
    zw_status st;
    if ((spec == NULL) || (ws == NULL)) {
        return ZW_ERR_NULL;
    }
    st = zw_box_fold(box, &f);
    if (st != ZW_OK) {
        return st;
    }
    st = bl_validate_work(work);
    if (st != ZW_OK) {
        return st;
    }
    sc = work->scratch; /* a pointer of our own, not the const struct's member (MISRA 11.8) */
    return bl_setup_scratch(L, &f, spec, sc);
}

/* ---- public functions -------------------------------------------------------------------- */

static void bl_fail_verdict(zw_box_loop_verdict *out)
{
    if (out == NULL) {
        return;
    }
    out->stable = false;
    out->decided = false;
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->evals = 0u;
    out->k_worst = ZW_NAN;
}

static zw_status bl_check(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                          zw_real K, zw_real B, const zw_box_loop_work *work, zw_box_loop_verdict *out)
{
    bl_loop L;
    bl_search s;
    bl_outcome outcome;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = bl_setup(&L, box, spec, ws, work);
    if (st != ZW_OK) {
        return st;
    }
    st = bx_validate_gain(&L.box, K, true);
    if (st != ZW_OK) {
        return st;
    }
    st = bx_validate_gain(&L.box, B, false);
    if (st != ZW_OK) {
        return st;
    }
    s.evals = 0u;
    if (!(K > ZW_R(0.0))) {
        /* K <= 0 is unstable at every plant without stiffness (p(1) = alpha Na(1)); with it,
         * small K <= 0 may be stable: not decided */
        const bool stiff = (L.box.k_hi > ZW_R(0.0));
        out->stable = false;
        out->decided = !stiff;
        out->m_worst = stiff ? ZW_NAN : L.box.m_lo;
        out->b_worst = stiff ? ZW_NAN : L.box.b_lo;
        out->k_worst = stiff ? ZW_NAN : ZW_R(0.0);
        out->evals = 0u;
        return ZW_OK;
    }
    st = bl_certify(&L, ws, K, B, B, work, &s, &outcome);
    if (st != ZW_OK) {
        return st;
    }
    out->stable = (outcome == BL_CERTIFIED);
    out->decided = (outcome != BL_OPEN);
    out->m_worst = s.m_worst;
    out->b_worst = s.b_worst;
    out->k_worst = s.k_worst;
    out->evals = s.evals;
    return ZW_OK;
}

zw_status zw_box_loop_check(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real K, zw_real B,
                            const zw_box_loop_work *work, zw_box_loop_verdict *out)
{
    zw_status st = bl_check(box, spec, ws, K, B, work, out);
    if (st != ZW_OK) {
        bl_fail_verdict(out);
    }
    return st;
}


/* K_max(B) at one plant (certified point value); keeps the least in *best. */
static zw_status bl_point_k_max(const bl_loop *L, zw_loop_workspace *ws, zw_real m, zw_real b, zw_real kp,
                                zw_real B, zw_box_loop_bound *best)
{
    zw_device_loop *dl = &L->sc->dl;
    zw_real k;
    zw_status st = bl_point_init(L, dl, m, b, kp);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_loop_k_max(dl, ws, B, &k);
    if (st != ZW_OK) {
        return st;
    }
    if (k < best->K_upper) {
        best->K_upper = k;
        best->m_worst = m;
        best->b_worst = b;
        best->k_worst = kp;
    }
    return ZW_OK;
}

static zw_status bl_k_max(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                          zw_real B, const zw_box_loop_work *work, zw_box_loop_bound *out)
{
    bl_loop L;
    bl_search s;
    bl_outcome outcome;
    zw_real lo = ZW_R(0.0), hi;
    int step, corner;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = bl_setup(&L, box, spec, ws, work);
    if (st != ZW_OK) {
        return st;
    }
    st = bx_validate_gain(&L.box, B, false);
    if (st != ZW_OK) {
        return st;
    }
    out->K_lower = ZW_R(0.0);
    out->K_upper = ZW_INF;
    out->m_worst = L.box.m_lo;
    out->b_worst = L.box.b_lo;
    out->k_worst = L.box.k_lo;
    out->evals = 0u;
    out->converged = false;
    /* the corners and the centre bound the answer from above (Kp's corners with stiffness) */
    for (corner = 0; corner < ((L.box.k_hi > ZW_R(0.0)) ? 9 : 5); ++corner) {
        const zw_plant_box *f = &L.box;
        const bool centre = (corner == 8) || ((corner == 4) && !(f->k_hi > ZW_R(0.0)));
        const zw_real m = centre ? bl_mid(f->m_lo, f->m_hi) : (((corner & 1) != 0) ? f->m_hi : f->m_lo);
        const zw_real b = centre ? bl_mid(f->b_lo, f->b_hi) : (((corner & 2) != 0) ? f->b_hi : f->b_lo);
        const zw_real kp = centre ? bl_mid(f->k_lo, f->k_hi) : (((corner & 4) != 0) ? f->k_hi : f->k_lo);
        st = bl_point_k_max(&L, ws, m, b, kp, B, out);
        if (st != ZW_OK) {
            return st;
        }
    }
    hi = out->K_upper;
    s.evals = 0u;
    for (step = 0; (step < BL_BISECT_STEPS) && (hi - lo > work->rel_tol * out->K_upper); ++step) {
        const zw_real mid = (lo > ZW_R(0.0)) ? bl_mid(lo, hi) : ZW_R(0.5) * hi;
        if (!(mid > lo) || !(mid < hi)) {
            break;
        }
        st = bl_certify(&L, ws, mid, B, B, work, &s, &outcome);
        if (st != ZW_OK) {
            return st;
        }
        if (outcome == BL_CERTIFIED) {
            lo = mid;
        } else {
            hi = mid;
            if (!ZW_IS_NAN(s.m_worst)) { /* the sub-box that limited: its centre's value */
                st = bl_point_k_max(&L, ws, s.m_worst, s.b_worst, s.k_worst, B, out);
                if (st != ZW_OK) {
                    return st;
                }
                hi = bx_min(hi, out->K_upper);
            }
        }
        if (out->K_upper <= ZW_R(0.0)) {
            break;
        }
    }
    out->K_lower = lo;
    out->evals = s.evals;
    out->converged = (out->K_upper - lo <= work->rel_tol * out->K_upper);
    return ZW_OK;
}

zw_status zw_box_loop_k_max(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real B, const zw_box_loop_work *work,
                            zw_box_loop_bound *out)
{
    zw_status st = bl_k_max(box, spec, ws, B, work, out);
    if (st != ZW_OK) {
        bx_fail_bound(out);
    }
    return st;
}

/* Grow [inside, ...] toward outside: each piece between the last certified end and the
 * bisection point is certified as a whole.  Returns the last certified end. */
static zw_status bl_grow(const bl_loop *L, zw_loop_workspace *ws, zw_real K, zw_real inside_start,
                         zw_real outside_start, const zw_box_loop_work *work, zw_real *end)
{
    zw_real inside = inside_start, outside = outside_start;
    const zw_real scale = ZW_FABS(inside) + ZW_FABS(outside) + L->box.b_hi;
    int step;
    for (step = 0; step < BL_BISECT_STEPS; ++step) {
        bl_search s;
        bl_outcome outcome;
        const zw_real mid = bl_mid(inside, outside);
        zw_status st;
        if (!(ZW_FABS(outside - inside) > work->rel_tol * scale) || (mid == inside) || (mid == outside)) {
            break;
        }
        s.evals = 0u;
        st = bl_certify(L, ws, K, bx_min(inside, mid), bx_max(inside, mid), work, &s, &outcome);
        if (st != ZW_OK) {
            return st;
        }
        if (outcome == BL_CERTIFIED) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    *end = inside;
    return ZW_OK;
}

static zw_status bl_b_range(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                            zw_real K, const zw_box_loop_work *work, zw_real *B_lo, zw_real *B_hi,
                            bool *nonempty)
{
    bl_loop L;
    bl_search s;
    bl_outcome outcome;
    zw_real nom_lo, nom_hi, start, lo, hi;
    bool any;
    zw_status st;
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return ZW_ERR_NULL;
    }
    st = bl_setup(&L, box, spec, ws, work);
    if (st != ZW_OK) {
        return st;
    }
    st = bx_validate_gain(&L.box, K, true);
    if (st != ZW_OK) {
        return st;
    }
    *B_lo = ZW_R(0.0);
    *B_hi = ZW_R(0.0);
    *nonempty = false;
    if (!(K > ZW_R(0.0))) {
        return ZW_OK;
    }
    /* the centre plant's certified range brackets the box's (which is inside every plant's) */
    st = zw_device_loop_b_range(&L.sc->dl, ws, K, &nom_lo, &nom_hi, &any); /* bl_setup built it */
    if ((st != ZW_OK) || !any) {
        return st;
    }
    start = bl_mid(nom_lo, nom_hi);
    s.evals = 0u;
    st = bl_certify(&L, ws, K, start, start, work, &s, &outcome);
    if ((st != ZW_OK) || (outcome != BL_CERTIFIED)) {
        return st;
    }
    st = bl_grow(&L, ws, K, start, nom_lo, work, &lo);
    if (st != ZW_OK) {
        return st;
    }
    st = bl_grow(&L, ws, K, start, nom_hi, work, &hi);
    if (st != ZW_OK) {
        return st;
    }
    *B_lo = lo;
    *B_hi = hi;
    *nonempty = true;
    return ZW_OK;
}

zw_status zw_box_loop_b_range(const zw_plant_box *box, const zw_device_loop_spec *spec,
                              zw_loop_workspace *ws, zw_real K, const zw_box_loop_work *work,
                              zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    zw_status st = bl_b_range(box, spec, ws, K, work, B_lo, B_hi, nonempty);
    if (st != ZW_OK) {
        zw_fail_interval(B_lo, B_hi, nonempty);
    }
    return st;
}

static void bl_fail_extremes(zw_box_loop_extremes *out)
{
    if (out == NULL) {
        return;
    }
    out->K_mmax = ZW_R(0.0);
    out->B_at = ZW_NAN;
    out->K_upper_at = ZW_R(0.0);
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->evals = 0u;
    out->converged = false;
    out->k_worst = ZW_NAN;
}

/* Golden-section search of B over the centre plant's B range (no proof that the box's K_max
 * is unimodal in B: only the value reported at the final B is claimed, and it is certified). */
static zw_status bl_k_mmax(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                           const zw_box_loop_work *work, zw_box_loop_extremes *out)
{
    static const zw_real k_inv_phi = ZW_R(0.6180339887498948482);
    zw_device_loop *dl;
    zw_device_loop_extremes x;
    zw_box_loop_bound f1, f2, fin;
    zw_plant_box f;
    zw_real a, b, c1, c2;
    uint_least32_t evals = 0u;
    int step;
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    if ((spec == NULL) || (ws == NULL)) {
        return ZW_ERR_NULL;
    }
    st = zw_box_fold(box, &f);
    if (st != ZW_OK) {
        return st;
    }
    st = bl_validate_work(work);
    if (st != ZW_OK) {
        return st;
    }
    dl = &work->scratch->dl;
    st = zw_device_loop_init_plant(dl, bl_mid(f.m_lo, f.m_hi), bl_mid(f.b_lo, f.b_hi), f.T, bl_mid(f.k_lo, f.k_hi),
                                   ZW_R(0.0), ZW_R(0.0), ZW_R(0.0), ZW_R(0.0), spec);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_device_loop_extremes_compute(dl, ws, &x);
    if (st != ZW_OK) {
        return st;
    }
    a = x.B_mmin;
    b = x.B_mmax;
    c1 = b - k_inv_phi * (b - a);
    c2 = a + k_inv_phi * (b - a);
    st = zw_box_loop_k_max(box, spec, ws, c1, work, &f1);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_box_loop_k_max(box, spec, ws, c2, work, &f2);
    if (st != ZW_OK) {
        return st;
    }
    evals = f1.evals + f2.evals;
    for (step = 0; step < BL_BISECT_STEPS; ++step) {
        if (!(c2 - c1 > work->rel_tol * (ZW_FABS(a) + ZW_FABS(b)))) {
            break;
        }
        if (f1.K_lower < f2.K_lower) {
            a = c1;
            c1 = c2;
            f1 = f2;
            c2 = a + k_inv_phi * (b - a);
            st = zw_box_loop_k_max(box, spec, ws, c2, work, &f2);
            evals += f2.evals;
        } else {
            b = c2;
            c2 = c1;
            f2 = f1;
            c1 = b - k_inv_phi * (b - a);
            st = zw_box_loop_k_max(box, spec, ws, c1, work, &f1);
            evals += f1.evals;
        }
        if (st != ZW_OK) {
            return st;
        }
    }
    fin = (f1.K_lower >= f2.K_lower) ? f1 : f2;
    out->K_mmax = fin.K_lower;
    out->B_at = (f1.K_lower >= f2.K_lower) ? c1 : c2;
    out->K_upper_at = fin.K_upper;
    out->m_worst = fin.m_worst;
    out->b_worst = fin.b_worst;
    out->k_worst = fin.k_worst;
    out->evals = evals;
    out->converged = fin.converged;
    return ZW_OK;
}

zw_status zw_box_loop_k_mmax(const zw_plant_box *box, const zw_device_loop_spec *spec,
                             zw_loop_workspace *ws, const zw_box_loop_work *work,
                             zw_box_loop_extremes *out)
{
    zw_status st = bl_k_mmax(box, spec, ws, work, out);
    if (st != ZW_OK) {
        bl_fail_extremes(out);
    }
    return st;
}

/* ---- certificates (box_cert.h) ------------------------------------------------------------- */

/* Node j (0xF, no code, past the last word: unreachable, the callers bound j). */
static unsigned bc_node(const zw_box_cert *cert, uint_least32_t j)
{
    if (j >= 4u * ZW_BOX_CERT_NODE_WORDS) {
        return 0xFu;
    }
    return ((unsigned)cert->nodes[j / 4u] >> (4u * (unsigned)(j % 4u))) & 0xFu;
}

static void bc_set_node(zw_box_cert *cert, uint_least32_t j, unsigned code)
{
    const unsigned shift = 4u * (unsigned)(j % 4u);
    const unsigned mask = 0xFu; /* unsigned int, not a constant's essential 8 bits (MISRA 12.2) */
    if (j < 4u * ZW_BOX_CERT_NODE_WORDS) {
        const unsigned word = ((unsigned)cert->nodes[j / 4u] & ~(mask << shift)) | ((code & mask) << shift);
        cert->nodes[j / 4u] = (uint_least16_t)word;
    }
}

/* A step's claim is one the box can normalize: finite increasing ends, a level > 0. */
static bool bc_step_ok(const bl_loop *L, float B_lo, float B_hi, float K)
{
    return (B_lo < B_hi) && (K > 0.0f) && (bx_validate_gain(&L->box, (zw_real)K, true) == ZW_OK) &&
           (bx_validate_gain(&L->box, (zw_real)B_lo, false) == ZW_OK) &&
           (bx_validate_gain(&L->box, (zw_real)B_hi, false) == ZW_OK);
}

/* One step's tree from node *pos: every leaf's cell proven, every split valid. */
static zw_box_cert_fault bc_verify_step(const bl_loop *L, const zw_box_cert *cert, unsigned step,
                                        const zw_box_loop_work *work, uint_least32_t *pos, uint_least32_t *leaves)
{
    zw_box_loop_cell *cells = work->cells;
    unsigned live = 1u;
    bl_root(&L->box, (zw_real)cert->K[step], (zw_real)cert->B[step], (zw_real)cert->B[step + 1u], &cells[0]);
    while (live > 0u) {
        zw_box_loop_cell c;
        unsigned code;
        if (live > ZW_BOX_CERT_STACK) { /* unreachable (the split below keeps it), for the analyser */
            return ZW_BOX_CERT_BAD_SPLIT;
        }
        c = cells[live - 1u];
        live -= 1u;
        if (*pos >= (uint_least32_t)cert->n_nodes) {
            return ZW_BOX_CERT_BAD_NODE;
        }
        code = bc_node(cert, *pos);
        *pos += 1u;
        if (code == ZW_BOX_CERT_LEAF) {
            bl_result res;
            if (*leaves >= ZW_BOX_CERT_MAX_LEAVES) {
                return ZW_BOX_CERT_TOO_MANY;
            }
            *leaves += 1u;
            if ((bl_cell_test(L, &c, &res) != ZW_OK) || (res != BL_STABLE)) {
                return ZW_BOX_CERT_LEAF_FAILS;
            }
        } else if (code > ZW_BOX_CERT_SPLIT_KP) {
            return ZW_BOX_CERT_BAD_NODE;
        } else {
            if ((live + 2u > ZW_BOX_CERT_STACK) || !bl_halve(&c, code, &cells[live + 1u], &cells[live])) {
                return ZW_BOX_CERT_BAD_SPLIT;
            }
            live += 2u;
        }
    }
    return ZW_BOX_CERT_OK;
}

/* The work's cells hold the walk's stack and its scratch the interval polynomials. */
static zw_status bc_validate_work(const zw_box_loop_work *work)
{
    if ((work == NULL) || (work->cells == NULL) || (work->scratch == NULL)) {
        return ZW_ERR_NULL;
    }
    return (work->capacity >= ZW_BOX_CERT_STACK) ? ZW_OK : ZW_ERR_ARG;
}

/* The loop over the folded box with the work's scratch (the spec validated as for
 * zw_box_loop_check). */
static zw_status bc_setup(bl_loop *L, const zw_plant_box *box, const zw_device_loop_spec *spec,
                          const zw_box_loop_work *work)
{
    zw_plant_box f;
    zw_box_loop_scratch *sc;
    zw_status st;
    if (spec == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_box_fold(box, &f);
    if (st == ZW_OK) {
        st = bc_validate_work(work);
    }
    if (st != ZW_OK) {
        return st;
    }
    sc = work->scratch; /* a pointer of our own, not the const struct's member (MISRA 11.8) */
    return bl_setup_scratch(L, &f, spec, sc);
}

static zw_status bc_verify(const zw_plant_box *box, const zw_device_loop_spec *spec, const zw_box_cert *cert,
                           const zw_box_loop_work *work, zw_box_cert_fault *fault, uint_least32_t *leaves)
{
    bl_loop L;
    uint_least32_t pos = 0u, j;
    unsigned i;
    zw_status st;
    if (cert == NULL) {
        return ZW_ERR_NULL;
    }
    st = bc_setup(&L, box, spec, work);
    if (st != ZW_OK) {
        return st;
    }
    if ((cert->n_steps < 1u) || (cert->n_steps > ZW_BOX_CERT_MAX_STEPS) || (cert->n_nodes < 1u) ||
        (cert->n_nodes > ZW_BOX_CERT_MAX_NODES)) {
        *fault = ZW_BOX_CERT_BAD_HEADER;
        return ZW_OK;
    }
    for (i = 0u; i < (unsigned)cert->n_steps; ++i) {
        if (!bc_step_ok(&L, cert->B[i], cert->B[i + 1u], cert->K[i])) {
            *fault = ZW_BOX_CERT_BAD_STEP;
            return ZW_OK;
        }
    }
    for (i = 0u; i < (unsigned)cert->n_steps; ++i) {
        *fault = bc_verify_step(&L, cert, i, work, &pos, leaves);
        if (*fault != ZW_BOX_CERT_OK) {
            return ZW_OK;
        }
    }
    /* every node used once, nothing after: one certificate, one encoding */
    for (j = pos; j < 4u * ZW_BOX_CERT_NODE_WORDS; ++j) {
        if ((j < (uint_least32_t)cert->n_nodes) || (bc_node(cert, j) != 0u)) {
            *fault = ZW_BOX_CERT_UNUSED;
            return ZW_OK;
        }
    }
    *fault = ZW_BOX_CERT_OK;
    return ZW_OK;
}

zw_status zw_box_cert_verify(const zw_plant_box *box, const zw_device_loop_spec *spec, const zw_box_cert *cert,
                             const zw_box_loop_work *work, zw_box_cert_fault *fault, uint_least32_t *leaves)
{
    zw_box_cert_fault local_fault = ZW_BOX_CERT_BAD_HEADER;
    uint_least32_t local_leaves = 0u;
    zw_status st;
    if ((fault == NULL) || (leaves == NULL)) {
        return ZW_ERR_NULL;
    }
    st = bc_verify(box, spec, cert, work, &local_fault, &local_leaves);
    *fault = (st == ZW_OK) ? local_fault : ZW_BOX_CERT_BAD_HEADER;
    *leaves = local_leaves;
    return st;
}

/* The step holding B (the one with the larger level on a breakpoint); false outside. */
static bool bc_step_at(const zw_box_cert *cert, float B, unsigned *step)
{
    unsigned lo = 0u, hi, n;
    if (cert == NULL) {
        return false;
    }
    n = (unsigned)cert->n_steps; /* a local: the bounds below are then the analyser's too */
    if ((n < 1u) || (n > ZW_BOX_CERT_MAX_STEPS)) {
        return false;
    }
    hi = n;
    if (!(B >= cert->B[0]) || !(B <= cert->B[hi])) {
        return false;
    }
    while (hi - lo > 1u) { /* the last step starting at or below B: lo < hi <= n */
        const unsigned mid = lo + ((hi - lo) / 2u);
        if (mid >= ZW_BOX_CERT_MAX_STEPS) { /* unreachable (mid < hi <= n), for the analyser */
            return false;
        }
        if (cert->B[mid] <= B) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    if (lo >= ZW_BOX_CERT_MAX_STEPS) { /* unreachable, as above */
        return false;
    }
    if ((lo > 0u) && (B == cert->B[lo]) && (cert->K[lo - 1u] > cert->K[lo])) {
        lo -= 1u;
    }
    *step = lo;
    return true;
}

void zw_box_cert_level(const zw_box_cert *cert, float B, float *K, bool *inside)
{
    unsigned step = 0u;
    const bool in = bc_step_at(cert, B, &step) && (step < ZW_BOX_CERT_MAX_STEPS);
    if (K != NULL) {
        *K = in ? cert->K[step] : 0.0f;
    }
    if (inside != NULL) {
        *inside = in;
    }
}

void zw_box_cert_b_range(const zw_box_cert *cert, float K, float B, float *B_lo, float *B_hi, bool *nonempty)
{
    unsigned step = 0u, first, last;
    const bool in = bc_step_at(cert, B, &step) && (step < ZW_BOX_CERT_MAX_STEPS) && (cert->K[step] >= K);
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return;
    }
    *nonempty = in;
    *B_lo = (float)ZW_NAN;
    *B_hi = (float)ZW_NAN;
    if (!in) {
        return;
    }
    first = step;
    last = step;
    while ((first > 0u) && (cert->K[first - 1u] >= K)) {
        first -= 1u;
    }
    /* n_steps <= ZW_BOX_CERT_MAX_STEPS (bc_step_at), repeated for the analyser */
    while ((last + 1u < (unsigned)cert->n_steps) && (last + 1u < ZW_BOX_CERT_MAX_STEPS) && (cert->K[last + 1u] >= K)) {
        last += 1u;
    }
    *B_lo = cert->B[first];
    *B_hi = cert->B[last + 1u];
}

void zw_box_cert_k_mmax(const zw_box_cert *cert, float *K, float *B)
{
    unsigned i, best = 0u;
    if ((K == NULL) || (B == NULL)) {
        return;
    }
    *K = 0.0f;
    *B = (float)ZW_NAN;
    if ((cert == NULL) || (cert->n_steps < 1u) || (cert->n_steps > ZW_BOX_CERT_MAX_STEPS)) {
        return;
    }
    for (i = 1u; i < (unsigned)cert->n_steps; ++i) {
        if (cert->K[i] > cert->K[best]) {
            best = i;
        }
    }
    *K = cert->K[best];
    *B = cert->B[best] + (0.5f * (cert->B[best + 1u] - cert->B[best]));
}

/* ---- the host's search (zw_box_cert_build) ---- */

/* The largest float not above x (0 < x < FLT_MAX). */
static float bc_float_down(zw_real x)
{
    float f = (float)x;
    if ((zw_real)f > x) {
        f = ZW_NEXTAFTERF(f, 0.0f);
    }
    return f;
}

/* c widened by ZW_BOX_CERT_WIDEN (relative) at every end but K_lo = 0, which stays. */
static void bc_widen(const zw_box_loop_cell *c, zw_box_loop_cell *w)
{
    const zw_real e = ZW_BOX_CERT_WIDEN;
    w->m_lo = c->m_lo - (e * c->m_lo);
    w->m_hi = c->m_hi + (e * c->m_hi);
    w->b_lo = c->b_lo - (e * c->b_lo);
    w->b_hi = c->b_hi + (e * c->b_hi);
    w->K_lo = c->K_lo - (e * c->K_lo);
    w->K_hi = c->K_hi + (e * c->K_hi);
    w->B_lo = c->B_lo - (e * ZW_FABS(c->B_lo));
    w->B_hi = c->B_hi + (e * ZW_FABS(c->B_hi));
    w->k_lo = c->k_lo - (e * c->k_lo);
    w->k_hi = c->k_hi + (e * c->k_hi);
}

typedef struct bc_builder {
    const bl_loop *L;
    zw_loop_workspace *ws;
    const zw_box_loop_work *work;
    zw_box_cert *cert;
    uint_least32_t tests;
} bc_builder;

/* Try to prove (0, K] over [B_lo, B_hi] within budget leaves, writing its preorder from node
 * pos; *n_nodes its length when *proven. */
static zw_status bc_prove(bc_builder *bd, zw_real K, zw_real B_lo, zw_real B_hi, unsigned budget,
                          uint_least32_t pos, uint_least32_t *n_nodes, bool *proven)
{
    const bl_loop *L = bd->L;
    zw_box_loop_cell *cells = bd->work->cells;
    unsigned live = 1u, leaves = 0u;
    uint_least32_t n = 0u;
    *proven = false;
    bl_root(&L->box, K, B_lo, B_hi, &cells[0]);
    while (live > 0u) {
        zw_box_loop_cell c, w;
        bl_result res = BL_UNSURE;
        unsigned side;
        bool unstable;
        if (live > ZW_BOX_CERT_STACK) { /* unreachable, as in bc_verify_step */
            return ZW_OK;
        }
        c = cells[live - 1u];
        live -= 1u;
        if ((leaves + live + 1u > budget) || (pos + n >= ZW_BOX_CERT_MAX_NODES)) {
            return ZW_OK; /* every waiting cell needs a leaf at least */
        }
        bc_widen(&c, &w);
        bd->tests += 1u;
        if ((bl_cell_test(L, &w, &res) == ZW_OK) && (res == BL_STABLE)) {
            bc_set_node(bd->cert, pos + n, ZW_BOX_CERT_LEAF);
            n += 1u;
            leaves += 1u;
            continue;
        }
        if (live + 2u > ZW_BOX_CERT_STACK) {
            return ZW_OK;
        }
        if (bl_point_unstable(L, bd->ws, bl_mid(c.m_lo, c.m_hi), bl_mid(c.b_lo, c.b_hi), bl_mid(c.k_lo, c.k_hi),
                              c.K_hi, bl_mid(c.B_lo, c.B_hi), &unstable) != ZW_OK) {
            return ZW_OK;
        }
        side = bl_split_side(L->box.T, K, &c);
        if (unstable || !bl_halve(&c, side, &cells[live + 1u], &cells[live])) {
            return ZW_OK;
        }
        bc_set_node(bd->cert, pos + n, side);
        n += 1u;
        live += 2u;
    }
    *n_nodes = n;
    *proven = true;
    return ZW_OK;
}

/* The least point K_max at the corners and centre of the box at B (bl_k_max's bracket). */
static zw_status bc_k_upper(const bl_loop *L, zw_loop_workspace *ws, zw_real B, zw_box_loop_bound *best)
{
    const zw_plant_box *f = &L->box;
    const bool stiff = (f->k_hi > ZW_R(0.0));
    int corner;
    for (corner = 0; corner < (stiff ? 9 : 5); ++corner) {
        const bool centre = (corner == 8) || ((corner == 4) && !stiff);
        const zw_real m = centre ? bl_mid(f->m_lo, f->m_hi) : (((corner & 1) != 0) ? f->m_hi : f->m_lo);
        const zw_real b = centre ? bl_mid(f->b_lo, f->b_hi) : (((corner & 2) != 0) ? f->b_hi : f->b_lo);
        const zw_real kp = centre ? bl_mid(f->k_lo, f->k_hi) : (((corner & 4) != 0) ? f->k_hi : f->k_lo);
        const zw_status st = bl_point_k_max(L, ws, m, b, kp, B, best);
        if (st != ZW_OK) {
            return st;
        }
    }
    return ZW_OK;
}

/* Step i's level: bisection between 0 and the point bracket, each try a proof within the
 * budget; the best proof is redone at the end so that its nodes are the ones left. */
static zw_status bc_build_step(bc_builder *bd, unsigned i, unsigned budget, zw_real rel_tol, uint_least32_t *pos,
                               zw_real *K_upper)
{
    zw_box_cert *cert = bd->cert;
    const zw_real B_lo = (zw_real)cert->B[i], B_hi = (zw_real)cert->B[i + 1u];
    zw_box_loop_bound best;
    zw_real lo = ZW_R(0.0), hi;
    uint_least32_t n = 0u;
    bool proven;
    int step;
    zw_status st;
    best.K_upper = ZW_INF;
    st = bc_k_upper(bd->L, bd->ws, B_lo, &best);
    if (st == ZW_OK) {
        st = bc_k_upper(bd->L, bd->ws, bl_mid(B_lo, B_hi), &best);
    }
    if (st == ZW_OK) {
        st = bc_k_upper(bd->L, bd->ws, B_hi, &best);
    }
    if (st != ZW_OK) {
        return st;
    }
    *K_upper = best.K_upper;
    hi = bx_min(best.K_upper, (zw_real)FLT_MAX);
    cert->K[i] = 0.0f;
    for (step = 0; (step < BL_BISECT_STEPS) && (hi - lo > rel_tol * best.K_upper); ++step) {
        const zw_real mid = (lo > ZW_R(0.0)) ? bl_mid(lo, hi) : ZW_R(0.5) * hi;
        const float Kf = bc_float_down(mid);
        if (!(Kf > 0.0f) || !((zw_real)Kf > lo)) {
            break;
        }
        st = bc_prove(bd, (zw_real)Kf, B_lo, B_hi, budget, *pos, &n, &proven);
        if (st != ZW_OK) {
            return st;
        }
        if (proven) {
            lo = (zw_real)Kf;
            cert->K[i] = Kf;
        } else {
            hi = mid;
        }
    }
    if (cert->K[i] > 0.0f) {
        st = bc_prove(bd, (zw_real)cert->K[i], B_lo, B_hi, budget, *pos, &n, &proven);
        if ((st == ZW_OK) && proven) {
            *pos += n;
        } else {
            cert->K[i] = 0.0f;
        }
    }
    return st;
}

static zw_status bc_build(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                          float B_lo, float B_hi, unsigned n_steps, unsigned max_leaves, zw_real rel_tol,
                          const zw_box_loop_work *work, zw_box_cert *cert, zw_box_cert_report *report)
{
    bl_loop L;
    bc_builder bd;
    uint_least32_t pos = 0u;
    unsigned i;
    zw_status st;
    if (ws == NULL) {
        return ZW_ERR_NULL;
    }
    st = bc_setup(&L, box, spec, work);
    if (st != ZW_OK) {
        return st;
    }
    if ((n_steps < 1u) || (n_steps > ZW_BOX_CERT_MAX_STEPS) || (max_leaves < n_steps) ||
        (max_leaves > ZW_BOX_CERT_MAX_LEAVES) || !(B_lo < B_hi) || !(rel_tol >= ZW_R(0.0)) ||
        !(rel_tol < ZW_R(1.0))) {
        return ZW_ERR_ARG;
    }
    cert->n_steps = (uint_least16_t)n_steps;
    for (i = 0u; i <= n_steps; ++i) { /* equal steps, the ends exact */
        const zw_real t = (zw_real)i / (zw_real)n_steps;
        cert->B[i] = (i == n_steps) ? B_hi : (float)((zw_real)B_lo + (t * ((zw_real)B_hi - (zw_real)B_lo)));
        if ((i > 0u) && !(cert->B[i] > cert->B[i - 1u])) {
            return ZW_ERR_ARG;
        }
    }
    for (i = 0u; i < n_steps; ++i) {
        if (!bc_step_ok(&L, cert->B[i], cert->B[i + 1u], 1.0f)) {
            return ZW_ERR_RANGE;
        }
    }
    bd.L = &L;
    bd.ws = ws;
    bd.work = work;
    bd.cert = cert;
    bd.tests = 0u;
    for (i = 0u; i < n_steps; ++i) {
        st = bc_build_step(&bd, i, max_leaves / n_steps, rel_tol, &pos, &report->K_upper[i]);
        if (st != ZW_OK) {
            return st;
        }
        if (!(cert->K[i] > 0.0f)) {
            report->failed_step = (uint_least16_t)i;
            break;
        }
    }
    report->tests = bd.tests;
    if (report->failed_step < ZW_BOX_CERT_MAX_STEPS) {
        return ZW_OK;
    }
    cert->n_nodes = (uint_least16_t)pos;
    while (pos < 4u * ZW_BOX_CERT_NODE_WORDS) { /* a longer failed try's nodes */
        bc_set_node(cert, pos, 0u);
        pos += 1u;
    }
    return ZW_OK;
}

zw_status zw_box_cert_build(const zw_plant_box *box, const zw_device_loop_spec *spec, zw_loop_workspace *ws,
                            float B_lo, float B_hi, unsigned n_steps, unsigned max_leaves, zw_real rel_tol,
                            const zw_box_loop_work *work, zw_box_cert *cert, zw_box_cert_report *report)
{
    unsigned i;
    zw_status st;
    if ((cert == NULL) || (report == NULL)) {
        return ZW_ERR_NULL;
    }
    (void)memset(cert, 0, sizeof(*cert));
    report->tests = 0u;
    report->leaves = 0u;
    report->failed_step = (uint_least16_t)ZW_BOX_CERT_MAX_STEPS;
    for (i = 0u; i < ZW_BOX_CERT_MAX_STEPS; ++i) {
        report->K_upper[i] = ZW_R(0.0);
    }
    st = bc_build(box, spec, ws, B_lo, B_hi, n_steps, max_leaves, rel_tol, work, cert, report);
    if ((st != ZW_OK) || (report->failed_step < ZW_BOX_CERT_MAX_STEPS)) {
        (void)memset(cert, 0, sizeof(*cert));
    }
    if (st == ZW_OK) {
        uint_least32_t j;
        for (j = 0u; j < (uint_least32_t)cert->n_nodes; ++j) {
            report->leaves += (bc_node(cert, j) == ZW_BOX_CERT_LEAF) ? 1u : 0u;
        }
    }
    return st;
}
