/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/device_loop.h - the loop a drive runs (loop.h), in real units (device.h).
 *
 * Built from the plant (m, b, T) and the loop in real units: delay d, differentiator,
 * velocity filter (low-pass by its cut-off f_c [Hz], a = exp(-2 pi f_c T), or by its pole a;
 * moving average over n).  Gains are K [N/m] and B [N s/m]; alpha = K T^2 / m and
 * beta = B T / m are computed with a relative error of at most 4u and 3u, and that
 * rounding is carried into the loop's guard explicitly (zw_loop_carry_gain_rounding), so
 * a verdict holds for the exact normalized gains of the K and B given.  Limits are
 * certified for the exact real inputs: K_max(B) never above the true sup at the exact
 * beta = B T / m, a B range never beyond the true one at the exact alpha = K T^2 / m.
 *
 * Fail-safe outputs (status.h): on every error a verdict is not stable, *within false,
 * *rho +inf, a limit 0, a range empty (lo = hi = 0, nonempty false), extremes all 0.
 */
#ifndef ZWIDTH_DEVICE_LOOP_H
#define ZWIDTH_DEVICE_LOOP_H

#include <stdbool.h>

#include "zwidth/device.h"
#include "zwidth/loop.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The loop in real units.  A zero-initialized spec is the paper's ideal loop. */
typedef struct zw_device_loop_spec {
    unsigned delay;                   /* d samples, 0..ZW_LOOP_MAX_DELAY */
    zw_differentiator differentiator;
    zw_velocity_filter filter;
    zw_real cutoff_hz; /* LOWPASS: f_c > 0 [Hz] gives a = zw_loop_lowpass_pole(f_c, T);
                          0 takes pole as given */
    zw_real pole;      /* LOWPASS with cutoff_hz == 0: a in [0, 1) */
    unsigned average;  /* AVERAGE: n, 1..ZW_LOOP_MAX_AVERAGE */
} zw_device_loop_spec;

/* The plant and its loop, the gains' conversion rounding carried in loop's bounds
 * (loop.spec.filter_pole is the pole used, from the cut-off or as given).  Large (about
 * 2.6 KB in double, 1.3 KB in float): keep it in static or owned storage, not on an
 * MCU's stack. */
typedef struct zw_device_loop {
    zw_device dev;
    zw_loop loop;
    /* Relative error of dev.m against the exact mass the gains are normalized by (0, or u
     * when dev.m = fl(m + m_h) for a hand); carried into the gain bounds and the limits. */
    zw_real mass_relerr;
} zw_device_loop;

/* Errors: those of zw_device_init, zw_loop_lowpass_pole (f_c, NaN -> ZW_ERR_NAN) and
 * zw_loop_init; ZW_ERR_NULL.  On error dev is NaN (zw_device_init's fail-safe) and loop
 * empty: every function below refuses it. */
zw_status zw_device_loop_init(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                              const zw_device_loop_spec *spec);

/* The loop on the plant with its plant-side parts (plant.h): a physical stiffness k_p
 * [N/m] (a return spring, a cable), an actuator (current-loop) lag tau [s], a coupled hand
 * of mass m_h [kg], damping b_h [N s/m] and stiffness k_h [N/m] (all 0: uncoupled).  Every
 * part 0 gives zw_device_loop_init's loop.  The gains are normalized by M = m + m_h
 * (alpha = K T^2 / M, beta = B T / M): dev is zw_device_init(M, b + b_h, T), its scales
 * M / T^2 and M / T (dev.co is the ideal plant at that delta, not the loop's plant: that is
 * loop.plant).  Verdicts and limits below then hold for the coupled plant: K_max(B) is the
 * certified sup at B of the stable K in (0, K_max) (with stiffness, small negative K may
 * be stable too: the z = 1 boundary is K = -(k_p + k_h)).
 * Errors: those of zw_plant_spec_from_device (ZW_ERR_ARG for k_p, tau, m_h or k_h < 0,
 * ZW_ERR_DAMPING for b_h < 0), zw_plant_init, zw_device_init and zw_device_loop_init;
 * fail-safe as zw_device_loop_init. */
zw_status zw_device_loop_init_plant(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                                    zw_real k_p, zw_real tau, zw_real m_h, zw_real b_h,
                                    zw_real k_h, const zw_device_loop_spec *spec);

/* Errors of the functions below: ZW_ERR_NULL, ZW_ERR_NAN / ZW_ERR_INF (K, B, a failed
 * device), ZW_ERR_ARG (an empty loop), ZW_ERR_RANGE (a gain or result overflows, or a
 * non-zero gain's normalized value underflows), and those of the loop function used. */

/* zw_loop_check of the exact (alpha, beta) of (K, B), guarded for the conversion. */
zw_status zw_device_loop_check(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                               zw_real B, zw_loop_verdict *out);
/* The verdict alone (zw_loop_is_stable: *stable as zw_device_loop_check's .stable, without
 * the deciding boundary's root run); *stable = false on error. */
zw_status zw_device_loop_is_stable(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                                   zw_real B, bool *stable);
/* zw_loop_radius_within likewise (r finite > 0). */
zw_status zw_device_loop_radius_within(const zw_device_loop *dl, zw_loop_workspace *ws,
                                       zw_real K, zw_real B, zw_real r, bool *within);
/* Informational (zw_loop_spectral_radius at the rounded gains). */
zw_status zw_device_loop_spectral_radius(const zw_device_loop *dl, zw_loop_workspace *ws,
                                         zw_real K, zw_real B, zw_real *rho, zw_real *theta);

/* Every K in (0, *K_max) is stable at B, for the exact beta = B T / m (certified; see
 * device_loop.c for why the rounding of beta cannot lift it).  0 when none is proved.
 * Cost: two zw_loop_alpha_max (one when B = 0) and one to a few zw_loop_check. */
zw_status zw_device_loop_k_max(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real B,
                              zw_real *K_max);

/* The widest stable B interval at K (> 0): every B in [*B_lo, *B_hi] stable for the exact
 * alpha = K T^2 / m (certified, by the edge theorem on a box of gains; device_loop.c).
 * Empty (nonempty false, 0, 0) when none is proved, and for K <= 0.  Cost: two
 * zw_loop_beta_interval and two or more zw_loop_check. */
zw_status zw_device_loop_b_range(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                                 zw_real *B_lo, zw_real *B_hi, bool *nonempty);

/* zw_loop_extremes in real units.  K_mmax, K_p_max, B_mmax never above, B_mmin never below
 * the true ones (they are sups / infs over every B or K, so only the scale's rounding is
 * at stake); B_at_K_mmax is informational: K_max at it (zw_device_loop_k_max) may sit a
 * rounding below K_mmax.  Every field 0 on error. */
typedef struct zw_device_loop_extremes {
    zw_real K_mmax;
    zw_real B_at_K_mmax;
    zw_real K_p_max;
    zw_real B_mmax;
    zw_real B_mmin;
} zw_device_loop_extremes;

zw_status zw_device_loop_extremes_compute(const zw_device_loop *dl, zw_loop_workspace *ws,
                                          zw_device_loop_extremes *out);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_DEVICE_LOOP_H */
