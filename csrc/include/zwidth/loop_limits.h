/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/loop_limits.h - limits of the general loop (loop.h) by D-decomposition.
 *
 * p(z) = D + alpha Na + beta Nb (loop.h).  A root crosses the unit circle only at z = 1,
 * z = -1 or a pair e^{+-j theta}.  Dividing p by (c1 z + c2) Dv, a pair crosses where
 *     alpha + beta V(z) = W(z),   W = -2 z^d (z - 1)(z - e) / (c1 z + c2),  V = Nv / Dv,
 * and writing W = (z - 1) Q0, V = (z - 1) Vt (every velocity estimate has the factor
 * z - 1), with R0 = e^{j theta/2} Q0 and S = e^{j theta/2} Vt:
 *     Re R0 = beta Re S,    alpha = -2 sin(theta/2) (Im R0 - beta Im S).
 * Both factors are evaluated in factored form (z - e = (z - 1) + (1 - e) with
 * 1 - e = delta (c1 + c2)/2, c1 z + c2 = c1 (z + 1) - d12, z - 1 = 2j sin(theta/2)
 * e^{j theta/2}), so they keep their relative accuracy for small delta and near z = +-1,
 * where the expanded coefficients of D, Na, Nb cancel.
 *   z = 1:  p(1) = alpha (c1 + c2) Dv(1): the line alpha = 0 (the plant integrates).
 *   z = -1: the line  c0 + ca alpha + cb beta = 0  (zw_loop_boundary_line).
 * A general plant N / D (zw_loop_init_plant: a lag, a spring, a hand): W = -z^d D / N and
 * R0 = W / (2 j sin(theta/2)) from the plant's bilinear images at s = j tan(theta/2)
 * (loop_limits.c, general_r0), with a relative error bound per point from the images'
 * coefficient bounds; with stiffness (kappa > 0) the z = 1 line is alpha = -kappa
 * (p(1) = Dv(1) (D(1) + alpha N(1))), R0 grows like 1 / theta and the scan starts from its
 * limit at theta -> 0+; "as alpha -> 0+" (extremes) is then the line alpha = 0 itself.  The
 * ideal plant keeps the factored response below (bit for bit the results it always had).
 *
 * Limits are found as the first crossing of a line (beta fixed, or alpha fixed) with these
 * curves: the crossing condition is scanned on a theta grid (uniform, refined
 * geometrically towards 0 and pi), sign changes are bisected, and local minima of its
 * magnitude are searched for a hidden pair of roots (a near-tangency); a root that cannot
 * be told from zero within the evaluation's error bound is kept as a crossing.  Each
 * crossing is reported as an interval certain to contain the exact one (from an
 * error bound on the evaluation that includes the coefficients' own error, ZW_COEF_ULPS,
 * and delta_relerr), and a limit takes the inner end of that interval.  The cell the limit
 * bounds is then labelled by zw_loop_check at interior points (the root count is constant
 * in a cell), so a limit is returned only where the guarded check proves stability.
 * The grid search is not itself a proof that no pair of crossings hides between two grid
 * points; the interior checks (seven per alpha_max) are the safety net against it.
 *
 * Where the crossing condition vanishes structurally (theta = 0: the double root at z = 1,
 * the region's corner (0, -delta); theta = pi: z = -1, where the curve ends on the z = -1
 * line, the corner of the extremes above delta1 and of most delayed loops) the corner
 * itself is computed separately (the line; beta = -delta; the double root at z = -1).
 *
 * Accuracy (measured against mpmath at 50 digits, tests/py/test_loop_limits_reference.py
 * and tests/c/test_loop_limits.c): a certified limit sits below the truth by its error
 * bound times the crossing's conditioning, about 1e-13 relative in double where the
 * boundary is well-conditioned (1000-4000 u times the gains' scale (1 + delta + |beta|),
 * over sqrt(delta) for small delta: 1.1e-10 relative at delta = 1e-6); float likewise in
 * its own u (1e-4 relative, 4 % at delta = 1e-6).  The ideal loop's extremes through this
 * path: alpha_mmax within 2e-13, beta_mmax within 1.4e-13 (4e-9 at delta0, where the pair
 * closing the range sits at z = -1) of the closed forms.
 *
 * Fail-safe outputs: on every error each limit is written as one that certifies nothing
 * (alpha_max = 0, empty intervals, extremes all 0, count 0).
 *
 * Firmware part: no heap, no recursion, fixed sizes, bounded iteration counts.  Costs (host,
 * x86-64): alpha_max 0.02-0.06 ms (degree 3-4) to 1-5 ms (degree 26); extremes 1-14 ms, 0.1-0.5 s at
 * degree 26 (a commissioning-time computation, not a control-loop one).  Stack (worst chain,
 * Cortex-M4F float, -Os, tools/footprint.sh, gated): alpha_max 496 B, beta intervals 480 /
 * 488 B, extremes 512 B, within the 512 B: the check's arrays and the scan's, walk's
 * and extremes' state are in the caller's zw_loop_workspace.
 * ws: the caller's scratch (loop.h); ZW_ERR_NULL when NULL.
 */
#ifndef ZWIDTH_LOOP_LIMITS_H
#define ZWIDTH_LOOP_LIMITS_H

