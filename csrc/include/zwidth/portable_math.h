/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/portable_math.h - C99 fallbacks for library functions some embedded toolchains
 * lack (avr-libc 2.0: expm1f, nextafterf; older TI C2000 RTS libraries).
 *
 * Always built into the core (so the host tests can compare them against the libm ones);
 * used in place of the libm versions only when the core is built with -DZW_PORTABLE_MATH
 * (real.h maps ZW_EXPM1 and ZW_NEXTAFTERF to them).  Plain arithmetic, frexp/ldexp and
 * exp: no type punning, no unions, no state.  Accuracy (docs/fp-environment.md, measured
 * by tests/c/test_portable_math.c): zw_expm1_portable within ZW_EXPM1_PORTABLE_ULPS of
 * the correctly rounded result given an exp within one ulp; zw_nextafterf_portable exact.
 */
#ifndef ZWIDTH_PORTABLE_MATH_H
#define ZWIDTH_PORTABLE_MATH_H

#include "zwidth/real.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Documented error bound of zw_expm1_portable, in ulps of the result. */
#define ZW_EXPM1_PORTABLE_ULPS 2

/* e^x - 1 without the cancellation of exp(x) - 1 near 0.  NaN gives NaN, +inf +inf,
 * -inf -1. */
zw_real zw_expm1_portable(zw_real x);

/* The next binary32 value after x in the direction of toward (C99 nextafterf): toward
 * itself when x == toward, NaN when either is NaN.  On a target that flushes subnormals
 * to zero the steps below FLT_MIN are flushed too. */
float zw_nextafterf_portable(float x, float toward);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_PORTABLE_MATH_H */
