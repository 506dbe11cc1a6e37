/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_coeffs_init: the coefficient functions c1, c2, d12 of paper eqs (3), (4) and the
 * derived fields, their limits, identities, accuracy and error handling; and that the
 * core keeps no global state (reentrancy). */
#include "zw_test.h"

/* ---- delta grids ---------------------------------------------------------------------- */

#define ZWT_MAX_GRID 4096

/* Geometric grid from lo to hi (ratio q), ascending. */
static size_t log_grid(zw_real *out, size_t cap, zw_real lo, zw_real hi, zw_real q)
{
    size_t n = 0;
    zw_real d = lo;
    while (d <= hi && n < cap) {
        out[n++] = d;
        d *= q;
    }
    return n;
}

/* The hard cases of shared/notes/math.md: 0, subnormal, tiny, cancellation range, the
 * series/literal switch at 2, every critical constant and its neighbours, large. */
static size_t hard_cases(zw_real *out)
{
    static const zw_real crit[] = {ZW_DELTA0,   ZW_DELTA1,   ZW_DELTA2,  ZW_DELTA_K1,
                                   ZW_DELTA_K2, ZW_DELTA_B,  ZW_DELTA_KM, R(2.0),
                                   R(1.0),      R(0.013),    R(5.1224)};
    size_t n = 0, i;
    out[n++] = R(0.0);
    out[n++] = ZWT_TRUE_MIN;
    out[n++] = ZW_REAL_MIN;
    out[n++] = R(PREC(1e-300, 1e-37));
    out[n++] = R(1e-12);
    out[n++] = R(1e-9);
    out[n++] = R(1e-6);
    out[n++] = R(1e-4);
    out[n++] = R(1e-2);
    out[n++] = R(0.5);
    for (i = 0; i < ZWT_ARRAY_LEN(crit); ++i) {
        out[n++] = ZWT_DOWN(crit[i]);
        out[n++] = crit[i];
        out[n++] = ZWT_UP(crit[i]);
    }
    out[n++] = R(10.0);
    out[n++] = R(1e6);
    out[n++] = R(1e12);
    out[n++] = R(1e19);
    out[n++] = R(PREC(1e154, 1e30));
    out[n++] = R(PREC(1e300, 1e37));
    out[n++] = ZW_REAL_MAX / R(4.0);
    return n;
}

/* Log grid over the whole useful range plus the hard cases. */
static size_t all_deltas(zw_real *out, size_t cap)
{
    size_t n = log_grid(out, cap, R(PREC(1e-300, 1e-37)), R(PREC(1e300, 1e37)), R(1.5));
    assert_true(n + 64 <= cap);
    n += hard_cases(out + n);
    return n;
}

static bool all_finite(const zw_coeffs *c)
{
    return isfinite(c->delta) && isfinite(c->e) && isfinite(c->c1) && isfinite(c->c2) &&
           isfinite(c->d12) && isfinite(c->s) && isfinite(c->g) && isfinite(c->sigma) &&
           isfinite(c->hs) && isfinite(c->delta_relerr);
}

/* ---- tests --------------------------------------------------------------------------- */

/* delta = 0: the limits c1 = c2 = 1, d12 = 0, s = 2, g = 1/2 (and e = 1, hs = 2/c2). */
static void test_delta_zero(void **state)
{
    zw_real zeros[2];
    size_t i;
    (void)state;
    zeros[0] = R(0.0);
    zeros[1] = -R(0.0); /* -0 is not negative */
    for (i = 0; i < 2; ++i) {
        zw_coeffs c = zwt_coeffs(zeros[i]);
        assert_true(c.c1 == R(1.0));
        assert_true(c.c2 == R(1.0));
        assert_true(c.d12 == R(0.0));
        assert_true(c.s == R(2.0));
        assert_true(c.g == R(0.5));
        assert_true(c.e == R(1.0));
        assert_true(c.sigma == R(1.0));
        assert_true(c.hs == R(2.0));
        assert_true(c.delta == R(0.0));
        assert_true(c.delta_relerr == R(0.0));
    }
}

