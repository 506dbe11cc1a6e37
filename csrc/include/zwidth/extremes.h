/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/extremes.h - achievable impedance extremes in the normalized space,
 * paper Section III, eqs (19)-(32), and the critical constants.
 */
#ifndef ZWIDTH_EXTREMES_H
#define ZWIDTH_EXTREMES_H

#include <stdbool.h>

#include "zwidth/coeffs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Critical NPDs (re-derived at 40 digits by root finding in tests/py/test_constants.py). */
#define ZW_DELTA0 ZW_R(2.310571356753694244202296)   /* line bites: (1+d)(1+e^-d)^2 = 4 */
#define ZW_DELTA1 ZW_R(3.659361627421783507110962)   /* beta1 = beta2: alpha_mmax switches branch */
#define ZW_DELTA2 ZW_R(3.720753996267921484348198)   /* beta at alpha_mmax = 0; line bites at beta = 0 */
#define ZW_DELTA_K1 ZW_R(1.043514020060016795481397) /* local min of alpha_mmax / delta */
#define ZW_DELTA_K2 ZW_R(5.774821841547911129033585) /* local max of alpha_mmax / delta */
#define ZW_DELTA_B ZW_R(1.793282132900761007557553)  /* local min of beta_mmax / delta */
#define ZW_DELTA_BB ZW_R(3.212230597605534728176283) /* local min of beta_mmax itself (> delta0):
                                                        B_mmax against b rises, falls on
                                                        (delta0, delta_BB), rises again */
/* delta < delta_K1 at which alpha_mmax/delta climbs back to its local max at delta_K2:
 * the inertia a device must be raised to (m = b T / ZW_DELTA_KM) to match m_K2. */
#define ZW_DELTA_KM ZW_R(0.2260830184931867972235071)
#define ZW_KMAX_LOCAL_MAX ZW_R(4.508675168782247672721439) /* alpha_mmax/delta at delta_K2 */
#define ZW_KMAX_LOCAL_MIN ZW_R(2.637422468249545389065620) /* alpha_mmax/delta at delta_K1 */

typedef struct zw_extremes {
    zw_real alpha_mmax;         /* largest alpha stable for some beta (sup, not attained) */
    zw_real beta_at_alpha_mmax; /* the beta that attains it */
    bool at_corner;             /* true: corner of hyperbola and line (delta > delta1), eqs (21)-(22);
                                   false: top of the hyperbola, eqs (19)-(20) */
    zw_real alpha_p_max;        /* proportional control (beta = 0), eq (29) */
    zw_real beta_mmax;          /* largest beta (alpha -> 0+), eq (32) */
    zw_real beta_mmin;          /* -delta (not attained) */
    zw_real alpha_mmin;         /* 0 (not attained) */
} zw_extremes;

/* Errors of every function below: ZW_ERR_NULL (c or an output), ZW_ERR_NAN / ZW_ERR_INF
 * (c->delta, the gain), ZW_ERR_ARG (c->delta_relerr negative or not finite), ZW_ERR_RANGE
 * (hs = +inf, or a result overflows), and as stated.  Fail-safe (status.h): on each error
 * every non-NULL output is written as a limit that certifies nothing: every real 0 (so
 * the alpha and beta ranges are empty) and every flag false. */

zw_status zw_extremes_compute(const zw_coeffs *c, zw_extremes *out);

/* Top of the hyperbola alpha = f(beta), eqs (19), (20) (exists for every delta). */
zw_status zw_hyperbola_top(const zw_coeffs *c, zw_real *alpha1, zw_real *beta1);

/* Corner where the line meets the hyperbola, eqs (21), (22); ZW_ERR_DOMAIN unless
 * delta > delta0 (below it the line lies outside the hyperbola). */
zw_status zw_corner(const zw_coeffs *c, zw_real *alpha2, zw_real *beta2);

/* sup alpha stable at this beta: min{f(beta), L(beta)} for -delta < beta < beta_mmax,
 * 0 outside. */
zw_status zw_alpha_max(const zw_coeffs *c, zw_real beta, zw_real *alpha_max);

/* The open interval (lo, hi) of beta that is stable at this alpha; *nonempty false (and
 * lo = hi = 0) when there is none (alpha <= 0 or alpha >= alpha_mmax), and on error. */
zw_status zw_beta_interval(const zw_coeffs *c, zw_real alpha, zw_real *lo, zw_real *hi,
                           bool *nonempty);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_EXTREMES_H */
