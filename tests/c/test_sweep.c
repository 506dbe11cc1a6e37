/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* The per-plant sweep (zwidth/sweep.h) against independent long-double references: the
 * fields from the literal formulas evaluated in long double (exact enough away from small
 * delta; the series near 0), the sweep's verdicts against zw_check's on points away from
 * the rounding band, and every error path fail-safe.  (The mpmath proof and ulps are in
 * tests/py/test_sweep.py.) */
#include "zw_test.h"

#include "zwidth/sweep.h"

/* e, g, 2/c2 and d12 in long double: series below 0.5 (positive terms), literal above. */
static void reference_fields(long double d, long double *e, long double *g, long double *w, long double *d12)
{
    long double c1, c2;
    *e = expl(-d);
    if (d < 0.5L) {
        long double p1 = 0, p2 = 0, p12 = 0, term = 1, f2 = 2; /* term = d^k, f2 = (k+2)! */
        int k;
        for (k = 0; k < 40; ++k) {
            p1 += 2.0L * (long double)(k + 1) / f2 * term;
            p2 += 2.0L / f2 * term;
            p12 += 2.0L * (long double)(k + 1) / (f2 * (long double)(k + 3)) * term;
            term *= d;
            f2 *= (long double)(k + 3);
        }
        c1 = *e * p1;
        c2 = *e * p2;
        *d12 = *e * d * p12;
    } else {
        c1 = 2.0L * (d - 1.0L + *e) / (d * d);
        c2 = 2.0L * (1.0L - *e - d * *e) / (d * d);
        *d12 = 2.0L * ((d + 2.0L) * *e + d - 2.0L) / (d * d);
    }
    *g = c1 / (c1 + c2);
    *w = 2.0L / c2;
}

static void test_fields_against_long_double(void **state)
{
    int i;
    (void)state;
    for (i = 0; i <= 4000; ++i) {
        const zw_real d = (zw_real)(1e-9L * powl(64e9L, (long double)i / 4000.0L)); /* 1e-9 .. 64 */
        long double e, g, w, d12;
        zw_sweep_fields f;
        EXPECT_OK(zw_sweep_fields_init(&f, d));
        reference_fields((long double)d, &e, &g, &w, &d12);
        /* the proved bounds (docs/numerics.md section 7), plus the reference's own error */
        EXPECT_REL(f.e, e, TOL(2.5));
        EXPECT_REL(f.g, g, TOL(5.5));
        EXPECT_REL((long double)f.hs * (long double)f.sigma, w, TOL(6.5));
        EXPECT_REL(f.d12, d12, TOL(7.5));
    }
}

static void test_fields_at_zero_and_beyond_64(void **state)
{
    zw_sweep_fields f;
    zw_coeffs c;
    (void)state;
    EXPECT_OK(zw_sweep_fields_init(&f, R(0.0)));
    EXPECT_REL(f.e, 1.0L, TOL(2));
    EXPECT_REL(f.g, 0.5L, TOL(2));
    EXPECT_REL(f.hs, 2.0L, TOL(2));
    assert_true(f.d12 == R(0.0));
    EXPECT_OK(zw_sweep_fields_init(&f, R(100.0))); /* zw_coeffs_init itself */
    EXPECT_OK(zw_coeffs_init(&c, R(100.0)));
    assert_true(f.e == c.e && f.g == c.g && f.hs == c.hs && f.d12 == c.d12 && f.sigma == c.sigma);
}

static void test_fields_error_paths(void **state)
{
    const zw_real bad[] = {R(-1.0), (zw_real)NAN, (zw_real)INFINITY};
    const zw_status want[] = {ZW_ERR_DELTA, ZW_ERR_NAN, ZW_ERR_INF};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(bad); ++i) {
        zw_sweep_fields f = {R(1.0), R(1.0), R(1.0), R(1.0), R(1.0)};
        EXPECT_STATUS(zw_sweep_fields_init(&f, bad[i]), want[i]);
        assert_true(ZW_IS_NAN(f.e) && ZW_IS_NAN(f.g) && ZW_IS_NAN(f.hs) && ZW_IS_NAN(f.d12) && ZW_IS_NAN(f.sigma));
    }
    EXPECT_STATUS(zw_sweep_fields_init(NULL, R(1.0)), ZW_ERR_NULL);
}