/* c1 - c2 == d12 and c1 + c2 == s (= 2 (1 - e) / delta) to a few ulps, g = c1 / s. */
static void test_identities(void **state)
{
    static zw_real grid[ZWT_MAX_GRID];
    size_t n = all_deltas(grid, ZWT_MAX_GRID), i;
    (void)state;
    for (i = 0; i < n; ++i) {
        zw_coeffs c = zwt_coeffs(grid[i]);
        long double c1 = c.c1, c2 = c.c2, d12 = c.d12, s = c.s;
        /* each field within ZW_COEF_ULPS ulps (<= 2u relative each): 16 u of c1 + c2 */
        long double tol = TOLL(4 * ZW_COEF_ULPS) * (c1 + c2) + (long double)ZW_REAL_MIN;
        EXPECT_TRUE_MSG(fabsl(c1 - c2 - d12) <= tol,
                        "delta %.9Lg: c1 - c2 - d12 = %.3Lg, tol %.3Lg", (long double)grid[i],
                        c1 - c2 - d12, tol);
        EXPECT_TRUE_MSG(fabsl(c1 + c2 - s) <= TOLL(4 * ZW_COEF_ULPS) * s + (long double)ZW_REAL_MIN,
                        "delta %.9Lg: c1 + c2 - s = %.3Lg", (long double)grid[i], c1 + c2 - s);
        EXPECT_NEAR(c.g * c.s, c.c1, ZW_REAL_MIN, TOLL(4));
        /* s = 2 (1 - e) / delta with the paper's e (no cancellation in -expm1) */
        if (grid[i] > R(0.0))
            EXPECT_NEAR(c.s, -2.0L * expm1l(-(long double)grid[i]) / (long double)grid[i],
                        ZW_REAL_MIN, TOLL(2 * ZW_COEF_ULPS));
    }
}

/* Every field against the long-double reference, to the ZW_COEF_ULPS the header states
 * ("worst error of every coefficient field below"). */
static void test_accuracy_vs_reference(void **state)
{
    static zw_real grid[ZWT_MAX_GRID];
    size_t n = all_deltas(grid, ZWT_MAX_GRID), i;
    (void)state;
    for (i = 0; i < n; ++i) {
        zw_coeffs c = zwt_coeffs(grid[i]);
        zwt_ref r = zwt_reference((long double)grid[i]);
        EXPECT_ULPS(c.e, r.e, ZW_COEF_ULPS);
        EXPECT_ULPS(c.c1, r.c1, ZW_COEF_ULPS);
        EXPECT_ULPS(c.c2, r.c2, ZW_COEF_ULPS);
        EXPECT_ULPS(c.d12, r.d12, ZW_COEF_ULPS);
        EXPECT_ULPS(c.s, r.s, ZW_COEF_ULPS);
        EXPECT_ULPS(c.g, r.c1 / r.s, ZW_COEF_ULPS);
        /* hs = (2 / c2) / sigma, finite even where c2 underflows */
        EXPECT_ULPS(c.hs, 2.0L / (r.c2 * (long double)c.sigma), ZW_COEF_ULPS);
    }
}

/* sigma: 1 for delta <= 1, else the smallest power of two >= delta. */
static void test_sigma(void **state)
{
    static zw_real grid[ZWT_MAX_GRID];
    size_t n = all_deltas(grid, ZWT_MAX_GRID), i;
    (void)state;
    for (i = 0; i < n; ++i) {
        zw_coeffs c = zwt_coeffs(grid[i]);
        int ex;
        long double f = frexpl((long double)c.sigma, &ex);
        assert_true(f == 0.5L); /* a power of two */
        if (grid[i] <= R(1.0)) {
            assert_true(c.sigma == R(1.0));
        } else {
            EXPECT_TRUE_MSG(c.sigma >= grid[i] && (long double)c.sigma < 2.0L * (long double)grid[i],
                            "delta %.9Lg sigma %.9Lg", (long double)grid[i], (long double)c.sigma);
        }
    }
}

