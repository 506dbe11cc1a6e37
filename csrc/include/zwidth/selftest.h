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

#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ZW_OK when the floating-point environment is the one the error bounds assume;
 * ZW_ERR_FPENV otherwise.  No side effects; reentrant; constant time. */
zw_status zw_selftest(void);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_SELFTEST_H */
