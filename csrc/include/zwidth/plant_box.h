/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/plant_box.h - the ideal sampled plant enclosed over an interval of delta.
 *
 * For every delta in [delta_lo, delta_hi] the exact coefficients of the ideal plant
 * (kappa = lambda = 0, plant.h)
 *     N = c1 z + c2,  D = 2 (z - 1)(z - e),
 *     num_s = d12 s + (c1 + c2),  den_s = 4 s ((1 + e) s + (1 - e)),  den_w = 2 w (w + 1 - e)
 * lie within value +- err of the fields of the zw_plant filled here: a midpoint-radius
 * enclosure, rigorous for any width (not a first-order bound).  How (docs/box.md):
 * e, c1, c2, c1 + c2 fall and 1 - e rises with delta (c1 = 2 int_0^1 (1 - t) e^(-delta t) dt,
 * c2 = 2 int_0^1 t e^(-delta t) dt, (c1 + c2) / 2 = int_0^1 e^(-delta t) dt), so their ranges
 * are spanned by the ends; d12 = c1 - c2 rises up to delta* = 2.68800 and falls beyond
 * (proof in docs/box.md), so its range is spanned by the ends and, when the interval meets
 * delta*, the maximum 0.2787031...  The end values come from zw_coeffs_init (accurate to
 * ZW_COEF_ULPS) and are rounded outward.
 *
 * The plant's spec and c describe the midpoint delta_mid with delta_relerr = the relative
 * half-width (informational: zw_coeffs' delta_relerr is carried to first order only, so
 * a consumer that needs the whole interval must read the bounds of num, den, num_s, den_s,
 * not c).
 */
#ifndef ZWIDTH_PLANT_BOX_H
#define ZWIDTH_PLANT_BOX_H

#include "zwidth/plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Errors: ZW_ERR_NULL, ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_DELTA (delta_lo < 0), ZW_ERR_BOX
 * (delta_lo > delta_hi), ZW_ERR_RANGE (a bound overflows).  Fail-safe: on error *out has
 * order 0 (refused by every consumer of zw_plant) and every number NaN. */
zw_status zw_plant_enclose(zw_plant *out, zw_real delta_lo, zw_real delta_hi);

/* The order-2 plant with stiffness (plant.h, lambda = 0) enclosed over every (delta, kappa)
 * of [delta_lo, delta_hi] x [kappa_lo, kappa_hi]: the exact coefficients (D, N, D_s, N_s,
 * D in w) lie within value +- err of the fields filled here, for any width.  How
 * (docs/box.md): every coefficient is an entire function of h = delta / 2 and
 * w2 = h^2 - kappa (plant.c's series regime), evaluated in midpoint-radius arithmetic
 * (zw_eb, whose products keep the radii's product: rigorous for any radius) from balls
 * enclosing h, h^2, w2 and kappa, with the series' truncation bounded for |w2|, h^2 <= 4.
 * So the domain is delta, kappa <= ZW_PLANT_ENCLOSE_MAX (beyond: ZW_ERR_RANGE).
 * kappa_hi = 0 is zw_plant_enclose.  Errors: those of zw_plant_enclose, ZW_ERR_ARG
 * (kappa_lo < 0), ZW_ERR_BOX (kappa_lo > kappa_hi); fail-safe as zw_plant_enclose. */
#define ZW_PLANT_ENCLOSE_MAX ZW_R(4.0)
zw_status zw_plant_enclose2(zw_plant *out, zw_real delta_lo, zw_real delta_hi, zw_real kappa_lo,
                            zw_real kappa_hi);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_PLANT_BOX_H */