/* 0 < c2 <= c1 <= 1, c1 > c2 once delta is resolvable, both non-increasing in delta and
 * strictly decreasing wherever the step is resolvable; d12 > 0 for delta > 0. */
static void test_order_and_monotonic(void **state)
{
    static zw_real grid[ZWT_MAX_GRID];
    size_t n = log_grid(grid, ZWT_MAX_GRID, R(PREC(1e-300, 1e-37)), R(PREC(1e300, 1e37)), R(1.5));
    size_t i;
    zw_real strict_lo = R(PREC(1e-9, 1e-3)); /* c1 - c2 ~ delta/3 well above 2 ulps of 1 */
    zw_coeffs prev = zwt_coeffs(R(0.0));
    (void)state;
    for (i = 0; i < n; ++i) {
        zw_coeffs c = zwt_coeffs(grid[i]);
        assert_true(c.c1 <= R(1.0) && c.c2 <= R(1.0));
        assert_true(c.c2 >= R(0.0) && c.c1 > R(0.0));
        assert_true(c.c1 >= c.c2);
        assert_true(c.d12 > R(0.0));
        /* mathematically decreasing; each value may be off by ZW_COEF_ULPS ulps */
        EXPECT_TRUE_MSG((long double)c.c1 <= (long double)prev.c1 + 2 * ZW_COEF_ULPS * zwt_ulp(prev.c1),
                        "delta %.17Lg: c1 %.17Lg > c1 at the previous delta %.17Lg",
                        (long double)grid[i], (long double)c.c1, (long double)prev.c1);
        EXPECT_TRUE_MSG((long double)c.c2 <= (long double)prev.c2 + 2 * ZW_COEF_ULPS * zwt_ulp(prev.c2),
                        "delta %.17Lg: c2 %.17Lg > c2 at the previous delta %.17Lg",
                        (long double)grid[i], (long double)c.c2, (long double)prev.c2);
        if (grid[i] >= strict_lo) {
            assert_true(c.c1 > c.c2);
            assert_true(c.c1 < prev.c1);
            if (prev.c2 > R(4.0) * ZW_REAL_MIN) assert_true(c.c2 < prev.c2);
        }
        if (c.c2 >= ZW_REAL_MIN) assert_true(c.c2 > R(0.0));
        prev = c;
    }
}

/* Large delta: c1 ~ 2/delta, c2 ~ 2/delta^2, d12 ~ 2/delta, s = 2/delta, g -> 1 and
 * hs = delta^2/sigma, no overflow; 1e300 (double) where delta^2 overflows and c2 underflows. */
static void test_large_delta(void **state)
{
    static const zw_real ds[] = {R(1e6), R(1e12), R(PREC(1e19, 1e19)), R(PREC(1e300, 1e30))};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        long double d = ds[i];
        zw_coeffs c = zwt_coeffs(ds[i]);
        assert_true(all_finite(&c));
        assert_true(c.e == R(0.0)); /* exp(-1e6) underflows */
        /* c1 = (2/d)(1 - 1/d) exactly when e = 0 */
        EXPECT_REL(c.c1 * d / 2.0L, 1.0L, 1.0L / d + TOLL(2 * ZW_COEF_ULPS + 2));
        EXPECT_REL(c.d12 * d / 2.0L, 1.0L, 2.0L / d + TOLL(2 * ZW_COEF_ULPS + 2));
        EXPECT_REL(c.s * d / 2.0L, 1.0L, TOLL(2 * ZW_COEF_ULPS + 2));
        EXPECT_REL(c.g, 1.0L, 1.0L / d + TOLL(2 * ZW_COEF_ULPS + 2));
        /* c2 = 2/d^2 where that is a normal number; else it may underflow (header) */
        if (2.0L / (d * d) >= (long double)ZW_REAL_MIN)
            EXPECT_REL(c.c2 * d * d / 2.0L, 1.0L, TOLL(2 * ZW_COEF_ULPS + 2));
        else
            assert_true(c.c2 >= R(0.0) && c.c2 <= ZW_REAL_MIN);
        /* hs = (2/c2)/sigma = d^2/sigma stays finite and right even there */
        EXPECT_REL((long double)c.hs * (long double)c.sigma / (d * d), 1.0L,
                   TOLL(2 * ZW_COEF_ULPS + 2));
    }
}

