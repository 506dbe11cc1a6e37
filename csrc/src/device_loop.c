/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The loop a drive runs, in real units: device.h's conversions, loop.h's checks and
 * loop_limits.h's limits, with the conversions' rounding carried explicitly.
 *
 * Notation: k* = m / T^2 and s* = m / T exactly; dev.k_scale, dev.b_scale their rounded
 * values (relative error <= 2u and u: two and one roundings).  alpha_f = fl(K / k_scale),
 * beta_f = fl(B / b_scale) are within ZW_ALPHA_RELERR = 4u and ZW_BETA_RELERR = 3u of the
 * exact alpha* = K / k*, beta* = B / s* (device.c).
 *
 * Box certificates.  p(z; alpha, beta) = D + alpha Na + beta Nb is affine in the gains and
 * its degree is D's for every gain (Na, Nb have lower degree), so by the edge theorem
 * (Bartlett, Hollot, Huang 1988: a polytope of polynomials of invariant degree is stable
 * for a simply connected region, here the open unit disk, iff its edges are) a closed box
 * of gains is stable iff its four edges are.  An edge is proved stable by
 *   - a certified limit along it (zw_loop_alpha_max on a vertical line, zw_loop_beta_interval
 *     on a horizontal one: every point inside is proved stable), or
 *   - one zw_loop_check on the loop whose gain error bounds (carried at init) cover the
 *     whole edge: a segment alpha_f (1 +- ea) or beta_f (1 +- eb) is a set of gains the
 *     guarded check proves stable all at once.
 */
#include "zwidth/device_loop.h"

#include <stddef.h>
#include <string.h>

#include "zwidth/loop_limits.h"
#include "internal.h"

/* The gain errors carried into the loop: the conversion's, plus 4u of room so that the
 * intervals below (rounded outward by 2u) lie inside what one check covers. */
#define GAIN_ALPHA_RELERR (ZW_ALPHA_RELERR + ZW_R(4.0) * ZW_U)
#define GAIN_BETA_RELERR (ZW_BETA_RELERR + ZW_R(4.0) * ZW_U)
/* Scaling a normalized limit x to real units: fl(x scale) errs by <= 3u + u against
 * x * (exact scale); one more factor (1 -+ 8u), itself rounded, pulls it inward. */
#define SCALE_INWARD (ZW_R(8.0) * ZW_U)

/* Relative retreats from a certified limit tried by the edge checks: the limit may sit
 * inside the check's rounding band (loop.h: up to 1e5 ulps), so back off until one is
 * proved.  0 first: most limits are proved where they are. */
#define N_RETREATS 8u
static const zw_real k_retreat[N_RETREATS] = {
    ZW_R(0.0), ZW_R(1e-13), ZW_R(1e-10), ZW_R(1e-7), ZW_R(1e-5), ZW_R(1e-3), ZW_R(1e-2), ZW_R(0.1)};

/* The loop spec of a device spec at period T (the low-pass pole from its cut-off). */
static zw_status loop_spec_of(const zw_device_loop_spec *spec, zw_real T, zw_loop_spec *ls)
{
    zw_status st;
    /* zeroed padding too: the loop keeps a copy, and a map rebuilt from the same block must
     * be the same bytes (test_regmap compares the whole struct after a refused SEAL) */
    (void)memset(ls, 0, sizeof *ls);
    ls->delay = spec->delay;
    ls->differentiator = spec->differentiator;
    ls->filter = spec->filter;
    ls->average = spec->average;
    ls->filter_pole = spec->pole;
    if ((spec->filter == ZW_VFILTER_LOWPASS) && !(spec->cutoff_hz == ZW_R(0.0))) {
        st = zw_loop_lowpass_pole(spec->cutoff_hz, T, &ls->filter_pole);
        if (st != ZW_OK) {
            return st;
        }
    }
    return ZW_OK;
}

static zw_status device_loop_init(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                                  const zw_device_loop_spec *spec)
{
    zw_loop_spec ls;
    zw_status st;
    out->mass_relerr = ZW_R(0.0);
    st = zw_device_init(&out->dev, m, b, T);
    if (st != ZW_OK) {
        return st;
    }
    st = loop_spec_of(spec, T, &ls);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_loop_init(&out->loop, &out->dev.co, &ls);
    if (st != ZW_OK) {
        return st;
    }
    return zw_loop_carry_gain_rounding(&out->loop, GAIN_ALPHA_RELERR, GAIN_BETA_RELERR);
}

