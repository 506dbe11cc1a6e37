/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_selftest: check, on the running target and with this build's zw_real, the arithmetic
 * properties the error bounds rely on (docs/fp-environment.md).
 *
 * Every operand is read from a volatile object, so the compiler cannot fold an expression
 * at build time (where it would use its own, correct, arithmetic): each check runs on the
 * target's FPU or soft-float routines, compiled with the flags of the rest of the build.
 * All checks always run (constant time); nothing but the stack is touched (reentrant).
 *
 * u below is the unit roundoff 2^-p (p = 24 or 53): 1 + 2u is the successor of 1, 1 - u
 * its predecessor.  All reference values are exact in zw_real.
 */
#include "zwidth/selftest.h"

#include <stdbool.h>
#include <stddef.h>

#include "zwidth/real.h"

/* The exact reference values, as compile-time constants (exactly representable, so the
 * compiler's own rounding does not matter). */
#define ST_U ZW_UNIT_ROUNDOFF
#define ST_ONE_2U (ZW_R(1.0) + ZW_R(2.0) * ST_U) /* successor of 1 */
#define ST_ONE_4U (ZW_R(1.0) + ZW_R(4.0) * ST_U) /* second successor of 1 */

static uint_least16_t flag(unsigned failed, uint_least16_t bit)
{
    return (failed != 0u) ? bit : (uint_least16_t)0u;
}

/* 1 when a property does not hold; the checks "or" these, so every one always runs. */
static unsigned fails(bool holds)
{
    return holds ? 0u : 1u;
}

/* Round to nearest, ties to even, one rounding per operation (no excess precision). */
static uint_least16_t check_rounding(zw_real one, zw_real u)
{
    const zw_real three_u = ZW_R(3.0) * u; /* exact */
    const zw_real up = one + ZW_R(2.0) * u, down = one - ZW_R(2.0) * u; /* exact */
    unsigned bad = 0u;
    bad |= fails(one + u == ZW_R(1.0));          /* tie 1 | 1+2u: even is 1 (not up, not away) */
    bad |= fails(one + three_u == ST_ONE_4U);    /* tie 1+2u | 1+4u: even is 1+4u (not truncated) */
    bad |= fails(-one - u == ZW_R(-1.0));        /* the same below zero (not toward -inf) */
    bad |= fails(-one - three_u == -ST_ONE_4U);  /* (not toward zero) */
    bad |= fails(up * down == ZW_R(1.0));        /* 1 - 4u^2: nearest is 1, truncation 1 - u */
    bad |= fails(up * up == ST_ONE_4U);          /* 1 + 4u + 4u^2: nearest 1 + 4u, upward 1 + 6u */
    bad |= fails(ST_ONE_4U / up == ST_ONE_2U);   /* 1 + 2u - 4u^2 + ...: nearest 1 + 2u, down 1 */
    return flag(bad, ZW_SELFTEST_ROUNDING);
}

/* The significand has exactly p bits: 1 + 2u is representable, 1 + u is not (tested above). */
static uint_least16_t check_precision(zw_real one, zw_real u)
{
    const zw_real up = one + ZW_R(2.0) * u;
    unsigned bad = 0u;
    bad |= fails(up != ZW_R(1.0));
    bad |= fails(up - one == ZW_R(2.0) * ST_U);
    return flag(bad, ZW_SELFTEST_PRECISION);
}

/* A NaN made at run time is unequal to itself and orders against nothing; it is what the
 * core's ZW_IS_NAN / ZW_IS_FINITE see. */
static uint_least16_t check_nan(zw_real zero, zw_real one, zw_real big)
{
    const zw_real nan1 = zero / zero;
    const zw_real inf = big * ZW_R(2.0);
    const zw_real nan2 = inf - inf;
    unsigned bad = 0u;
    bad |= fails(nan1 != nan1);
    bad |= fails(!(nan1 == nan1));
    bad |= fails(!(nan1 < one));
    bad |= fails(!(nan1 > one));
    bad |= fails(!(nan1 <= one));
    bad |= fails(!(nan1 >= one));
    bad |= fails(!(nan1 < inf));  /* NaN treated as infinity (TI C28x) fails here or above */
    bad |= fails(!(nan1 >= inf));
    bad |= fails(ZW_IS_NAN(nan2));
    bad |= fails(!(ZW_IS_FINITE(nan1)));
    bad |= fails(!(ZW_IS_FINITE(nan2)));
    bad |= fails(ZW_IS_NAN(nan1 * zero + one)); /* NaN propagates through arithmetic */
    return flag(bad, ZW_SELFTEST_NAN);
}

