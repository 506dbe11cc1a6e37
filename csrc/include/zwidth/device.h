/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/device.h - real units: a plant (m, b, T) and gains (K, B), paper Section IV.
 *
 *   delta = b T / m,  alpha = K T^2 / m,  beta = B T / m
 * For a rotary device read m as the inertia J [kg m^2], K in N m/rad, B in N m s/rad.
 * The rounding of these conversions is carried into the checks' guard, so a real-unit
 * verdict is as safe as a normalized one.
 */
#ifndef ZWIDTH_DEVICE_H
#define ZWIDTH_DEVICE_H

#include <stdbool.h>

#include "zwidth/extremes.h"
#include "zwidth/margin.h"
#include "zwidth/region.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct zw_device {
    zw_real m;        /* mass [kg] or inertia J [kg m^2], > 0 */
    zw_real b;        /* physical damping [N s/m] or [N m s/rad], >= 0 */
    zw_real T;        /* sampling period [s], > 0 */
    zw_real k_scale;  /* m / T^2: K = alpha k_scale */
    zw_real b_scale;  /* m / T:   B = beta b_scale */
    zw_coeffs co;     /* coefficients at delta = b T / m */
} zw_device;

/* Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_MASS (m <= 0), ZW_ERR_PERIOD (T <= 0),
 * ZW_ERR_DAMPING (b < 0), ZW_ERR_RANGE (m, T, a positive b, T/m, delta, m/T or m/T^2 not
 * a normal number: a subnormal carries an unbounded relative error that the checks could
 * not budget for).  Fail-safe (status.h): on each error but ZW_ERR_NULL every field of
 * *out is NaN (an older plant in *out is overwritten, not kept), and every function below
 * refuses such a device with ZW_ERR_NAN and its own fail-safe outputs. */
zw_status zw_device_init(zw_device *out, zw_real m, zw_real b, zw_real T);

/* Errors of every function below: ZW_ERR_NULL (d or an output), ZW_ERR_NAN (K, B, or a
 * device left NaN by a failed zw_device_init), ZW_ERR_INF (K, B), ZW_ERR_ARG (d->co's
 * delta_relerr negative or not finite), ZW_ERR_RANGE (a normalized gain or a result
 * overflows, or a zeroed device), and as stated.  Fail-safe (status.h): on each error every
 * non-NULL output is written, whichever other pointer is NULL, as one that certifies
 * nothing: a verdict not stable (region.h: ZW_BOUND_INVALID), *within false, *rho +inf,
 * a limit 0, a range empty (lo = hi = 0, nonempty false), a normalized gain NaN. */

/* Normalize gains: alpha = K / k_scale, beta = B / b_scale (ZW_ERR_RANGE on overflow). */
zw_status zw_device_normalize(const zw_device *d, zw_real K, zw_real B, zw_real *alpha,
                              zw_real *beta);

/* Verdicts in real units (exact region, or any zw_region: ZW_ERR_ARG for an unknown one). */
zw_status zw_device_check(const zw_device *d, zw_real K, zw_real B, zw_verdict *out);
zw_status zw_device_check_region(zw_region region, const zw_device *d, zw_real K, zw_real B,
                                 zw_verdict *out);
zw_status zw_device_spectral_radius(const zw_device *d, zw_real K, zw_real B, zw_real *rho);
zw_status zw_device_radius_within(const zw_device *d, zw_real K, zw_real B, zw_real r,
                                  bool *within);

typedef struct zw_device_extremes {
    zw_real K_mmax;        /* [N/m]   largest stable K (sup) */
    zw_real B_at_K_mmax;   /* [N s/m] the B that attains it */
    bool at_corner;        /* K_mmax sits on the corner of hyperbola and line */
    zw_real K_p_max;       /* [N/m]   largest K with B = 0 */
    zw_real B_mmax;        /* [N s/m] largest stable B (K -> 0+) */
    zw_real B_mmin;        /* [N s/m] -b, not attained */
    zw_real K_mmin;        /* 0, not attained */
} zw_device_extremes;

/* On error every real of *out is 0 (the K and B ranges empty) and at_corner false. */
zw_status zw_device_extremes_compute(const zw_device *d, zw_device_extremes *out);
/* sup K stable at this B (0 when none). */
zw_status zw_device_k_max(const zw_device *d, zw_real B, zw_real *K_max);
/* The open interval of B stable at this K (nonempty false and B_lo = B_hi = 0 if none). */
zw_status zw_device_b_range(const zw_device *d, zw_real K, zw_real *B_lo, zw_real *B_hi,
                            bool *nonempty);

/* Direction in which a limit moves when a parameter grows (the others fixed). */
typedef enum zw_trend {
    ZW_FALLS = -1,
    ZW_FLAT = 0,
    ZW_RISES = 1,
    ZW_TREND_UNKNOWN = 2 /* only from a failed zw_device_influence */
} zw_trend;

/* Where the plant sits on the (non-monotonic) curves of K_mmax and B_mmax against m, b, T,
 * paper Section IV and Table 1.  When b = 0, delta = 0 for every m and T and the curves
 * have no interior turning points: the critical masses are 0 and the periods +inf. */
typedef struct zw_influence {
    zw_real delta;
    zw_real K_mmax, B_mmax;        /* at the plant */
    /* K_mmax against m: rises on (0, m_K2), falls on (m_K2, m_K1), rises beyond m_K1. */
    zw_real m_K1, m_K2;            /* b T / delta_K1, b T / delta_K2 */
    zw_real K_mmax_at_m_K2;        /* local max 4.5087 b / T */
    zw_real K_mmax_at_m_K1;        /* local min 2.6374 b / T */
    zw_real m_K_match;             /* b T / delta_KM > m_K1: raise m past this to beat m_K2 */
    /* B_mmax against T: falls on (0, T_B), rises on (T_B, T_0), falls beyond T_0;
     * against m: rises on (0, m_0), falls on (m_0, m_B), rises beyond m_B. */
    zw_real T_B, T_0;              /* m delta_B / b, m delta_0 / b */
    zw_real m_0, m_B;              /* b T / delta_0, b T / delta_B */
    /* B_mmax against b: rises on (0, b_0), falls on (b_0, b_BB), rises beyond b_BB. */
    zw_real b_0, b_BB;             /* m delta_0 / T, m delta_BB / T */
    /* Sign of the derivative of each limit in each parameter, at the plant. */
    zw_trend K_vs_m, K_vs_b, K_vs_T;
    zw_trend B_vs_m, B_vs_b, B_vs_T;
    /* Knob-switch advice for K_mmax through m: when the plant sits on the falling stretch
     * (m_K2 < m < m_K1), reducing m to m_K2 gives the local max, and only raising m past
     * m_K_match does better; best_m_for_K is m_K2 then, else m itself (already rising). */
    zw_real best_m_for_K;
} zw_influence;

/* Fail-safe on error: the limits (K_mmax, B_mmax, K_mmax_at_m_K1/K2) 0, every parameter
 * value (delta, the critical m, T, b, best_m_for_K) NaN, so a device built from one is
 * refused, and every trend ZW_TREND_UNKNOWN. */
zw_status zw_device_influence(const zw_device *d, zw_influence *out);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_DEVICE_H */
