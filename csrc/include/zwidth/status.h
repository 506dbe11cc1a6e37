/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/status.h - status codes shared by every zwidth function.
 *
 * Every function returns a zw_status and writes its results through pointers.  Invalid
 * input gives a named error, never a wrong number.
 *
 * Fail-safe outputs: a caller that ignores the status must never read "stable".  On every
 * status other than ZW_OK each non-NULL output (also when another pointer argument is
 * NULL) is written with a value that certifies nothing: a verdict as not stable
 * (ZW_BOUND_INVALID, region.h), a "within" flag or per-pair flag as false, a limit (K_max,
 * alpha_max, extremes) as 0, a range as empty (lo = hi = 0, nonempty false), a spectral
 * radius as +inf, and a plant, coefficient set or normalized gain as NaN (every later
 * check on it answers ZW_ERR_NAN).  Each header states its functions' fail-safe values
 * (and the few outputs that are no verdict, limit or plant and stay untouched, such as
 * zw_sim_init's *sim).
 */
#ifndef ZWIDTH_STATUS_H
#define ZWIDTH_STATUS_H

#include "zwidth/precision.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum zw_status {
    ZW_OK = 0,
    ZW_ERR_NULL = 1,             /* a required pointer argument is NULL */
    ZW_ERR_NAN = 2,              /* an input is NaN */
    ZW_ERR_INF = 3,              /* an input is infinite where only finite values mean anything */
    ZW_ERR_MASS = 4,             /* m (or J) <= 0 */
    ZW_ERR_PERIOD = 5,           /* T <= 0 */
    ZW_ERR_DAMPING = 6,          /* b < 0 */
    ZW_ERR_DELTA = 7,            /* normalized physical damping delta < 0 */
    ZW_ERR_RANGE = 8,            /* a derived quantity (delta, T^2/m, K T^2/m, ...) over- or underflows */
    ZW_ERR_ARG = 9,              /* another argument is out of its documented domain (e.g. r <= 0) */
    ZW_ERR_DOMAIN = 10,          /* the requested quantity does not exist for this plant
                                    (e.g. the hyperbola/line corner when delta <= delta0) */
    ZW_ERR_FPENV = 11,           /* the floating-point environment is not the one the error
                                    bounds assume (zw_selftest): nothing can be certified */
    ZW_ERR_DELAY = 12,           /* loop delay outside 0..ZW_LOOP_MAX_DELAY samples */
    ZW_ERR_FILTER = 13,          /* velocity estimate out of its domain: filter pole outside
                                    [0, 1), cut-off <= 0 or at/above Nyquist, average length
                                    outside 1..ZW_LOOP_MAX_AVERAGE, unknown kind */
    ZW_ERR_BUSY = 14,            /* no consistent snapshot of data another context kept
                                    publishing (zw_regmap_active_gains): output off */
    ZW_ERR_BOX = 15              /* a plant box with lo > hi in m or b (box.h) */
} zw_status;

/* The last status code: every value in ZW_OK..ZW_STATUS_LAST has a name. */
#define ZW_STATUS_LAST ZW_ERR_BOX

/* Stable, upper-case name of a status ("ZW_ERR_MASS"); "ZW_UNKNOWN" for other values. */
const char *zw_status_name(zw_status status);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_STATUS_H */