static zw_status device_loop_init_plant(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                                        zw_real k_p, zw_real tau, zw_real m_h, zw_real b_h,
                                        zw_real k_h, const zw_device_loop_spec *spec)
{
    zw_plant_spec ps;
    zw_loop_spec ls;
    zw_real M = ZW_R(0.0);
    zw_status st;
    st = zw_plant_spec_from_device(m, b, T, k_p, tau, m_h, b_h, k_h, &ps, &M);
    if (st != ZW_OK) {
        return st;
    }
    /* M = fl(m + m_h): one rounding against the exact mass (none without a hand) */
    out->mass_relerr = (m_h == ZW_R(0.0)) ? ZW_R(0.0) : ZW_U;
    st = zw_device_init(&out->dev, M, b + b_h, T);
    if (st != ZW_OK) {
        return st;
    }
    st = loop_spec_of(spec, T, &ls);
    if (st != ZW_OK) {
        return st;
    }
    /* the plant is built in place (too large for a firmware caller's stack) */
    st = zw_plant_init(&out->loop.plant, &ps);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_loop_init_plant(&out->loop, &out->loop.plant, &ls);
    if (st != ZW_OK) {
        return st;
    }
    return zw_loop_carry_gain_rounding(&out->loop, GAIN_ALPHA_RELERR + ZW_R(2.0) * out->mass_relerr,
                                       GAIN_BETA_RELERR + ZW_R(2.0) * out->mass_relerr);
}

zw_status zw_device_loop_init_plant(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                                    zw_real k_p, zw_real tau, zw_real m_h, zw_real b_h,
                                    zw_real k_h, const zw_device_loop_spec *spec)
{
    static const zw_loop k_no_loop; /* zero: degree 0, refused by every loop function */
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = (spec == NULL) ? ZW_ERR_NULL
                        : device_loop_init_plant(out, m, b, T, k_p, tau, m_h, b_h, k_h, spec);
    if (st != ZW_OK) {
        (void)zw_device_init(&out->dev, ZW_NAN, ZW_NAN, ZW_NAN); /* every field NaN */
        out->loop = k_no_loop;
        out->mass_relerr = ZW_R(0.0);
    }
    return st;
}

zw_status zw_device_loop_init(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                              const zw_device_loop_spec *spec)
{
    static const zw_loop k_no_loop; /* zero: degree 0, refused by every loop function */
    zw_status st;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    st = (spec == NULL) ? ZW_ERR_NULL : device_loop_init(out, m, b, T, spec);
    if (st != ZW_OK) {
        (void)zw_device_init(&out->dev, ZW_NAN, ZW_NAN, ZW_NAN); /* every field NaN */
        out->loop = k_no_loop;
        out->mass_relerr = ZW_R(0.0);
    }
    return st;
}

/* The normalized gains of (K, B).  The loop's guard carries the conversion as a relative
 * error (GAIN_*_RELERR), which only a normal result has: a non-zero gain whose normalized
 * value underflows (subnormal, or 0 with beta* != 0 below) is ZW_ERR_RANGE, as in
 * zw_device_init.  So alpha == 0 iff K == 0 and beta == 0 iff B == 0. */
static zw_status gains(const zw_device_loop *dl, zw_real K, zw_real B, zw_real *alpha, zw_real *beta)
{
    zw_status st;
    if (dl == NULL) {
        return ZW_ERR_NULL;
    }
    st = zw_device_normalize(&dl->dev, K, B, alpha, beta);
    if (st != ZW_OK) {
        return st;
    }
    if (((K != ZW_R(0.0)) && !(ZW_FABS(*alpha) >= ZW_REAL_MIN)) ||
        ((B != ZW_R(0.0)) && !(ZW_FABS(*beta) >= ZW_REAL_MIN))) {
        return ZW_ERR_RANGE;
    }
    return ZW_OK;
}

zw_status zw_device_loop_check(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                               zw_real B, zw_loop_verdict *out)
{
    zw_real alpha, beta;
    zw_status st = gains(dl, K, B, &alpha, &beta);
    if (st != ZW_OK) {
        zw_fail_loop_verdict(out);
        return st;
    }
    return zw_loop_check(&dl->loop, ws, alpha, beta, out);
}

zw_status zw_device_loop_is_stable(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                                   zw_real B, bool *stable)
{
    zw_real alpha, beta;
    zw_status st = gains(dl, K, B, &alpha, &beta);
    if (st != ZW_OK) {
        zw_fail_bool(stable);
        return st;
    }
    return zw_loop_is_stable(&dl->loop, ws, alpha, beta, stable);
}

