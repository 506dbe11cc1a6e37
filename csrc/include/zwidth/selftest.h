/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/selftest.h - run-time check of the arithmetic the error bounds rely on.
 *
 * Every guard in zwidth (the running error bounds of region.c, margin.c, loop.c, ...)
 * assumes IEEE-754 binary32 / binary64 arithmetic with round to nearest, NaN that
 * compares unequal to itself, overflow to infinity, gradual underflow where the bounds
 * count on it, and one rounding per operation (no fused multiply-add contraction).
 * A compiler flag (-ffast-math, a vendor IDE's -ffp-contract=fast), an FPU mode (flush
 * to zero, round toward zero) or a non-IEEE target (TI C28x: NaN compares as infinity,
 * denormals are zero) can void them silently.  zw_selftest() checks each property at
 * run time, on the target, with the build's own zw_real.
 *
 * Firmware calls it once at start-up; the register map refuses to seal a certified
 * block (and so the drive to start) when it fails.
 */
#ifndef ZWIDTH_SELFTEST_H
#define ZWIDTH_SELFTEST_H

#include <stdint.h>

#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ZW_OK when the floating-point environment is the one the error bounds assume;
 * ZW_ERR_FPENV otherwise.  No side effects; reentrant; constant time. */
zw_status zw_selftest(void);

/* The properties zw_selftest checks, one bit each (docs/fp-environment.md says why each
 * matters to the bounds). */
#define ZW_SELFTEST_ROUNDING 0x01u    /* + - * / round to nearest, ties to even, once */
#define ZW_SELFTEST_PRECISION 0x02u   /* significand of 24 (float) / 53 (double) bits */
#define ZW_SELFTEST_NAN 0x04u         /* 0/0 and inf-inf are NaN; NaN != NaN; NaN orders nothing */
#define ZW_SELFTEST_OVERFLOW 0x08u    /* overflow gives +-inf, and inf orders above ZW_REAL_MAX */
#define ZW_SELFTEST_UNDERFLOW 0x10u   /* gradual underflow: no flush to zero (FTZ), no DAZ */
#define ZW_SELFTEST_CONTRACTION 0x20u /* a * b - c rounds the product (no fused multiply-add) */
#define ZW_SELFTEST_LIBM 0x40u        /* ZW_EXP, ZW_EXPM1, ZW_SQRT, ZW_FREXP, ZW_LDEXP at exact points */

/* zw_selftest, also telling which properties failed: *failed gets the ZW_SELFTEST_* bits
 * of the failing properties (0 on ZW_OK).  ZW_ERR_NULL when failed is NULL. */
zw_status zw_selftest_failures(uint_least16_t *failed);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_SELFTEST_H */