/* No NaN and no infinity in any field for finite delta up to max/2 (beyond it hs alone
 * is documented to become +inf); no NaN anywhere for any finite delta. */
static void test_finite_fields(void **state)
{
    static zw_real grid[ZWT_MAX_GRID];
    size_t n = all_deltas(grid, ZWT_MAX_GRID), i;
    zw_coeffs c;
    (void)state;
    for (i = 0; i < n; ++i) {
        c = zwt_coeffs(grid[i]);
        EXPECT_TRUE_MSG(all_finite(&c), "delta %.9Lg: a field is not finite", (long double)grid[i]);
    }
    c = zwt_coeffs(ZW_REAL_MAX);
    assert_false(isnan(c.e) || isnan(c.c1) || isnan(c.c2) || isnan(c.d12) || isnan(c.s) ||
                 isnan(c.g) || isnan(c.sigma) || isnan(c.hs));
    assert_true(isfinite(c.c1) && isfinite(c.c2) && isfinite(c.d12) && isfinite(c.s) &&
                isfinite(c.g) && isfinite(c.sigma) && isfinite(c.e));
    assert_true(isinf(c.hs) && c.hs > R(0.0)); /* documented: +inf beyond ~max/2 */
    /* exactly 2^(max_exp - 1) (= sigma, hs = delta / n2) is still finite */
    c = zwt_coeffs(ZW_LDEXP(R(1.0), ZW_REAL_MAX_EXP - 1));
    assert_true(all_finite(&c));
}

/* delta = +inf: e = c1 = c2 = d12 = s = 0, g = 1, sigma = hs = +inf (header). */
static void test_delta_infinite(void **state)
{
    zw_coeffs c = zwt_coeffs((zw_real)INFINITY);
    (void)state;
    assert_true(isinf(c.delta) && c.delta > R(0.0));
    assert_true(c.e == R(0.0));
    assert_true(c.c1 == R(0.0));
    assert_true(c.c2 == R(0.0));
    assert_true(c.d12 == R(0.0));
    assert_true(c.s == R(0.0));
    assert_true(c.g == R(1.0));
    assert_true(isinf(c.sigma) && c.sigma > R(0.0));
    assert_true(isinf(c.hs) && c.hs > R(0.0));
}

/* Errors: NaN -> ZW_ERR_NAN, negative -> ZW_ERR_DELTA, NULL -> ZW_ERR_NULL; the output is
 * fail-safe: every field NaN, and a check on it refuses with ZW_ERR_NAN. */