/* Overflow gives infinity, which is above every finite value and absorbs further growth. */
static uint_least16_t check_overflow(zw_real one, zw_real big)
{
    const zw_real inf = big * ZW_R(2.0);
    const zw_real ninf = -big * ZW_R(2.0);
    unsigned bad = 0u;
    bad |= fails(inf > big);
    bad |= fails(inf == big * ZW_R(4.0));
    bad |= fails(ninf < -big);
    bad |= fails(one / inf == ZW_R(0.0));
    bad |= fails(!(ZW_IS_FINITE(inf)));
    bad |= fails(!(ZW_IS_FINITE(ninf)));
    bad |= fails(big + one == ZW_REAL_MAX); /* no spurious overflow below the threshold */
    return flag(bad, ZW_SELFTEST_OVERFLOW);
}

/* Gradual underflow: the smallest normal number is kept, half of it is the exact
 * subnormal (not flushed to zero, FTZ), and a subnormal operand is used as itself (not as
 * zero, DAZ).  The ZW_ETA = ZW_REAL_MIN each bound adds per operation would cover the
 * error of one flushed result, but flushing also turns quotients of two flushed fields
 * into 0/0 = NaN (zw_coeffs_init at delta = ZW_REAL_MAX: g) and makes a negative subnormal
 * compare equal to zero (zw_device_init accepts b = -2^-1074 as b = 0): outcomes the
 * bounds were not derived for (docs/fp-environment.md), so FTZ / DAZ are refused. */
static uint_least16_t check_underflow(zw_real tiny, zw_real sub, zw_real one)
{
    const zw_real half = tiny * ZW_R(0.5);
    const zw_real square = tiny * tiny;
    unsigned bad = 0u;
    bad |= fails(tiny > ZW_R(0.0));
    bad |= fails(tiny * one == ZW_REAL_MIN);
    bad |= fails(half > ZW_R(0.0) && half + half == ZW_REAL_MIN);      /* FTZ gives 0 */
    bad |= fails(sub > ZW_R(0.0) && sub + sub == ZW_REAL_MIN);         /* DAZ reads 0 */
    bad |= fails(-sub < ZW_R(0.0));
    bad |= fails(square == ZW_R(0.0)); /* below the subnormal range: 0 */
    bad |= fails((tiny * ZW_R(3.0)) * ZW_R(0.5) == ZW_R(1.5) * ZW_REAL_MIN); /* normal: exact */
    return flag(bad, ZW_SELFTEST_UNDERFLOW);
}

/* a * a - c with a = 1 + 2u, c = 1 + 4u: rounding the product first gives exactly 0; a
 * fused multiply-add gives 4u^2.  Written as the core writes its discriminants (margin.c:
 * hp * hp - q), within one expression and across two statements.  Each product reads its
 * own operands from the volatile objects: a product shared with a comparison elsewhere
 * (common subexpression) would not be fused, and the check would miss the contraction. */
static uint_least16_t check_contraction(const volatile zw_real *a, const volatile zw_real *c)
{
    const zw_real a1 = *a, c1 = *c, a2 = *a, c2 = *c, a3 = *a, c3 = *c;
    const zw_real fused_in_expression = a1 * a1 - c1;
    const zw_real negated = c2 - a2 * a2;
    const zw_real square = a3 * a3;
    const zw_real fused_across_statements = square - c3;
    unsigned bad = 0u;
    bad |= fails(fused_in_expression == ZW_R(0.0));
    bad |= fails(negated == ZW_R(0.0));
    bad |= fails(fused_across_statements == ZW_R(0.0));
    return flag(bad, ZW_SELFTEST_CONTRACTION);
}

