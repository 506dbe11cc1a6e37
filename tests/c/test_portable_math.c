/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The ZW_PORTABLE_MATH fallbacks against the host's libm and long double references:
 * zw_expm1_portable within ZW_EXPM1_PORTABLE_ULPS ulps of expm1l over the whole range,
 * zw_nextafterf_portable bit for bit equal to nextafterf.  They are built into every core,
 * so this runs on the normal build as well as on a -DZW_PORTABLE_MATH one. */
#include "zw_test.h"

#include "zwidth/portable_math.h"

/* Deterministic pseudo-random 32-bit words (LCG, Numerical Recipes constants). */
static uint32_t next_word(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s;
}

/* A pseudo-random value in [lo, hi]. */
static long double uniform(uint32_t *s, long double lo, long double hi)
{
    return lo + (hi - lo) * (long double)next_word(s) / 4294967295.0L;
}

/* ulps of zw_real between got and the reference want (long double). */
static long double ulps(zw_real got, long double want)
{
    return fabsl((long double)got - want) / zwt_ulp(want);
}

#ifdef ZW_REAL_FLOAT
#define ZWT_LIBM_EXPM1 expm1f
#else
#define ZWT_LIBM_EXPM1 expm1
#endif

/* Largest x with expm1(x) finite in zw_real. */
#define ZWT_EXPM1_MAX ((long double)ZW_REAL_MAX_EXP * 0.6931471805599453094L)

/* One point: the fallback within its documented bound; returns its error in ulps.  The
 * reference is expm1l of the zw_real input (long double: 11 more bits than double). */
static long double check_expm1_at(zw_real x)
{
    const long double want = expm1l((long double)x);
    const zw_real got = zw_expm1_portable(x);
    const long double err = ulps(got, want);
    EXPECT_TRUE_MSG(err <= (long double)ZW_EXPM1_PORTABLE_ULPS,
                    "zw_expm1_portable(%.9Lg) = %.21Lg, expm1l %.21Lg: %.3Lg ulp",
                    (long double)x, (long double)got, want, err);
    return err;
}

static void test_expm1_accuracy(void **state)
{
    uint32_t seed = 12345u;
    long double worst = 0.0L, worst_libm = 0.0L, e;
    unsigned i;
    int k;
    (void)state;
    /* dense where the series is used and across its edge at |x| = 1 */
    for (i = 0; i < 200000u; ++i) {
        const zw_real x = (zw_real)uniform(&seed, -1.25L, 1.25L);
        const long double libm_err = ulps(ZWT_LIBM_EXPM1(x), expm1l((long double)x));
        e = check_expm1_at(x);
        if (e > worst) worst = e;
        if (libm_err > worst_libm) worst_libm = libm_err;
    }
    /* every binade from the smallest normal to the overflow threshold, both signs */
    for (k = ZWT_MIN_EXP - 1; k < ZW_REAL_MAX_EXP; ++k) {
        for (i = 0; i < 64u; ++i) {
            const long double x = ldexpl(uniform(&seed, 1.0L, 2.0L), k);
            if (x < ZWT_EXPM1_MAX) {
                e = check_expm1_at((zw_real)x);
                if (e > worst) worst = e;
            }
            e = check_expm1_at((zw_real)-x);
            if (e > worst) worst = e;
        }
    }
    print_message("zw_expm1_portable (%s): max error %.3Lg ulp (bound %d); libm in [-1.25, 1.25]: "
                  "%.3Lg ulp\n", ZW_REAL_NAME, worst, ZW_EXPM1_PORTABLE_ULPS, worst_libm);
}

/* Exact cases and the special values. */
static void test_expm1_special(void **state)
{
    volatile zw_real zero = ZW_R(0.0);
    const zw_real inf = ZW_HUGE_VAL, nan = zero / zero;
    const zw_real sub = (zw_real)ZWT_TRUE_MIN;
    (void)state;
    assert_true(zw_expm1_portable(ZW_R(0.0)) == ZW_R(0.0));
    assert_true(zw_expm1_portable(sub) == sub); /* e^x - 1 = x (1 + x/2 ...) rounds to x */
    assert_true(zw_expm1_portable(ZW_REAL_MIN) == ZW_REAL_MIN);
    assert_true(zw_expm1_portable(inf) == inf);
    assert_true(zw_expm1_portable(-inf) == ZW_R(-1.0));
    assert_true(zw_expm1_portable(ZW_R(-1000.0)) == ZW_R(-1.0));
    assert_true(ZW_IS_NAN(zw_expm1_portable(nan)));
    assert_true(zw_expm1_portable(ZW_R(1000.0)) == inf);
}

static void expect_same_nextafterf(float x, float toward)
{
    const float got = zw_nextafterf_portable(x, toward), want = nextafterf(x, toward);
    if (want != want) {
        EXPECT_TRUE_MSG(got != got, "nextafterf(%a, %a): %a, want NaN", (double)x,
                        (double)toward, (double)got);
        return;
    }
    EXPECT_TRUE_MSG(zwt_bits_of(got) == zwt_bits_of(want), "nextafterf(%a, %a): %a (0x%08lx), libm %a (0x%08lx)",
                    (double)x, (double)toward, (double)got, (unsigned long)zwt_bits_of(got),
                    (double)want, (unsigned long)zwt_bits_of(want));
}

static void test_nextafterf_matches_libm(void **state)
{
    const float inf = ZW_HUGE_VALF;
    const float specials[] = {0.0f, -0.0f, FLT_MIN, -FLT_MIN, FLT_MAX, -FLT_MAX, inf, -inf,
                              1.0f, -1.0f, 0.5f, 2.0f, 3.0f, -0.75f, 1.0e-40f, -1.0e-40f,
                              zwt_float_of(0x00000001u), zwt_float_of(0x80000001u),
                              zwt_float_of(0x007FFFFFu), zwt_float_of(0x00800001u), zwt_float_of(0x7F7FFFFEu)};
    const float towards[] = {inf, -inf, 0.0f, -0.0f, 1.0f, -1.0f, FLT_MAX, -FLT_MIN};
    uint32_t seed = 777u;
    size_t i, j;
    unsigned n;
    (void)state;
    expect_same_nextafterf(zwt_float_of(0x7FC00000u), 1.0f); /* NaN in, NaN out */
    expect_same_nextafterf(1.0f, zwt_float_of(0x7FC00000u));
    for (i = 0; i < ZWT_ARRAY_LEN(specials); ++i) {
        for (j = 0; j < ZWT_ARRAY_LEN(towards); ++j)
            expect_same_nextafterf(specials[i], towards[j]);
        for (j = 0; j < ZWT_ARRAY_LEN(specials); ++j) expect_same_nextafterf(specials[i], specials[j]);
    }
    /* random finite values (every exponent), each way */
    for (n = 0; n < 400000u; ++n) {
        const uint32_t w = next_word(&seed);
        const float x = zwt_float_of(w);
        if ((w & 0x7F800000u) == 0x7F800000u) continue; /* inf / NaN: covered above */
        expect_same_nextafterf(x, inf);
        expect_same_nextafterf(x, -inf);
        expect_same_nextafterf(x, 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_expm1_accuracy),
        cmocka_unit_test(test_expm1_special),
        cmocka_unit_test(test_nextafterf_matches_libm),
    };
    return cmocka_run_group_tests_name("portable_math_" ZW_REAL_NAME, tests, NULL, NULL);
}