static void test_errors_leave_output_nan(void **state)
{
    static const struct {
        zw_real delta;
        zw_status want;
    } cases[] = {
        {(zw_real)NAN, ZW_ERR_NAN},      {-(zw_real)NAN, ZW_ERR_NAN},
        {R(-1.0), ZW_ERR_DELTA},         {-(zw_real)INFINITY, ZW_ERR_DELTA},
        {-ZWT_TRUE_MIN, ZW_ERR_DELTA},   {-ZW_REAL_MAX, ZW_ERR_DELTA},
        {R(-1e-30), ZW_ERR_DELTA},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_coeffs out = zwt_coeffs(R(1.0)); /* a valid plant must not survive */
        zw_verdict v;
        EXPECT_STATUS(zw_coeffs_init(&out, cases[i].delta), cases[i].want);
        assert_true(zwt_all_nan_coeffs(&out));
        EXPECT_STATUS(zw_check(&out, R(0.1), R(0.1), &v), ZW_ERR_NAN);
        assert_true(zwt_failsafe_verdict(&v));
    }
    EXPECT_STATUS(zw_coeffs_init(NULL, R(1.0)), ZW_ERR_NULL);
    EXPECT_STATUS(zw_coeffs_init(NULL, (zw_real)NAN), ZW_ERR_NULL);
}

/* The literal formulas: same limits at 0, same errors, and agreement with the careful
 * ones where eqs (3), (4) do not cancel (delta >= 2, both precisions). */
static void test_literal(void **state)
{
    static const zw_real ds[] = {R(2.0), R(3.0), R(5.1224), R(10.0), R(100.0)};
    zw_real c1 = R(7.0), c2 = R(7.0), d12 = R(7.0);
    size_t i;
    (void)state;
    EXPECT_OK(zw_coeffs_literal(R(0.0), &c1, &c2, &d12));
    assert_true(c1 == R(1.0) && c2 == R(1.0) && d12 == R(0.0));
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        zwt_ref r = zwt_reference((long double)ds[i]);
        EXPECT_OK(zw_coeffs_literal(ds[i], &c1, &c2, &d12));
        EXPECT_REL(c1, r.c1, TOLL(64));
        EXPECT_REL(c2, r.c2, TOLL(64));
        EXPECT_REL(d12, r.d12, TOLL(256));
    }
    c1 = c2 = d12 = R(7.0);
    EXPECT_STATUS(zw_coeffs_literal((zw_real)NAN, &c1, &c2, &d12), ZW_ERR_NAN);
    assert_true(isnan(c1) && isnan(c2) && isnan(d12));
    c1 = c2 = d12 = R(7.0);
    EXPECT_STATUS(zw_coeffs_literal(R(-1.0), &c1, &c2, &d12), ZW_ERR_DELTA);
    assert_true(isnan(c1) && isnan(c2) && isnan(d12));
    EXPECT_STATUS(zw_coeffs_literal(R(1.0), NULL, &c2, &d12), ZW_ERR_NULL);
    EXPECT_STATUS(zw_coeffs_literal(R(1.0), &c1, NULL, &d12), ZW_ERR_NULL);
    EXPECT_STATUS(zw_coeffs_literal(R(1.0), &c1, &c2, NULL), ZW_ERR_NULL);
}

/* Continuity across the series/literal switch at delta = 2: the neighbours of 2 differ
 * from each other by about the function's own slope times one ulp. */