zw_status zw_device_loop_radius_within(const zw_device_loop *dl, zw_loop_workspace *ws,
                                       zw_real K, zw_real B, zw_real r, bool *within)
{
    zw_real alpha, beta;
    zw_status st = gains(dl, K, B, &alpha, &beta);
    if (st != ZW_OK) {
        zw_fail_bool(within);
        return st;
    }
    return zw_loop_radius_within(&dl->loop, ws, alpha, beta, r, within);
}

zw_status zw_device_loop_spectral_radius(const zw_device_loop *dl, zw_loop_workspace *ws,
                                         zw_real K, zw_real B, zw_real *rho, zw_real *theta)
{
    zw_real alpha, beta;
    zw_status st = gains(dl, K, B, &alpha, &beta);
    if (st != ZW_OK) {
        zw_fail_real(rho, ZW_INF);
        zw_fail_real(theta, ZW_R(0.0));
        return st;
    }
    return zw_loop_spectral_radius(&dl->loop, ws, alpha, beta, rho, theta);
}

/* x scale, rounded toward zero past every rounding (x and the exact scale both >= 0 or x
 * of either sign: the magnitude shrinks). */
static zw_real scale_inward(zw_real x, zw_real scale)
{
    return (x * scale) * (ZW_R(1.0) - SCALE_INWARD);
}

/* x scale, rounded away from zero past every rounding (callers pick by x's sign). */
static zw_real scale_outward(zw_real x, zw_real scale)
{
    return (x * scale) * (ZW_R(1.0) + SCALE_INWARD);
}

/* A certified lower end lo of a beta range, to real units and pulled up: the B returned
 * is >= lo s* (so B / s* >= lo). */
static zw_real lower_to_real(zw_real lo, zw_real scale)
{
    return (lo >= ZW_R(0.0)) ? scale_outward(lo, scale) : scale_inward(lo, scale);
}

/* An upper end hi, pulled down: B <= hi s*. */
static zw_real upper_to_real(zw_real hi, zw_real scale)
{
    return (hi >= ZW_R(0.0)) ? scale_inward(hi, scale) : scale_outward(hi, scale);
}

/* [x (1 - rel), x (1 + rel)] rounded outward: 2u of room covers the roundings of w and of
 * the sums (each <= u of |x|). */
static void widen_by(zw_real x, zw_real rel, zw_real *lo, zw_real *hi)
{
    const zw_real w = ZW_FABS(x) * (rel + ZW_R(2.0) * ZW_U);
    *lo = x - w;
    *hi = x + w;
}

static bool proved_stable(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta)
{
    bool stable; /* written by zw_loop_is_stable on every path */
    const zw_status st = zw_loop_is_stable(loop, ws, alpha, beta, &stable);
    return (st == ZW_OK) && stable;
}

/* The first of A (1 - k_retreat[i]) that one check at (., beta) proves stable, else 0. */
static zw_real retreat_alpha(const zw_loop *loop, zw_loop_workspace *ws, zw_real A, zw_real beta)
{
    unsigned i;
    if (A > ZW_R(0.0)) {
        for (i = 0u; i < N_RETREATS; ++i) {
            const zw_real At = A * (ZW_R(1.0) - k_retreat[i]);
            if (proved_stable(loop, ws, At, beta)) {
                return At;
            }
        }
    }
    return ZW_R(0.0);
}

/* [*lo, *hi] pulled inward by (hi - lo) k_retreat[i] at both ends, for the first i whose
 * two ends one check each at alpha proves stable; false (and unchanged) when none is. */
static bool retreat_range(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real *lo,
                          zw_real *hi)
{
    const zw_real lo0 = *lo, hi0 = *hi, w = hi0 - lo0;
    unsigned i;
    for (i = 0u; i < N_RETREATS; ++i) {
        const zw_real l = lo0 + w * k_retreat[i], h = hi0 - w * k_retreat[i];
        if ((l < h) && (l >= lo0) && (h <= hi0) && proved_stable(loop, ws, alpha, l) &&
            proved_stable(loop, ws, alpha, h)) {
            *lo = l;
            *hi = h;
            return true;
        }
    }
    return false;
}