#include <stdbool.h>

#include "zwidth/loop.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most stable beta intervals zw_loop_beta_intervals reports at one alpha. */
#define ZW_LOOP_MAX_INTERVALS 4u

/* sup of the stable interval (0, alpha_max) on the vertical line beta = const: every alpha
 * in (0, *alpha_max) is stable (certified), and *alpha_max is never above the true sup.
 * 0 when alpha just above 0 is not stable (or cannot be proved so).
 * Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF (beta), ZW_ERR_ARG (uninitialized loop),
 * ZW_ERR_RANGE (delta too large for the factored response).  *alpha_max = 0 on error. */
zw_status zw_loop_alpha_max(const zw_loop *loop, zw_loop_workspace *ws, zw_real beta,
                            zw_real *alpha_max);

/* The stable beta intervals on the horizontal line alpha = const (> 0), in increasing
 * order.  For the ideal loop there is one; a general loop may have several (the region
 * need not be convex in beta).  Each reported (lo, hi) is inside a stable interval
 * (certified: lo >= true lo, hi <= true hi, every beta in between stable).  Intervals
 * unbounded in beta are not reported (they do not occur for the loops of loop.h: large
 * |beta| always destabilizes).  truncated: more than ZW_LOOP_MAX_INTERVALS exist (the
 * lowest ones are reported). */
typedef struct zw_loop_beta_set {
    unsigned count;
    bool truncated;
    zw_real lo[ZW_LOOP_MAX_INTERVALS];
    zw_real hi[ZW_LOOP_MAX_INTERVALS];
} zw_loop_beta_set;

/* Errors: as zw_loop_alpha_max (for alpha).  count = 0 (and every entry 0) on error and
 * when alpha <= 0. */
zw_status zw_loop_beta_intervals(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                 zw_loop_beta_set *out);

/* The widest of those intervals (the one a drive tuning B at fixed K has most room in);
 * *nonempty false and lo = hi = 0 when there is none or on error. */
zw_status zw_loop_beta_interval(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real *lo, zw_real *hi, bool *nonempty);

/* Extremes of the general loop (all certified: never beyond the true values).
 *   alpha_mmax: max over beta of zw_loop_alpha_max, attained (as a certified limit) at
 *     beta_at_alpha_mmax (golden-section search on a grid over each stable beta range,
 *     so a maximum between grid humps could be missed: the value is still certified);
 *     searched over the beta stable as alpha -> 0+ only: a filtered loop's region can lean
 *     past beta = -delta where the stable alphas no longer reach down to 0 (measured:
 *     delta = 5.12241, d = 1, low-pass at f_c T = 0.05: stable at (6, -5.62)); such parts
 *     are not limits of the form (0, K_max) and are not searched (conservative);
 *   alpha_p_max: zw_loop_alpha_max(0) (proportional control);
 *   beta_mmax, beta_mmin: sup and inf of the beta stable as alpha -> 0+
 *     (beta_mmin >= true inf, beta_mmax <= true sup; ideal loop: -delta and eq (32)). */
typedef struct zw_loop_extremes {
    zw_real alpha_mmax;
    zw_real beta_at_alpha_mmax;
    zw_real alpha_p_max;
    zw_real beta_mmax;
    zw_real beta_mmin;
} zw_loop_extremes;

/* Errors: ZW_ERR_NULL, ZW_ERR_ARG, ZW_ERR_DOMAIN (no beta is stable as alpha -> 0+: no
 * gains are stable, e.g. Tustin with an even average).  Every field 0 on error. */
zw_status zw_loop_extremes_compute(const zw_loop *loop, zw_loop_workspace *ws,
                                   zw_loop_extremes *out);

/* The complex-pair boundary curve at angle theta in (0, pi) (rad per sample): the one
 * (alpha, beta) at which p has the roots e^{+-j theta}.  ZW_ERR_DOMAIN where the 2x2 system
 * is singular (Re S = 0 within its error: the curve has an asymptote there, or at
 * delta = 0 / Tustin near theta = pi); ZW_ERR_ARG for theta outside (0, pi) or an
 * uninitialized loop; ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF.  Informational (plots); 0, 0 on
 * error. */
zw_status zw_loop_boundary_point(const zw_loop *loop, zw_real theta, zw_real *alpha,
                                 zw_real *beta);

/* The line where p has a root at z = 1 (which = ZW_LOOP_BOUNDARY_Z_PLUS1) or z = -1
 * (ZW_LOOP_BOUNDARY_Z_MINUS1), as c0 + ca alpha + cb beta = 0 (up to a common factor).
 * All three 0: p(-1) vanishes identically (Tustin with an even moving average, or Tustin at
 * delta = 0): z = -1 is always a root and no gains are stable.  ca = cb = 0, c0 != 0: no
 * root at z = -1 for any gains (delta = 0).  Errors: ZW_ERR_NULL, ZW_ERR_ARG (other
 * which, uninitialized loop); all 0 on error. */
zw_status zw_loop_boundary_line(const zw_loop *loop, zw_loop_boundary which, zw_real *c0,
                                zw_real *ca, zw_real *cb);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_LOOP_LIMITS_H */