#define N_POINTS 20000

static void test_verdicts_equal_check_away_from_band(void **state)
{
    static zw_real d[N_POINTS], a[N_POINTS], b[N_POINTS];
    static bool s[N_POINTS];
    size_t i, compared = 0, differ = 0;
    unsigned long seed = 12345u;
    (void)state;
    for (i = 0; i < N_POINTS; ++i) {
        zw_coeffs c;
        zw_extremes x;
        seed = seed * 6364136223846793005ul + 1442695040888963407ul;
        d[i] = (zw_real)(1e-4L * powl(1e6L, (long double)(seed >> 11) / 9007199254740992.0L)); /* 1e-4 .. 100 */
        EXPECT_OK(zw_coeffs_init(&c, d[i]));
        EXPECT_OK(zw_extremes_compute(&c, &x));
        seed = seed * 6364136223846793005ul + 1442695040888963407ul;
        a[i] = (zw_real)((long double)x.alpha_mmax * 1.3L * (long double)(seed >> 11) / 9007199254740992.0L);
        seed = seed * 6364136223846793005ul + 1442695040888963407ul;
        b[i] = (zw_real)(-(long double)d[i] + ((long double)x.beta_mmax + (long double)d[i]) *
                         (long double)(seed >> 11) / 9007199254740992.0L);
    }
    EXPECT_OK(zw_sweep_check_many(N_POINTS, d, 1, a, 1, b, 1, s, NULL));
    for (i = 0; i < N_POINTS; ++i) {
        zw_coeffs c;
        zw_verdict v;
        zw_real rho;
        EXPECT_OK(zw_coeffs_init(&c, d[i]));
        EXPECT_OK(zw_check(&c, a[i], b[i], &v));
        EXPECT_OK(zw_spectral_radius(&c, a[i], b[i], &rho));
        if (ZW_FABS(rho - R(1.0)) > PREC(R(1e-9), R(1e-3))) {
            ++compared;
            differ += (size_t)(s[i] != v.stable);
        } else {
            assert_true(!s[i] || v.stable || v.marginal); /* in the band: never stable for a surely unstable one */
        }
    }
    assert_true(compared > N_POINTS / 2);
    assert_int_equal(differ, 0);
}

static void test_check_many_errors_fail_safe(void **state)
{
    zw_real d[3] = {R(1.0), R(-1.0), R(3.0)}, a[3] = {R(1.0), R(1.0), R(1.0)}, b[3] = {R(0.0), R(0.0), R(0.0)};
    bool s[4] = {true, true, true, true};
    size_t first = 99;
    (void)state;
    EXPECT_STATUS(zw_sweep_check_many(3, d, 1, a, 1, b, 1, s, &first), ZW_ERR_DELTA);
    assert_int_equal(first, 1);
    assert_true(!s[0] && !s[1] && !s[2] && s[3]); /* all false, nothing past n */
    d[1] = R(2.0);
    a[2] = (zw_real)NAN;
    EXPECT_STATUS(zw_sweep_check_many(3, d, 1, a, 1, b, 1, s, &first), ZW_ERR_NAN);
    assert_int_equal(first, 2);
    EXPECT_STATUS(zw_sweep_check_many(3, NULL, 1, a, 1, b, 1, s, NULL), ZW_ERR_NULL);
    EXPECT_OK(zw_sweep_check_many(0, NULL, 1, NULL, 1, NULL, 1, NULL, NULL));
    a[2] = R(0.1);
    EXPECT_OK(zw_sweep_check_many(3, d, 1, a, 0, b, 0, s, NULL)); /* strides 0 repeat a value */
    assert_true(s[0] && s[1] && s[2]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fields_against_long_double),
        cmocka_unit_test(test_fields_at_zero_and_beyond_64),
        cmocka_unit_test(test_fields_error_paths),
        cmocka_unit_test(test_verdicts_equal_check_away_from_band),
        cmocka_unit_test(test_check_many_errors_fail_safe),
    };
    printf("zwidth C tests: sweep (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("sweep_" ZW_REAL_NAME, tests, NULL, NULL);
}