/* Why K_max(B) below is never above the true k* alpha_max(beta*).
 * beta* lies in [b_lo, b_hi] = beta_f (1 -+ (3u + 2u)), rounded outward.  With
 * A = min(alpha_max(b_lo), alpha_max(b_hi)) (each certified) and At <= A:
 *  1. the two vertical sides {b_lo, b_hi} x (0, At] are stable (certified limits);
 *  2. the top edge [b_lo, b_hi] x {At} is stable: one check at (At, beta_f) on the loop
 *     whose beta error (3u + 4u) covers it (retreating At until it is proved);
 *  3. so no boundary curve of the region meets the three sides.  The z = -1 boundary is a
 *     line: entering the open box it would leave it through a second boundary point, and
 *     with the three sides excluded both would lie on alpha = 0, so the line would be
 *     alpha = 0 and not enter.  A complex-pair arc (alpha(theta), beta(theta)) is a curve
 *     whose ends are at theta -> 0 (the corner (0, -delta)), theta -> pi (on the z = -1
 *     line: not inside, by the above) or at infinity (asymptotes): entering the box it
 *     leaves it, through alpha = 0 only.  That needs p(z; 0, beta) = (z - 1) q(z; beta) to
 *     have a unit-circle pair at two betas inside the 5u-wide [b_lo, b_hi]: corners of the
 *     region on alpha = 0, where the stable alphas at b_lo and b_hi themselves shrink to
 *     within rounding of 0.  Outside that degenerate case every (alpha, beta) in
 *     (0, At) x [b_lo, b_hi] is stable, so the true sup at beta* is >= At.
 *  4. K < K_max = fl(At k_scale)(1 - 8u) gives alpha* = K / k* < At (k_scale's and the
 *     products' roundings are < 8u).
 * B = 0 is exact (beta* = 0): the certified alpha_max(0) directly, no box. */
static zw_status k_max(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real B, zw_real *K_max)
{
    zw_real alpha, beta, b_lo, b_hi, a_lo, a_hi, A, K;
    zw_status st;
    if (K_max == NULL) {
        return ZW_ERR_NULL;
    }
    st = gains(dl, ZW_R(0.0), B, &alpha, &beta);
    if (st != ZW_OK) {
        return st;
    }
    if (beta == ZW_R(0.0)) {
        st = zw_loop_alpha_max(&dl->loop, ws, ZW_R(0.0), &A);
        if (st != ZW_OK) {
            return st;
        }
    } else {
        widen_by(beta, ZW_BETA_RELERR + ZW_R(2.0) * dl->mass_relerr, &b_lo, &b_hi);
        st = zw_loop_alpha_max(&dl->loop, ws, b_lo, &a_lo);
        if (st != ZW_OK) {
            return st;
        }
        st = zw_loop_alpha_max(&dl->loop, ws, b_hi, &a_hi);
        if (st != ZW_OK) {
            return st;
        }
        A = retreat_alpha(&dl->loop, ws, (a_lo < a_hi) ? a_lo : a_hi, beta);
    }
    K = scale_inward(A, dl->dev.k_scale);
    if (!ZW_IS_FINITE(K)) {
        return ZW_ERR_RANGE;
    }
    *K_max = (K > ZW_R(0.0)) ? K : ZW_R(0.0);
    return ZW_OK;
}

zw_status zw_device_loop_k_max(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real B,
                              zw_real *K_max)
{
    zw_status st = k_max(dl, ws, B, K_max);
    if (st != ZW_OK) {
        zw_fail_real(K_max, ZW_R(0.0));
    }
    return st;
}

/* The B range at K: alpha* lies in [a_lo, a_hi] = alpha_f (1 -+ (4u + 2u)), alpha_f > 0.
 * [lo, hi] = the intersection of the widest certified beta intervals at a_lo and at a_hi,
 * retreated inward until the vertical sides {lo, hi} x [a_lo, a_hi] are each proved by one
 * check at alpha_f (the loop's alpha error, 4u + 4u, covers them).  The top and bottom
 * edges lie inside certified intervals, so all four edges of the closed box
 * [lo, hi] x [a_lo, a_hi] are stable and so is the box (edge theorem; alpha > 0, so no
 * corner of the region on alpha = 0 is involved).  Then B in [B_lo, B_hi] with
 * B_lo >= lo s*, B_hi <= hi s* has beta* = B / s* in [lo, hi]. */
