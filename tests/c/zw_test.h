/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_test.h - shared helpers for the zwidth C unit tests (cmocka).
 *
 * Every test file is compiled twice: against zwidth_d (zw_real = double) and against
 * zwidth_f (ZW_REAL_FLOAT, zw_real = float).  Tolerances therefore scale with the
 * precision: TOL(k) is k unit roundoffs of the build's zw_real.
 *
 * Reference values are computed here independently of the library, in long double
 * (64-bit significand on x86-64, 2^11 times finer than double), from the paper's
 * definitions (or published numbers), never from the library's own output.
 */
#ifndef ZW_TEST_H
#define ZW_TEST_H

/* cmocka needs these before its header. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "zwidth/zwidth.h"

#ifdef ZW_REAL_FLOAT
#define ZWT_FLOAT 1
#define ZWT_MANT_DIG FLT_MANT_DIG
#define ZWT_MIN_EXP FLT_MIN_EXP
#define ZWT_TRUE_MIN ((zw_real)FLT_MIN * (zw_real)FLT_EPSILON)
#define ZWT_NEXTAFTER nextafterf
#else
#define ZWT_FLOAT 0
#define ZWT_MANT_DIG DBL_MANT_DIG
#define ZWT_MIN_EXP DBL_MIN_EXP
#define ZWT_TRUE_MIN (DBL_MIN * DBL_EPSILON)
#define ZWT_NEXTAFTER nextafter
#endif
#define ZWT_UP(x) ZWT_NEXTAFTER((x), (zw_real)INFINITY)     /* next zw_real above x */
#define ZWT_DOWN(x) ZWT_NEXTAFTER((x), -(zw_real)INFINITY)  /* next zw_real below x */

/* k unit roundoffs of zw_real (k may be any arithmetic expression). */
#define TOL(k) ((zw_real)(k) * ZW_UNIT_ROUNDOFF)
/* The same, as a long double, for tolerances that do not fit in zw_real arithmetic. */
#define TOLL(k) ((long double)(k) * (long double)ZW_UNIT_ROUNDOFF)
/* Pick a value by precision: PREC(double_value, float_value). */
#define PREC(d, f) (ZWT_FLOAT ? (f) : (d))
/* A literal of zw_real type without -Wconversion noise. */
#define R(x) ((zw_real)(x))

#define ZWT_ARRAY_LEN(a) (sizeof(a) / sizeof((a)[0]))

/* A byte pattern put into outputs before a call, so that a test sees which bytes the call
 * wrote (and that nothing past an output was touched). */
#define ZWT_SENTINEL 0x5A

/* The bits of a float and back (memcpy: a test may look at representations, the core
 * does not). */
