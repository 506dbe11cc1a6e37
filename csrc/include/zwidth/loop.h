/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/loop.h - the loop a real drive runs: delay, velocity filters, differentiators.
 *
 * The paper's loop applies F_k = -(K x_k + B v_k) at once, with v_k the backward
 * difference.  A drive adds a delay of d samples (the force computed from x_k is applied
 * over [(k+d)T, (k+d+1)T)) and estimates the velocity differently.  In normalized units
 * (delta = bT/m, alpha = KT^2/m, beta = BT/m) the sampled plant is
 *     x/F = (c1 z + c2) / (2 (z - 1)(z - e))          (times T^2/m; coeffs.h)
 * and the velocity estimate is T V(z) = Nv(z) / Dv(z):
 *     backward difference        (z - 1) / z
 *     Tustin                     2 (z - 1) / (z + 1)
 *     low-pass (pole a) on it    (1 - a) z / (z - a)            times the differentiator
 *     moving average over n      (1/n) sum_{i<n} z^-i           times the differentiator
 *                                (backward: (z^n - 1) / (n z^n))
 * so the closed loop's characteristic polynomial is affine in (alpha, beta):
 *     p(z) = D(z) + alpha Na(z) + beta Nb(z)
 *     D  = 2 z^d (z - 1)(z - e) Dv(z),  Na = (c1 z + c2) Dv(z),  Nb = (c1 z + c2) Nv(z)
 * (d = 0 with the backward difference gives the paper's cubic, eqs (7), (8)).  See
 * shared notes general-loop.md and docs/numerics.md for the derivation and its checks.
 *
 * A zero-initialized zw_loop_spec is the paper's ideal loop.
 *
 * Safety, as for the ideal loop: a verdict says stable only if every root is inside the
 * unit circle for every value within the rounding error bound of the computation
 * (including the coefficient functions' own error, ZW_COEF_ULPS, and delta_relerr); a
 * stable point is called unstable only within that band, and then marginal = true.  A
 * limit (alpha_max, beta interval, extremes) is never above the true one.
 *
 * Fail-safe outputs: on every error, a verdict output is written as not stable
 * (stable = false) and a limit output as one that certifies nothing (0, an empty range),
 * so a caller that ignores the status can never read "stable".
 */
#ifndef ZWIDTH_LOOP_H
#define ZWIDTH_LOOP_H

#include <stdbool.h>

#include "zwidth/coeffs.h"
#include "zwidth/plant.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ZW_LOOP_MAX_DELAY 8u    /* d in 0..8 samples */
#define ZW_LOOP_MAX_AVERAGE 16u /* moving average over n in 1..16 samples */
/* Plant (2, or 3 with an actuator lag) + delay + velocity estimate (at most
 * ZW_LOOP_MAX_AVERAGE). */
#define ZW_LOOP_MAX_DEGREE (ZW_PLANT_MAX_ORDER + ZW_LOOP_MAX_DELAY + ZW_LOOP_MAX_AVERAGE)

typedef enum zw_differentiator {
    ZW_DIFF_BACKWARD = 0, /* v_k = (x_k - x_{k-1}) / T (the paper's) */
    ZW_DIFF_TUSTIN = 1    /* v_k = (2/T)(x_k - x_{k-1}) - v_{k-1} */
} zw_differentiator;

typedef enum zw_velocity_filter {
    ZW_VFILTER_NONE = 0,
    ZW_VFILTER_LOWPASS = 1, /* vf_k = a vf_{k-1} + (1 - a) v_k, a = filter_pole in [0, 1) */
    ZW_VFILTER_AVERAGE = 2  /* mean of the last n differentiator outputs, n = average */
} zw_velocity_filter;

/* What the drive runs.  filter_pole is used by LOWPASS only, average by AVERAGE only.
 * The pole is taken as exact: the drive's filter multiplies by its own stored a, so the
 * certificate is for that a (zw_loop_lowpass_pole gives it from a cut-off). */
typedef struct zw_loop_spec {
    unsigned delay;                   /* d, 0..ZW_LOOP_MAX_DELAY */
    zw_differentiator differentiator;
    zw_velocity_filter filter;
    zw_real filter_pole;              /* a, LOWPASS */
    unsigned average;                 /* n, AVERAGE */
} zw_loop_spec;

/* a = exp(-2 pi f_c T) for a cut-off f_c [Hz] at period T [s].  Errors: ZW_ERR_NULL,
 * ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_PERIOD (T <= 0), ZW_ERR_FILTER (f_c <= 0,
 * f_c >= 1 / (2 T), the Nyquist frequency, or so low that a rounds to 1).  *a = 0 on error. */
zw_status zw_loop_lowpass_pole(zw_real f_c, zw_real T, zw_real *a);

/* The loop for one plant: the three polynomial parts, each coefficient with a bound on
 * its absolute error against the exact value (from e, c1, c2's own error and delta_relerr
 * and every rounding of the construction).  Coefficients are stored highest power first
 * (index 0 is z^degree), like zw_char_poly.  Filled by zw_loop_init; read-only after. */
typedef struct zw_loop {
    zw_coeffs c;     /* the ideal plant's coefficients at the plant's delta (plant.c) */
    zw_loop_spec spec;
    unsigned degree; /* order + d + 1 (backward, Tustin, backward + low-pass), order + d + 2
                        (Tustin + low-pass), order + d + n (moving average over n); order 2,
                        3 with a lag */
    zw_real D[ZW_LOOP_MAX_DEGREE + 1u], D_err[ZW_LOOP_MAX_DEGREE + 1u];
    zw_real Na[ZW_LOOP_MAX_DEGREE + 1u], Na_err[ZW_LOOP_MAX_DEGREE + 1u];
    zw_real Nb[ZW_LOOP_MAX_DEGREE + 1u], Nb_err[ZW_LOOP_MAX_DEGREE + 1u];
    /* The same parts after the bilinear map z = (1 + s)/(1 - s), times (1 - s)^degree
     * (highest power of s first): p is Schur stable iff P = Ds + alpha Nas + beta Nbs is
     * Hurwitz of full degree.  Each factor is formed without cancellation (z - e becomes
     * (1 + e) s + (1 - e) with 1 - e = delta (c1 + c2)/2, c1 z + c2 becomes d12 s + c1 + c2),
     * so small delta keeps full relative accuracy here, unlike in the z coefficients. */
    zw_real Ds[ZW_LOOP_MAX_DEGREE + 1u], Ds_err[ZW_LOOP_MAX_DEGREE + 1u];
    zw_real Nas[ZW_LOOP_MAX_DEGREE + 1u], Nas_err[ZW_LOOP_MAX_DEGREE + 1u];
    zw_real Nbs[ZW_LOOP_MAX_DEGREE + 1u], Nbs_err[ZW_LOOP_MAX_DEGREE + 1u];
    /* Relative error bounds of the gains the checks will be given (0 from zw_loop_init:
     * exact gains; zw_loop_carry_gain_rounding sets them, e.g. for gains converted from
     * real units).  Read by the factored evaluation of p; the coefficient parts carry them
     * in their own bounds. */
    zw_real alpha_relerr, beta_relerr;
    /* The sampled plant N / D (plant.h) the parts were built from: its factored evaluation
     * (the root test's p) and its bilinear images (the D-decomposition) are read from here. */
    zw_plant plant;
} zw_loop;

/* A complex number of the workspace below (its roots). */
typedef struct zw_loop_complex {
    zw_real re, im;
} zw_loop_complex;

/* A complex value with a bound on its absolute error (the workspace's root test). */
typedef struct zw_loop_ceb {
    zw_loop_complex v;
    zw_real e;
} zw_loop_ceb;

/* Scratch memory of the checks and limits of the general loop: the arrays of the maximum
 * degree (Routh / Schur-Cohn rows with their error bounds, Aberth roots, inclusion radii)
 * that would otherwise sit on the stack (the 512 B stack target at the maximum
 * degree: tools/footprint.sh).  Passed to every function of loop.h, loop_limits.h and
 * device_loop.h that can reach the guarded check.
 *   - Owned by the caller: static storage, a task's own memory, a struct that already
 *     lives outside the stack (zw_regmap keeps one), or the stack where it is large.
 *     About 0.8 KB (float) / 1.5 KB (double).
 *   - Needs no initialisation, and holds nothing between calls: each call overwrites what
 *     it reads before reading it, so any contents (garbage, another loop's) are fine.
 *   - One per concurrent caller: two calls running at the same time (threads, an interrupt
 *     preempting a task) must not share one.  Calls one after another may.
 * Its members are private to the library (their layout may change). */
typedef struct zw_loop_workspace {
    zw_real row[ZW_LOOP_MAX_DEGREE + 1u];     /* Routh / Schur-Cohn row */
    zw_real row_err[ZW_LOOP_MAX_DEGREE + 1u]; /* its error bounds */
    zw_loop_complex root[ZW_LOOP_MAX_DEGREE]; /* Aberth roots */
    zw_real radius[ZW_LOOP_MAX_DEGREE];       /* their inclusion radii */
    /* The limits' state (loop_limits.c), kept here so that the D-decomposition's frames
     * are small under the guarded check's chain (512 B target). */
    struct zw_loop_lim_plant { /* the loop's factored frequency response */
        const zw_loop *loop;
        struct zw_loop_workspace *ws; /* this workspace, for the guarded checks */
        zw_real one_minus_e, r12, two_c1, phase, one_minus_a, eps, grid_h;
        unsigned grid_n;
        bool general; /* a plant other than the ideal one: its bilinear images */
        bool stiff;   /* D(1) != 0 (a spring or a hand's stiffness) */
    } lim_plant;
    struct zw_loop_lim_point { /* the crossing condition f at theta, its value v */
        zw_real theta, f, f_err, v, v_err;
    } lim_pt;
    zw_loop_complex lim_r0, lim_s; /* the response at theta */
    struct zw_loop_lim_scan { /* one search for crossings of a line */
        const struct zw_loop_lim_plant *p;
        struct zw_loop_lim_point *pt; /* where the scan evaluates (lim_pt) */
        unsigned mode, take;
        zw_real fixed, floor;
        bool found, degenerate;
        zw_real est, lo, hi;
    } lim_scan;
    struct zw_loop_lim_walk { /* crossings along a horizontal line, the stable cells */
        bool have_prev, cell, truncated;
        unsigned step, count, i;
        zw_real alpha; /* the line's (0 for alpha = 0+) */
        zw_real prev_est, prev_lo, prev_hi, floor, est, lo, hi, mid;
        zw_real cell_lo[4], cell_hi[4]; /* ZW_LOOP_MAX_INTERVALS (loop_limits.h) */
        zw_real outer[2];
    } lim_walk;
    struct zw_loop_lim_ext { /* the extremes' searches over beta */
        zw_real bl, bh, w, a, b, c, d, fc, fd, t, best_a, best_b;
        unsigned i, ibest, it;
    } lim_ext;
    zw_real lim_amax; /* the last alpha_max found */
    bool lim_stable;  /* the last guarded verdict */
    zw_real plant_at[6]; /* the plant's N, D at a root estimate: re, im, bound each (loop.c) */
    const zw_loop *plant_loop; /* the loop they belong to */
    zw_loop_ceb eval[3];       /* the factored evaluation's running products (loop.c) */
} zw_loop_workspace;

/* Build the loop of spec for the plant c (a copy of *c is kept).  Errors: ZW_ERR_NULL,
 * ZW_ERR_DELAY, ZW_ERR_FILTER (pole outside [0, 1), n outside 1..16, unknown kind),
 * ZW_ERR_NAN (delta or the pole), ZW_ERR_INF (delta) / ZW_ERR_RANGE (a part overflows),
 * ZW_ERR_ARG (bad delta_relerr).  On error *out is an empty loop (degree 0) that every
 * function below refuses with ZW_ERR_ARG (as it refuses a loop whose degree does not
 * match its spec, e.g. one never initialized).  Tustin with an even-length average is
 * accepted but never stable: the Tustin mode (-1)^k averages out of the estimate, so
 * z = -1 is a root for every gain. */
zw_status zw_loop_init(zw_loop *out, const zw_coeffs *c, const zw_loop_spec *spec);

/* The loop of spec on a general sampled plant N(z) / D(z) (plant.h: a spring, a hand, an
 * actuator lag): p(z) = z^d D Dv + N (alpha Dv + beta Nv), the gains normalized by the
 * plant's mass M (alpha = K T^2 / M, beta = B T / M).  zw_loop_init(c, spec) is this with
 * zw_plant_from_coeffs(c).  A copy of *plant is kept.  With stiffness (kappa > 0) the
 * z = 1 boundary is the line alpha = -kappa (p(1) = Dv(1) (D(1) + alpha N(1))), so small
 * negative alphas may be stable too.  Errors: ZW_ERR_NULL, ZW_ERR_ARG (a plant of order
 * other than 2 or 3, e.g. one a failed zw_plant_init left), ZW_ERR_NAN / ZW_ERR_INF (a
 * coefficient or bound not finite), and those of zw_loop_init's spec; on error *out is the
 * empty loop. */
zw_status zw_loop_init_plant(zw_loop *out, const zw_plant *plant, const zw_loop_spec *spec);

/* Make every check on *loop hold for each gain within the given relative error of the one
 * passed (the exact gain is alpha (1 + ea), |ea| <= alpha_relerr; beta likewise): the
 * bounds of Na, Nb and their bilinear images widen by |part| times the error, and the
 * factored evaluation of p (root-inclusion test) adds |gain| err |part(z)|.  Cumulative
 * (a second call adds to the first).  Errors: ZW_ERR_NULL, ZW_ERR_ARG (uninitialized loop,
 * an error negative, NaN or >= 1/16), ZW_ERR_RANGE (a bound overflows); on error *loop is
 * made an empty loop, which every function refuses. */
zw_status zw_loop_carry_gain_rounding(zw_loop *loop, zw_real alpha_relerr, zw_real beta_relerr);

/* p(z) = D + alpha Na + beta Nb, highest power first, p[0..*degree].  On error every
 * entry is 0 and *degree = 0. */
zw_status zw_loop_poly(const zw_loop *loop, zw_real alpha, zw_real beta,
                       zw_real p[ZW_LOOP_MAX_DEGREE + 1u], unsigned *degree);

/* Which boundary of the stability region a point is beyond (or nearest, when marginal):
 * where the root of largest modulus sits. */
typedef enum zw_loop_boundary {
    ZW_LOOP_BOUNDARY_NONE = 0,      /* stable */
    ZW_LOOP_BOUNDARY_Z_PLUS1 = 1,   /* a real root at z >= 1 (static divergence) */
    ZW_LOOP_BOUNDARY_Z_MINUS1 = 2,  /* a real root at z <= -1 (oscillation at Nyquist) */
    ZW_LOOP_BOUNDARY_COMPLEX = 3    /* a complex pair e^{+-j theta} (oscillation at
                                       theta / (2 pi T) Hz) */
} zw_loop_boundary;

typedef struct zw_loop_verdict {
    bool stable;
    bool marginal;              /* within the rounding band: could not prove stable */
    zw_loop_boundary deciding;  /* NONE when stable */
    zw_real theta;              /* COMPLEX: angle of the deciding pair in (0, pi) rad per
                                   sample; 0 for the real boundaries and when stable */
} zw_loop_verdict;

/* Guarded verdict of the general loop (always the general path; the ideal loop's closed
 * form is zw_check).  How: a Routh test with running error bounds on the bilinear parts
 * and a Schur-Cohn test with running error bounds on the z coefficients (the latter first
 * from degree 13: it keeps its bound on the roots a delay line and a moving average put
 * near z = 0) decide most points; where neither can tell, an a-posteriori root-inclusion test
 * (Braess-Hadeler disks around Aberth roots, p evaluated from its factors) proves "every
 * root inside" or "one root surely outside"; otherwise marginal.  Stable only if proved;
 * a stable point is called unstable only within the band below, and then marginal = true.
 * Plants of plant.h: the same tests (tests/py/test_loop_plant_ref.py measures their band).
 * Band (tests/py/test_loop_reference.py, 1..1e7-ulp steps from labelled boundary points,
 * delta 2^-20..1e3, a up to 0.999, d up to 8): <= 1e5 ulps of the stepped gain up
 * to degree 12 (both precisions); above, <= 1e6 (double), <= 1e7 (float: the
 * long moving averages are ill-conditioned there).  z = 1 is alpha = 0 (integrating plant) and, with Tustin,
 * z = -1 is beta = 0 for every loop: both decided by the gain's exact sign.
 * deciding: z = 1 if alpha is not surely > 0, else z = -1 if p(-1) has the wrong sign
 * (or cannot be told), else where the root of largest modulus is (real: +-1; a pair
 * within ~sqrt(u) of the real axis counts as real).
 * Cost (host, double, bench/loop): 0.1-0.3 us for points the Routh / Schur-Cohn tests
 * settle up to degree 11, ~1.5 us at degree 18, ~10 us at 26; the root test and the
 * deciding root of an unstable point cost an Aberth run (tens of us at degree 10,
 * hundreds at 26); zw_loop_is_stable skips the latter.  Stack (worst chain with the root
 * test, tools/footprint.sh, arrays in *ws): 448 B on the Cortex-M4F float (M0 456 B), within
 * the 512 B (gated).
 * Errors: ZW_ERR_NULL (also ws), ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_ARG (an uninitialized loop).
 * On error *out = {stable = false, marginal = false, NONE, 0}. */
zw_status zw_loop_check(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                        zw_loop_verdict *out);

/* The verdict alone (*stable as zw_loop_check's .stable, for every input): the Routh test,
 * then the root-inclusion test only where Routh cannot tell; never the Aberth run that
 * zw_loop_check spends on the deciding boundary of a not-stable point.  The call for a
 * control loop's "is this gain safe?".  Errors as zw_loop_check; *stable = false on error. */
zw_status zw_loop_is_stable(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha, zw_real beta,
                            bool *stable);

/* "Every root has |z| < r" with the same guard (never true when rho >= r); r finite > 0.
 * Routh on (1 - s)^n p(r (1 + s)/(1 - s)) formed from the z coefficients (wider band than
 * zw_loop_check at r = 1), then the root-inclusion test.  Errors as zw_loop_check, and
 * ZW_ERR_ARG for r <= 0 or infinite; *within = false on error. */
zw_status zw_loop_radius_within(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                zw_real beta, zw_real r, bool *within);

/* Spectral radius rho (largest root modulus), with the angle in [0, pi] of that root, by
 * Aberth-Ehrlich iteration (at most 100 sweeps, no heap).  Informational (plots,
 * reports): verdicts never rest on it.  *rho = +inf, *theta = 0 on error. */
zw_status zw_loop_spectral_radius(const zw_loop *loop, zw_loop_workspace *ws, zw_real alpha,
                                  zw_real beta, zw_real *rho, zw_real *theta);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_LOOP_H */
