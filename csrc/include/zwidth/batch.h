/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/batch.h - the exact-region check over many gain pairs of one plant.
 *
 * stable[i] is exactly zw_check(...).stable (or zw_device_check(...).stable) of pair i,
 * without the reasons: one validation pass, then a branch-free loop the compiler can
 * vectorize and the CPU need not predict.  For gain tables on a drive, design sweeps on a
 * host, and the Python bindings.
 *
 * Pair i reads alpha[i * alpha_stride] and beta[i * beta_stride] (strides in elements; 0
 * repeats one value).  Errors: ZW_ERR_NULL (a NULL pointer with n > 0) and the errors
 * zw_check / zw_device_check would give for the coefficients or the device (both with
 * *first_invalid = 0: they concern every pair); and, for the first pair those functions
 * would refuse, its status with its index in *first_invalid.  first_invalid may be NULL.
 * Fail-safe (status.h): on any error stable[0 .. n-1] (when stable is not NULL) are all
 * false, whichever pair was refused.  n = 0 is ZW_OK and reads and writes nothing.
 */
#ifndef ZWIDTH_BATCH_H
#define ZWIDTH_BATCH_H
#include <stdbool.h>
#include <stddef.h>
#include "zwidth/device.h"

#ifdef __cplusplus
extern "C" {
#endif
zw_status zw_check_many(const zw_coeffs *c, size_t n, const zw_real *alpha, ptrdiff_t alpha_stride,
                        const zw_real *beta, ptrdiff_t beta_stride, bool *stable,
                        size_t *first_invalid);
/* Real units: K [N/m], B [N s/m] on device d (conversion roundings guarded as in
 * zw_device_check). */
zw_status zw_device_check_many(const zw_device *d, size_t n, const zw_real *K, ptrdiff_t K_stride,
                               const zw_real *B, ptrdiff_t B_stride, bool *stable,
                               size_t *first_invalid);
#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_BATCH_H */