/* |r - ref| within one ulp of ref (an ulp is at most 2u |ref|). */
static bool within_ulp(zw_real r, zw_real ref)
{
    return ZW_FABS(r - ref) <= ZW_R(2.0) * ST_U * ZW_FABS(ref);
}

/* The library functions the core calls, at points with known results: exact where the
 * function is exact, within an ulp where ZW_COEF_ULPS assumes a good libm. */
static uint_least16_t check_libm(zw_real zero, zw_real one, zw_real u)
{
    const zw_real tiny_x = u * u; /* expm1(x) = x (1 + x/2 + ...) rounds to x */
    const zw_real square = ZW_R(4095.0) * ZW_R(4095.0) * one; /* 16769025 < 2^24: exact */
    const zw_real up2 = one + ZW_R(4.0) * u;
    int e2 = 0, e3 = 0;
    const zw_real m2 = ZW_FREXP(one + one, &e2);
    const zw_real m3 = ZW_FREXP(ZW_R(3.0) * one, &e3);
    unsigned bad = 0u;
    bad |= fails(ZW_EXP(zero) == ZW_R(1.0));
    bad |= fails(ZW_EXPM1(zero) == ZW_R(0.0));
    bad |= fails(ZW_EXPM1(tiny_x) == tiny_x);
    bad |= fails(within_ulp(ZW_EXP(one), ZW_R(2.718281828459045235360287)));
    bad |= fails(within_ulp(ZW_EXP(-one), ZW_R(0.3678794411714423215955238)));
    bad |= fails(within_ulp(ZW_EXP(ZW_R(10.0) * one), ZW_R(22026.46579480671651695790)));
    bad |= fails(within_ulp(ZW_EXPM1(one), ZW_R(1.718281828459045235360287)));
    bad |= fails(within_ulp(ZW_EXPM1(-one), ZW_R(-0.6321205588285576784044762)));
    bad |= fails(within_ulp(ZW_EXPM1(ZW_R(0.0078125) * one), ZW_R(0.007843097206447977120265683)));
    bad |= fails(ZW_SQRT(square) == ZW_R(4095.0));
    bad |= fails(ZW_SQRT(ZW_R(0.25) * one) == ZW_R(0.5));
    bad |= fails(ZW_SQRT(up2) == ST_ONE_2U); /* 1 + 2u - 2u^2 + ...: correctly rounded */
    bad |= fails(m2 == ZW_R(0.5) && e2 == 2);
    bad |= fails(m3 == ZW_R(0.75) && e3 == 2);
    bad |= fails(ZW_LDEXP(one, -3) == ZW_R(0.125));
    return flag(bad, ZW_SELFTEST_LIBM);
}

zw_status zw_selftest_failures(uint_least16_t *failed)
{
    /* Read once from volatile objects: the compiler knows nothing of these values. */
    volatile zw_real v_zero = ZW_R(0.0), v_one = ZW_R(1.0), v_u = ST_U;
    volatile zw_real v_big = ZW_REAL_MAX, v_tiny = ZW_REAL_MIN;
    volatile zw_real v_sub = ZW_REAL_MIN * ZW_R(0.5); /* a subnormal, exact */
    volatile zw_real v_succ1 = ST_ONE_2U, v_succ2 = ST_ONE_4U;
    const zw_real zero = v_zero, one = v_one, u = v_u, big = v_big, tiny = v_tiny, sub = v_sub;
    uint_least16_t bits;
    if (failed == NULL) {
        return ZW_ERR_NULL;
    }
    bits = (uint_least16_t)(check_rounding(one, u) | check_precision(one, u) |
                            check_nan(zero, one, big) | check_overflow(one, big) |
                            check_underflow(tiny, sub, one) | check_contraction(&v_succ1, &v_succ2) |
                            check_libm(zero, one, u));
    *failed = bits;
    return bits == 0u ? ZW_OK : ZW_ERR_FPENV;
}

zw_status zw_selftest(void)
{
    uint_least16_t failed = 0u;
    return zw_selftest_failures(&failed);
}
