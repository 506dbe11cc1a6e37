/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Portable C99 fallbacks for expm1 and nextafterf (zwidth/portable_math.h). */
#include "zwidth/portable_math.h"

#include <stdbool.h>

/* 1/(k+2)! for k = 0.. : Q(x) = (e^x - 1 - x) / x^2 = sum_k x^k / (k+2)!.  Enough terms
 * that the first one left out is below u/8 of Q for |x| <= 1. */
#ifdef ZW_REAL_FLOAT
#define EXPM1_TERMS 10u
#else
#define EXPM1_TERMS 18u
#endif
static const zw_real k_inv_factorial[EXPM1_TERMS] = {
    ZW_R(0.5),
    ZW_R(0.16666666666666666666666667),
    ZW_R(0.041666666666666666666666667),
    ZW_R(0.0083333333333333333333333333),
    ZW_R(0.0013888888888888888888888889),
    ZW_R(0.00019841269841269841269841270),
    ZW_R(0.000024801587301587301587301587),
    ZW_R(2.7557319223985890652557319e-6),
    ZW_R(2.7557319223985890652557319e-7),
    ZW_R(2.5052108385441718775052108e-8),
#ifndef ZW_REAL_FLOAT
    ZW_R(2.0876756987868098979210091e-9),
    ZW_R(1.6059043836821614599392378e-10),
    ZW_R(1.1470745597729724713851699e-11),
    ZW_R(7.6471637318198164759011320e-13),
    ZW_R(4.7794773323873852974382075e-14),
    ZW_R(2.8114572543455207631989456e-15),
    ZW_R(1.5619206968586226462216364e-16),
    ZW_R(8.2206352466243297169559812e-18),
#endif
};

zw_real zw_expm1_portable(zw_real x)
{
    zw_real q;
    unsigned k;
    /* Away from 0 there is no cancellation to avoid: exp(x) - 1 loses at most a factor
     * e / (e - 1) = 1.58 of exp's relative error (at x = 1; less beyond).  NaN and the
     * infinities take this path too. */
    if (!(ZW_FABS(x) <= ZW_R(1.0))) {
        return ZW_EXP(x) - ZW_R(1.0);
    }
    /* x + x^2 Q(x): x is exact, and the correction is at most 0.58 of the result. */
    q = k_inv_factorial[EXPM1_TERMS - 1u];
    for (k = EXPM1_TERMS - 1u; k > 0u; --k) {
        q = q * x + k_inv_factorial[k - 1u];
    }
    return x + (x * x) * q;
}

float zw_nextafterf_portable(float x, float toward)
{
    int e = 0;
    float m;
    float step;
    float next_mag;
    bool away; /* moving away from zero */
    if (x != x || toward != toward) { /* NaN */
        return x + toward;
    }
    if (x == toward) {
        return toward;
    }
    /* from zero: the smallest subnormal, 2^(FLT_MIN_EXP - FLT_MANT_DIG) = 2^-149 */
    if (x == 0.0f) {
        const float smallest = ldexpf(1.0f, FLT_MIN_EXP - FLT_MANT_DIG);
        return toward > 0.0f ? smallest : -smallest;
    }
    if (!(fabsf(x) <= FLT_MAX)) { /* from an infinity */
        return x > 0.0f ? FLT_MAX : -FLT_MAX;
    }
    /* x = m 2^e with 0.5 <= |m| < 1: the spacing above |x| is 2^(e - 24); just below a
     * power of two it is half that; below FLT_MIN it is fixed at 2^-149.  x +- step is
     * exact (or overflows to infinity above FLT_MAX, as nextafterf does). */
    m = frexpf(x, &e);
    away = (toward > x) == (x > 0.0f);
    /* x is finite and nonzero: e is in [-148, 128]; clamping to FLT_MIN_EXP here as well
     * as below changes nothing and keeps the decrement from overflowing whatever a frexpf
     * returned (tools/eva.sh cannot know its range otherwise). */
    if (e < FLT_MIN_EXP) {
        e = FLT_MIN_EXP;
    }
    if (!away && fabsf(m) == 0.5f) {
        e -= 1;
    }
    if (e < FLT_MIN_EXP) {
        e = FLT_MIN_EXP;
    }
    step = ldexpf(1.0f, e - FLT_MANT_DIG);
    /* on the magnitude, so that a step to zero keeps x's sign (-2^-149 -> -0, as in C99) */
    next_mag = away ? fabsf(x) + step : fabsf(x) - step;
    return x < 0.0f ? -next_mag : next_mag;
}