static inline uint32_t zwt_bits_of(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static inline float zwt_float_of(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* ---- assertions that print the values involved ------------------------------------ */

static inline void zwt_expect_status(zw_status got, zw_status want, const char *expr,
                                     const char *file, int line)
{
    if (got != want) {
        print_error("%s:%d: %s returned %s, expected %s\n", file, line, expr,
                    zw_status_name(got), zw_status_name(want));
        _fail(file, line);
    }
}
#define EXPECT_STATUS(expr, want) zwt_expect_status((expr), (want), #expr, __FILE__, __LINE__)
#define EXPECT_OK(expr) EXPECT_STATUS(expr, ZW_OK)

/* |got - want| <= abs_tol + rel_tol |want| (fails on NaN). */
static inline void zwt_expect_near(long double got, long double want, long double abs_tol,
                                   long double rel_tol, const char *expr, const char *file,
                                   int line)
{
    long double err = fabsl(got - want);
    long double tol = abs_tol + rel_tol * fabsl(want);
    if (!(err <= tol)) {
        print_error("%s:%d: %s = %.21Lg, expected %.21Lg (|err| = %.3Lg > tol = %.3Lg)\n", file,
                    line, expr, got, want, err, tol);
        _fail(file, line);
    }
}
#define EXPECT_NEAR(got, want, abs_tol, rel_tol)                                                 \
    zwt_expect_near((long double)(got), (long double)(want), (long double)(abs_tol),             \
                    (long double)(rel_tol), #got, __FILE__, __LINE__)
#define EXPECT_REL(got, want, rel_tol) EXPECT_NEAR(got, want, 0, rel_tol)
#define EXPECT_ABS(got, want, abs_tol) EXPECT_NEAR(got, want, abs_tol, 0)

/* A boolean claim with a formatted explanation on failure. */
#define EXPECT_TRUE_MSG(cond, ...)                                                               \
    do {                                                                                         \
        if (!(cond)) {                                                                           \
            print_error("%s:%d: expected %s: ", __FILE__, __LINE__, #cond);                     \
            print_error(__VA_ARGS__);                                                            \
            print_error("\n");                                                                   \
            _fail(__FILE__, __LINE__);                                                           \
        }                                                                                        \
    } while (0)

/* ---- ulps ------------------------------------------------------------------------------ */

/* The spacing of zw_real numbers at |x| (the ulp of x), subnormals included. */
static inline long double zwt_ulp(long double x)
{
    int ex;
    int lowest = ZWT_MIN_EXP - ZWT_MANT_DIG; /* exponent of the smallest subnormal */
    (void)frexpl(fabsl(x), &ex);             /* |x| = f 2^ex, f in [1/2, 1) */
    if (x == 0.0L || ex - ZWT_MANT_DIG < lowest) return ldexpl(1.0L, lowest);
    return ldexpl(1.0L, ex - ZWT_MANT_DIG);
}

/* |got - want| <= k ulp(want), want an accurate reference. */
static inline void zwt_expect_ulps(zw_real got, long double want, long double k, const char *expr,
                                   const char *file, int line)
{
    long double err = fabsl((long double)got - want);
    long double ulp = zwt_ulp(want);
    if (!(err <= k * ulp)) {
        print_error("%s:%d: %s = %.21Lg, reference %.21Lg: error %.3Lg ulp > %.3Lg ulp\n", file,
                    line, expr, (long double)got, want, err / ulp, k);
        _fail(file, line);
    }
}
#define EXPECT_ULPS(got, want, k)                                                                \
    zwt_expect_ulps((got), (long double)(want), (long double)(k), #got, __FILE__, __LINE__)

/* ---- independent references -------------------------------------------------------- */

typedef struct zwt_ref {
    long double e, c1, c2, d12, s;
} zwt_ref;

/* The coefficient functions of paper eqs (3), (4) in long double.  Below delta = 1 the
 * paper's alternating Taylor series (shared/notes/math.md), whose terms shrink at once so
 * nothing cancels; above it the literal formulas, whose cancellation costs at most a
 * factor ~30 of long double precision there.  delta must be finite and >= 0. */
static inline zwt_ref zwt_reference(long double d)
{
    zwt_ref r;
    r.e = expl(-d);
    if (d < 1.0L) {
        /* t_n = d^n / (n+2)!:  c1 = 2 sum (-1)^n t_n,  c2 = 2 sum (-1)^n (n+1) t_n,
         * d12 = 2 sum_{n>=1} (-1)^(n+1) n t_n. */
        long double t = 0.5L, c1 = 0.0L, c2 = 0.0L, d12 = 0.0L, sign = 1.0L;
        int n;
        for (n = 0; n < 60; ++n) {
            c1 += sign * t;
            c2 += sign * (long double)(n + 1) * t;
            d12 -= sign * (long double)n * t;
            t *= d / (long double)(n + 3);
            sign = -sign;
        }
        r.c1 = 2.0L * c1;
        r.c2 = 2.0L * c2;
        r.d12 = 2.0L * d12;
        r.s = d == 0.0L ? 2.0L : -2.0L * expm1l(-d) / d;
    } else {
        long double one_minus_e = -expm1l(-d);
        r.c1 = 2.0L * ((d - one_minus_e) / d) / d;
        r.c2 = 2.0L * ((one_minus_e - d * r.e) / d) / d;
        r.d12 = 2.0L * (((d + 2.0L) * r.e + (d - 2.0L)) / d) / d;
        r.s = 2.0L * one_minus_e / d;
    }
    return r;
}

/* Fill a zw_coeffs, failing the test on any error. */
static inline zw_coeffs zwt_coeffs(zw_real delta)
{
    zw_coeffs c;
    memset(&c, 0, sizeof c);
    EXPECT_OK(zw_coeffs_init(&c, delta));
    return c;
}

/* Same-verdict comparison. */
static inline bool zwt_same_verdict(const zw_verdict *a, const zw_verdict *b)
{
    return a->stable == b->stable && a->marginal == b->marginal && a->deciding == b->deciding &&
           a->violated == b->violated;
}

/* ---- fail-safe outputs (status.h) ------------------------------------------------- */

/* The verdict every failed check writes. */
static inline bool zwt_failsafe_verdict(const zw_verdict *v)
{
    return !v->stable && !v->marginal && v->deciding == ZW_BOUND_INVALID &&
           v->violated == (uint_least16_t)ZW_BOUND_INVALID;
}

/* Every field of a coefficient set a failed zw_coeffs_init writes is NaN. */
static inline bool zwt_all_nan_coeffs(const zw_coeffs *c)
{
    const zw_real f[] = {c->delta, c->e, c->c1, c->c2, c->d12, c->s, c->g, c->sigma, c->hs,
                         c->delta_relerr};
    size_t i;
    for (i = 0; i < ZWT_ARRAY_LEN(f); ++i)
        if (!isnan(f[i])) return false;
    return true;
}

/* The deltas the brief and shared/notes/math.md single out, for sweeps. */
#define ZWT_SWEEP_DELTAS                                                                          \
    {                                                                                            \
        R(0.0), R(1e-6), R(0.013), R(1.0), R(2.3), R(3.0), R(5.12), R(20.0), R(1e4)               \
    }

#endif /* ZW_TEST_H */