static zw_status loop_b_range(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                              zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    zw_real alpha, beta, a_lo, a_hi, l1, h1, l2, h2, lo, hi, Bl, Bh;
    bool ok1, ok2;
    zw_status st;
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return ZW_ERR_NULL;
    }
    st = gains(dl, K, ZW_R(0.0), &alpha, &beta);
    if (st != ZW_OK) {
        return st;
    }
    *B_lo = ZW_R(0.0);
    *B_hi = ZW_R(0.0);
    *nonempty = false;
    if (!(alpha > ZW_R(0.0))) { /* empty, but an empty loop is still refused */
        st = zw_loop_beta_interval(&dl->loop, ws, alpha, &l1, &h1, &ok1);
        return st;
    }
    widen_by(alpha, ZW_ALPHA_RELERR + ZW_R(2.0) * dl->mass_relerr, &a_lo, &a_hi);
    if (!(a_lo > ZW_R(0.0))) {
        return ZW_OK;
    }
    st = zw_loop_beta_interval(&dl->loop, ws, a_lo, &l1, &h1, &ok1);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_loop_beta_interval(&dl->loop, ws, a_hi, &l2, &h2, &ok2);
    if (st != ZW_OK) {
        return st;
    }
    if (!ok1 || !ok2) {
        return ZW_OK;
    }
    lo = (l1 > l2) ? l1 : l2;
    hi = (h1 < h2) ? h1 : h2;
    if (!(lo < hi)) {
        return ZW_OK;
    }
    if (!retreat_range(&dl->loop, ws, alpha, &lo, &hi)) {
        return ZW_OK;
    }
    Bl = lower_to_real(lo, dl->dev.b_scale);
    Bh = upper_to_real(hi, dl->dev.b_scale);
    if (!ZW_IS_FINITE(Bl) || !ZW_IS_FINITE(Bh)) {
        return ZW_ERR_RANGE;
    }
    if (Bl < Bh) {
        *B_lo = Bl;
        *B_hi = Bh;
        *nonempty = true;
    }
    return ZW_OK;
}

zw_status zw_device_loop_b_range(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                                 zw_real *B_lo, zw_real *B_hi, bool *nonempty)
{
    zw_status st = loop_b_range(dl, ws, K, B_lo, B_hi, nonempty);
    if (st != ZW_OK) {
        zw_fail_interval(B_lo, B_hi, nonempty);
    }
    return st;
}

/* The extremes are sups / infs over all gains of the exact region, so only the scales'
 * rounding matters: each is pulled inward past it. */
static zw_status extremes(const zw_device_loop *dl, zw_loop_workspace *ws,
                          zw_device_loop_extremes *out)
{
    zw_loop_extremes x;
    zw_status st;
    zw_real v[5];
    unsigned i;
    if ((dl == NULL) || (out == NULL)) {
        return ZW_ERR_NULL;
    }
    /* refuses a device a failed init left NaN */
    st = zw_device_normalize(&dl->dev, ZW_R(0.0), ZW_R(0.0), &v[0], &v[1]);
    if (st != ZW_OK) {
        return st;
    }
    st = zw_loop_extremes_compute(&dl->loop, ws, &x);
    if (st != ZW_OK) {
        return st;
    }
    v[0] = scale_inward(x.alpha_mmax, dl->dev.k_scale);
    v[1] = x.beta_at_alpha_mmax * dl->dev.b_scale;
    v[2] = scale_inward(x.alpha_p_max, dl->dev.k_scale);
    v[3] = upper_to_real(x.beta_mmax, dl->dev.b_scale);
    v[4] = lower_to_real(x.beta_mmin, dl->dev.b_scale);
    for (i = 0u; i < 5u; ++i) {
        if (!ZW_IS_FINITE(v[i])) {
            return ZW_ERR_RANGE;
        }
    }
    out->K_mmax = v[0];
    out->B_at_K_mmax = v[1];
    out->K_p_max = v[2];
    out->B_mmax = v[3];
    out->B_mmin = v[4];
    return ZW_OK;
}

zw_status zw_device_loop_extremes_compute(const zw_device_loop *dl, zw_loop_workspace *ws,
                                          zw_device_loop_extremes *out)
{
    zw_status st = extremes(dl, ws, out);
    if ((st != ZW_OK) && (out != NULL)) {
        out->K_mmax = ZW_R(0.0);
        out->B_at_K_mmax = ZW_R(0.0);
        out->K_p_max = ZW_R(0.0);
        out->B_mmax = ZW_R(0.0);
        out->B_mmin = ZW_R(0.0);
    }
    return st;
}
