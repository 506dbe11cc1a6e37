/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/margin.h - how stable: the closed-loop poles, paper eqs (7), (8).
 *
 *   p(z) = 2 z^3 + a1 z^2 + a2 z - c2 beta
 *   a1 = c1 (alpha + beta) - 2 (1 + e),  a2 = c2 alpha + (c2 - c1) beta + 2 e
 */
#ifndef ZWIDTH_MARGIN_H
#define ZWIDTH_MARGIN_H

#include <stdbool.h>

#include "zwidth/coeffs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Errors of every function here: ZW_ERR_NULL (c or the output), ZW_ERR_NAN / ZW_ERR_INF
 * (alpha, beta, c->delta), ZW_ERR_ARG (c->delta_relerr negative or not finite), and as
 * stated below.  Fail-safe (status.h): on each error every non-NULL output is written as
 * one that certifies nothing: p all NaN, *rho = +inf, *within = false. */

/* Coefficients of p(z), highest power first: p[0] = 2, p[1] = a1, p[2] = a2, p[3] = -c2 beta
 * (ZW_ERR_RANGE when one overflows). */
zw_status zw_char_poly(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real p[4]);

/* Spectral radius rho = max |z| over the three closed-loop poles (stable iff rho < 1).
 * Real root by safeguarded Newton on a bracket, the other two from the deflated
 * quadratic by the cancellation-free formulas.  Accuracy: see tests/py/test_margin.py.
 * ZW_ERR_RANGE when a coefficient or the radius overflows. */
zw_status zw_spectral_radius(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real *rho);

/* "Every pole has |z| < r", decided without root finding by the Jury conditions on
 * p(r z), with a running error bound: *within is true only if that holds for every value
 * within the rounding bound (never true when rho >= r).  r must be finite and > 0
 * (ZW_ERR_NAN for NaN, ZW_ERR_ARG otherwise). */
zw_status zw_radius_within(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_real r,
                           bool *within);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_MARGIN_H */