static void test_switch_continuity(void **state)
{
    zw_coeffs lo = zwt_coeffs(ZWT_DOWN(R(2.0))), mid = zwt_coeffs(R(2.0)),
              hi = zwt_coeffs(ZWT_UP(R(2.0)));
    (void)state;
    EXPECT_REL(lo.c1, mid.c1, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(hi.c1, mid.c1, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(lo.c2, mid.c2, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(hi.c2, mid.c2, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(lo.d12, mid.d12, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(hi.d12, mid.d12, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(lo.hs * lo.sigma, mid.hs * mid.sigma, TOLL(4 * ZW_COEF_ULPS));
    EXPECT_REL(hi.hs * hi.sigma, mid.hs * mid.sigma, TOLL(4 * ZW_COEF_ULPS));
}

/* No global state: two plants computed interleaved give bit-identical coefficients and
 * verdicts to the same plants computed alone, and nothing writes through a const plant. */
static void test_reentrancy(void **state)
{
    const zw_real da = R(0.013), db = R(5.1224);
    zw_coeffs a_alone, b_alone, a, b, a_copy, b_copy;
    zw_verdict va_alone[3], vb_alone[3], va, vb;
    zw_real ra_alone[3], rb_alone[3], ra, rb;
    zw_extremes xa_alone, xb_alone, xa, xb;
    static const zw_real alphas[3] = {R(0.3), R(15.0), R(23.0)};
    static const zw_real betas[3] = {R(0.5), R(4.0), R(-1.5)};
    int i, round;
    (void)state;

    memset(&a_alone, 0, sizeof a_alone);
    memset(&b_alone, 0, sizeof b_alone);
    EXPECT_OK(zw_coeffs_init(&a_alone, da));
    for (i = 0; i < 3; ++i) {
        EXPECT_OK(zw_check(&a_alone, alphas[i], betas[i], &va_alone[i]));
        EXPECT_OK(zw_spectral_radius(&a_alone, alphas[i], betas[i], &ra_alone[i]));
    }
    EXPECT_OK(zw_extremes_compute(&a_alone, &xa_alone));
    EXPECT_OK(zw_coeffs_init(&b_alone, db));
    for (i = 0; i < 3; ++i) {
        EXPECT_OK(zw_check(&b_alone, alphas[i], betas[i], &vb_alone[i]));
        EXPECT_OK(zw_spectral_radius(&b_alone, alphas[i], betas[i], &rb_alone[i]));
    }
    EXPECT_OK(zw_extremes_compute(&b_alone, &xb_alone));

    for (round = 0; round < 3; ++round) {
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        EXPECT_OK(zw_coeffs_init(&a, da));
        EXPECT_OK(zw_coeffs_init(&b, db));
        EXPECT_OK(zw_coeffs_init(&a, da)); /* again, after the other plant */
        assert_memory_equal(&a, &a_alone, sizeof a);
        assert_memory_equal(&b, &b_alone, sizeof b);
        memcpy(&a_copy, &a, sizeof a);
        memcpy(&b_copy, &b, sizeof b);
        for (i = 0; i < 3; ++i) {
            EXPECT_OK(zw_check(&a, alphas[i], betas[i], &va));
            EXPECT_OK(zw_check(&b, alphas[i], betas[i], &vb));
            assert_true(zwt_same_verdict(&va, &va_alone[i]));
            assert_true(zwt_same_verdict(&vb, &vb_alone[i]));
            EXPECT_OK(zw_spectral_radius(&b, alphas[i], betas[i], &rb));
            EXPECT_OK(zw_spectral_radius(&a, alphas[i], betas[i], &ra));
            assert_true(ra == ra_alone[i]);
            assert_true(rb == rb_alone[i]);
        }
        EXPECT_OK(zw_extremes_compute(&b, &xb));
        EXPECT_OK(zw_extremes_compute(&a, &xa));
        assert_true(xa.alpha_mmax == xa_alone.alpha_mmax && xb.alpha_mmax == xb_alone.alpha_mmax);
        assert_true(xa.beta_mmax == xa_alone.beta_mmax && xb.beta_mmax == xb_alone.beta_mmax);
        assert_memory_equal(&a, &a_copy, sizeof a); /* const really const */
        assert_memory_equal(&b, &b_copy, sizeof b);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_delta_zero),
        cmocka_unit_test(test_identities),
        cmocka_unit_test(test_accuracy_vs_reference),
        cmocka_unit_test(test_sigma),
        cmocka_unit_test(test_order_and_monotonic),
        cmocka_unit_test(test_large_delta),
        cmocka_unit_test(test_finite_fields),
        cmocka_unit_test(test_delta_infinite),
        cmocka_unit_test(test_errors_leave_output_nan),
        cmocka_unit_test(test_literal),
        cmocka_unit_test(test_switch_continuity),
        cmocka_unit_test(test_reentrancy),
    };
    printf("zwidth C tests: coeffs (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("coeffs_" ZW_REAL_NAME, tests, NULL, NULL);
}
