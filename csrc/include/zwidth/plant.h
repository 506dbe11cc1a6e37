/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/plant.h - the plant under the zero-order hold, with its plant-side parts.
 *
 * The paper's plant is m x'' + b x' = F.  A drive's plant may add
 *   - a physical stiffness k_p (a return spring, a cable),
 *   - a coupled operator: a hand of mass m_h, damping b_h, stiffness k_h rigidly attached
 *     (uncoupled is m_h = b_h = k_h = 0),
 *   - an actuator (current-loop) lag: the force reaches the plant through 1 / (tau s + 1).
 * With M = m + m_h, Bp = b + b_h, Kp = k_p + k_h the continuous plant is
 *     x / F = 1 / ((tau s + 1) (M s^2 + Bp s + Kp)),
 * and in normalized time (t / T) with the gains normalized by M (alpha = K T^2 / M,
 * beta = B T / M) it depends on three numbers:
 *     delta  = Bp T / M,   kappa = Kp T^2 / M,   lambda = tau / T.
 * Under the zero-order hold the sampled plant is (times T^2 / M)
 *     G(z) = N(z) / D(z),   deg D = order (2, or 3 with a lag), deg N = order - 1,
 * scaled as the ideal plant's (c1 z + c2) / (2 (z - 1)(z - e)): for kappa = lambda = 0,
 * N = c1 z + c2 and D = 2 (z - 1)(z - e) with the fields of zw_coeffs_init(delta).
 * The loop (loop.h) builds p(z) = z^d D Dv + N (alpha Dv + beta Nv) from these.
 *
 * Every coefficient carries a rigorous bound on its absolute error against the exact
 * value at the exact (delta, kappa, lambda) (each given with its relative uncertainty), as
 * zw_coeffs' fields do (ZW_COEF_ULPS), so the guarded checks stay safe.  The bilinear
 * images (z = (1 + s) / (1 - s), times (1 - s)^deg) are formed from the factors without
 * cancellation: a pole near z = 1 (small delta, kappa; lambda >> 1) keeps full relative
 * accuracy in s, as F_ZME does for the ideal plant (loop.c).
 *
 * Hard cases it handles without 0/0 or unbounded cancellation (docs/numerics.md, "Plant-side
 * parts"): critical damping (delta^2 = 4 kappa: everything is an entire function of
 * delta^2/4 - kappa), complex poles (a hand's spring), kappa -> 0 (the ideal plant),
 * lambda -> 0 (N -> z N2, D -> z D2), lambda = 1 / |p| (the lag's pole on a plant pole),
 * lambda >> 1 (a pole next to z = 1: D keeps 1 - e^(-1/lambda) as a factor), delta -> 0.
 *
 * Measured (tests/py/test_plant_ref.py against 80..1280-digit mpmath; every coefficient was
 * within its bound at every point, both precisions): the bound over the actual error is
 * ~5..40 at the median; in units of u times the largest coefficient of the same polynomial
 * the bounds are, median / 90th percentile,
 *   order 2 (delta in [0, 1e6], kappa in [0, 1e6]):     D 0.6 / 6, N 29 / 214, D_s 2 / 57,
 *                                                        N_s 12 / 34
 *   order 3 (lambda in [0.01, 10], delta <= 1e4, kappa <= 1e5): D 1 / 17, N 31 / 222,
 *                                                        D_s 6 / 218, N_s 45 / 516
 *   order 3, lambda in [1e-4, 1e-3] u [30, 1e4]:        D 2 / 18, N 32 / 219, N_s 64 / 502
 * (maxima ~5e3, 1.7e4 in float's order 2: a rounded omega = sqrt(kappa - h^2) ~ 300..1000
 * costs u omega in sin, cos, which the bound must charge).
 * Limits: ZW_ERR_RANGE when (delta/2)^2 or (1/lambda)^2 overflows (delta above ~2.7e154,
 * lambda below ~7.5e-155; float: 3.7e19, 5.4e-20) or a bound does.
 */
#ifndef ZWIDTH_PLANT_H
#define ZWIDTH_PLANT_H

#include <stdbool.h>

#include "zwidth/coeffs.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ZW_PLANT_MAX_ORDER 3u

/* The normalized plant.  A zero-initialized spec is the paper's plant at delta = 0. */
typedef struct zw_plant_spec {
    zw_real delta;  /* Bp T / M >= 0 */
    zw_real kappa;  /* Kp T^2 / M >= 0 (0: no stiffness, the integrating plant) */
    zw_real lambda; /* tau / T >= 0 (0: no lag, order 2) */
    /* Relative uncertainty of each input (0: given exactly; a few u when computed from
     * real units).  The coefficient bounds cover it. */
    zw_real delta_relerr;
    zw_real kappa_relerr;
    zw_real lambda_relerr;
} zw_plant_spec;

/* The sampled plant.  Filled by zw_plant_init; read-only after.  Polynomials highest power
 * first (index 0 is z^order for den, z^(order-1) for num). */
typedef struct zw_plant {
    zw_plant_spec spec;
    unsigned order; /* 2, or 3 when lambda > 0 */
    zw_real den[ZW_PLANT_MAX_ORDER + 1u];
    zw_real den_err[ZW_PLANT_MAX_ORDER + 1u];
    zw_real num[ZW_PLANT_MAX_ORDER];
    zw_real num_err[ZW_PLANT_MAX_ORDER];
    /* D((1 + s) / (1 - s)) (1 - s)^order and N((1 + s) / (1 - s)) (1 - s)^(order - 1). */
    zw_real den_s[ZW_PLANT_MAX_ORDER + 1u];
    zw_real den_s_err[ZW_PLANT_MAX_ORDER + 1u];
    zw_real num_s[ZW_PLANT_MAX_ORDER];
    zw_real num_s_err[ZW_PLANT_MAX_ORDER];
    /* The ideal plant's fields at delta (kappa = lambda = 0 uses them for num / den). */
    zw_coeffs c;
    /* D as a polynomial in w = z - 1 (its Taylor coefficients at z = 1, formed from the
     * factors): zw_plant_eval uses it, so D keeps its relative accuracy near z = 1. */
    zw_real den_w[ZW_PLANT_MAX_ORDER + 1u];
    zw_real den_w_err[ZW_PLANT_MAX_ORDER + 1u];
} zw_plant;

/* Fill *out.  Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_DELTA (delta < 0),
 * ZW_ERR_ARG (kappa < 0, lambda < 0, a relerr negative, NaN or >= 1/16), ZW_ERR_RANGE (a
 * coefficient or bound overflows).  Fail-safe: on error *out has order 0, which every
 * consumer refuses (ZW_ERR_ARG). */
zw_status zw_plant_init(zw_plant *out, const zw_plant_spec *spec);

/* The ideal plant (kappa = lambda = 0) from coefficients already computed (zw_coeffs_init,
 * or a device's, with its delta_relerr): N = c1 z + c2, D = 2 (z - 1)(z - e), the bounds
 * those loop.c has always used.  Errors: ZW_ERR_NULL, and those of an invalid *c
 * (ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_DELTA, ZW_ERR_ARG); order 0 on error. */
zw_status zw_plant_from_coeffs(zw_plant *out, const zw_coeffs *c);

/* N(z) and D(z) at a complex z (for the loop's root inclusion test and its
 * D-decomposition), each with a bound on its absolute error; D keeps relative accuracy
 * near z = 1 (Horner in w = z - 1 on den_w, D's Taylor coefficients at 1 formed from its
 * factors, not from the expanded coefficients).  Errors: ZW_ERR_NULL, ZW_ERR_ARG (order 0),
 * ZW_ERR_NAN / ZW_ERR_INF (z), ZW_ERR_RANGE (a bound overflows); on error every non-NULL
 * output is NaN. */
zw_status zw_plant_eval(const zw_plant *plant, zw_real re, zw_real im, zw_real *num_re,
                        zw_real *num_im, zw_real *num_err, zw_real *den_re, zw_real *den_im,
                        zw_real *den_err);

/* The plant in real units: m, b, T as device.h; k_p >= 0 [N/m]; tau >= 0 [s]; a hand
 * (m_h, b_h, k_h >= 0; all 0: uncoupled).  Fills *spec (relerrs from the conversion's
 * rounding) and *mass = M = m + m_h (the mass the gains are normalized by).
 * Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_MASS, ZW_ERR_PERIOD, ZW_ERR_DAMPING
 * (b < 0 or b_h < 0), ZW_ERR_ARG (k_p, k_h, tau or m_h < 0), ZW_ERR_RANGE.  On error
 * *spec is all NaN and *mass NaN. */
zw_status zw_plant_spec_from_device(zw_real m, zw_real b, zw_real T, zw_real k_p, zw_real tau,
                                    zw_real m_h, zw_real b_h, zw_real k_h, zw_plant_spec *spec,
                                    zw_real *mass);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_PLANT_H */
