/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Closed-loop poles: the characteristic polynomial (7), (8), the spectral radius on cases
 * whose roots are known in closed form, and the Jury test "every pole inside |z| < r". */
#include "zw_test.h"

#include <complex.h>

/* ---- independent roots: Durand-Kerner in long double complex -------------------------- */

/* max |z| over the roots of p[0] z^3 + p[1] z^2 + p[2] z + p[3] (p[0] != 0). */
static long double dk_radius(const long double p[4])
{
    long double complex z[3], a1 = p[1] / p[0], a2 = p[2] / p[0], a3 = p[3] / p[0];
    long double scale = 1.0L + fabsl(p[1] / p[0]) + fabsl(p[2] / p[0]) + fabsl(p[3] / p[0]);
    long double best = 0.0L;
    int it, i, j;
    for (i = 0; i < 3; ++i) z[i] = scale * cpowl(0.4L + 0.9L * I, (long double)i);
    for (it = 0; it < 1000; ++it) {
        long double change = 0.0L;
        for (i = 0; i < 3; ++i) {
            long double complex num = ((z[i] + a1) * z[i] + a2) * z[i] + a3, den = 1.0L, step;
            for (j = 0; j < 3; ++j)
                if (j != i) den *= z[i] - z[j];
            step = num / den;
            z[i] -= step;
            if (cabsl(step) > change) change = cabsl(step);
        }
        if (change <= 4.0L * LDBL_EPSILON * scale) break;
    }
    for (i = 0; i < 3; ++i)
        if (cabsl(z[i]) > best) best = cabsl(z[i]);
    return best;
}

static long double ref_radius(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_real p[4];
    long double q[4];
    int i;
    EXPECT_OK(zw_char_poly(c, alpha, beta, p));
    for (i = 0; i < 4; ++i) q[i] = p[i];
    return dk_radius(q);
}

static zw_real radius(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_real rho = R(-1.0);
    EXPECT_OK(zw_spectral_radius(c, alpha, beta, &rho));
    return rho;
}

/* ---- characteristic polynomial -------------------------------------------------------- */

/* p = [2, c1 (alpha + beta) - 2 (1 + e), c2 alpha + (c2 - c1) beta + 2 e, -c2 beta] from the
 * plant's own fields, and the identities p(1) = (c1 + c2) alpha (the hyperbola's constraint
 * p(1) > 0 is alpha > 0) and p(-1) = d12 (alpha + 2 beta) - 4 (1 + e) (the line). */
static void test_char_poly_definition(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-6), R(0.013), R(1.0), R(2.049), R(5.1224), R(20.0), R(1e4)};
    static const zw_real ab[][2] = {{R(0.0), R(0.0)},   {R(1.0), R(0.0)},  {R(0.3), R(-0.2)},
                                    {R(23.0), R(-1.5)}, {R(5.0), R(10.0)}, {R(-2.0), R(7.5)},
                                    {R(1e3), R(-40.0)}};
    size_t k, i;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        long double c1 = c.c1, c2 = c.c2, e = c.e, d12 = c.d12, s = c.s;
        for (i = 0; i < ZWT_ARRAY_LEN(ab); ++i) {
            zw_real p[4] = {R(9.0), R(9.0), R(9.0), R(9.0)};
            long double a = ab[i][0], b = ab[i][1], sum, mag;
            EXPECT_OK(zw_char_poly(&c, ab[i][0], ab[i][1], p));
            assert_true(p[0] == R(2.0));
            mag = fabsl(c1 * (a + b)) + 2.0L * (1.0L + e);
            EXPECT_ABS(p[1], c1 * (a + b) - 2.0L * (1.0L + e), TOLL(8) * mag);
            mag = fabsl(c2 * a) + fabsl(c1 * b) + 2.0L * e;
            EXPECT_ABS(p[2], c2 * a + (c2 - c1) * b + 2.0L * e, TOLL(16) * mag + ZW_REAL_MIN);
            EXPECT_ABS(p[3], -c2 * b, TOLL(2) * fabsl(c2 * b) + ZW_REAL_MIN);
            mag = 4.0L + 4.0L * (fabsl(c1) + fabsl(c2)) * (fabsl(a) + fabsl(b));
            sum = (long double)p[0] + p[1] + p[2] + p[3];
            EXPECT_ABS(sum, s * a, TOLL(32) * mag);
            sum = -(long double)p[0] + p[1] - p[2] + p[3];
            EXPECT_ABS(sum, d12 * (a + 2.0L * b) - 4.0L * (1.0L + e), TOLL(32) * mag);
        }
    }
}

static void test_char_poly_errors(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0)), cinf = zwt_coeffs((zw_real)INFINITY);
    zw_real p[4];
    (void)state;
    memset(p, ZWT_SENTINEL, sizeof p);
    EXPECT_STATUS(zw_char_poly(NULL, R(1.0), R(0.0), p), ZW_ERR_NULL);
    EXPECT_STATUS(zw_char_poly(&c, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_char_poly(&c, (zw_real)NAN, R(0.0), p), ZW_ERR_NAN);
    EXPECT_STATUS(zw_char_poly(&c, R(1.0), (zw_real)NAN, p), ZW_ERR_NAN);
    EXPECT_STATUS(zw_char_poly(&c, (zw_real)INFINITY, R(0.0), p), ZW_ERR_INF);
    EXPECT_STATUS(zw_char_poly(&c, R(1.0), -(zw_real)INFINITY, p), ZW_ERR_INF);
    EXPECT_STATUS(zw_char_poly(&cinf, R(1.0), R(0.0), p), ZW_ERR_INF);
    /* alpha + beta overflows: a1 is not finite */
    EXPECT_STATUS(zw_char_poly(&c, ZW_REAL_MAX, ZW_REAL_MAX, p), ZW_ERR_RANGE);
    assert_true(isnan(p[0]) && isnan(p[1]) && isnan(p[2]) && isnan(p[3])); /* fail-safe */
}

/* ---- spectral radius on known roots ------------------------------------------------------- */

/* delta > 0, alpha = beta = 0: p = 2 z (z - 1)(z - e), rho = 1 exactly (simple root). */
static void test_radius_open_loop(void **state)
{
    static const zw_real ds[] = {R(1e-3), R(0.013), R(1.0), R(2.049), R(5.1224), R(20.0), R(1e4)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        /* the root 1 is separated from e by 1 - e; its condition number is ~1/(1 - e) */
        EXPECT_REL(radius(&c, R(0.0), R(0.0)), 1.0L, TOLL(32) / (1.0L - expl(-(long double)ds[k])));
    }
    {
        /* delta = 0: double root at 1, accurate to about sqrt(u) */
        zw_coeffs c0 = zwt_coeffs(R(0.0));
        EXPECT_REL(radius(&c0, R(0.0), R(0.0)), 1.0L, 8.0L * sqrtl(TOLL(1)));
    }
}

/* Closed forms.  At delta = 0 (c1 = c2 = e = 1), p(z) = 2 z^3 + (alpha + beta - 4) z^2 +
 * (alpha + 2) z - beta, so roots r1, r2, r3 with (1 + r1)(1 + r2)(1 + r3) = 4 are reached
 * by alpha = 2 (r1 r2 + r1 r3 + r2 r3) - 2, beta = 2 r1 r2 r3. */
static void test_radius_closed_forms(void **state)
{
    static const struct {
        zw_real delta, alpha, beta;
        long double rho;
        const char *roots;
    } cases[] = {
        {R(0.0), R(18.0), R(0.0), 5.0L, "{0, -2, -5}"},
        {R(0.0), R(2.0), R(0.0), 1.41421356237309504880L, "{0, (1 +- i sqrt 7)/2}"},
        {R(0.0), R(0.0), R(-3.0), 3.0L, "{-0.5, 1, 3}"},
        {R(0.0), R(1.0) / R(18.0), R(7.0) / R(18.0), 7.0L / 9.0L, "{0.5, 0.5, 7/9}"},
        {R(0.0), R(0.2), R(0.6), 0.70710678118654752440L, "{0.6, 0.5 +- 0.5 i}"},
        {R(0.0), R(-2.0), R(0.0), 3.0L, "{3, 0, 0}"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_coeffs c = zwt_coeffs(cases[i].delta);
        zw_real rho = radius(&c, cases[i].alpha, cases[i].beta);
        EXPECT_TRUE_MSG(fabsl((long double)rho - cases[i].rho) <= TOLL(256) * cases[i].rho,
                        "roots %s: rho %.17Lg, expected %.17Lg", cases[i].roots, (long double)rho,
                        cases[i].rho);
    }
    {
        /* delta = 1, alpha = 1, beta = 0: c1 = 2/E, so a1 = -2 and the quadratic factor
         * 2 z^2 - 2 z + (2 - 2/E) has complex roots with |z|^2 = 1 - 1/E. */
        zw_coeffs c = zwt_coeffs(R(1.0));
        EXPECT_REL(radius(&c, R(1.0), R(0.0)), sqrtl(1.0L - expl(-1.0L)), TOLL(64));
    }
}

/* Against the independent root finder over a grid: the same radius wherever the roots are
 * simple (near multiple roots both are only good to about sqrt(u)). */
static void test_radius_vs_independent_roots(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real top = R(1.5) * (R(4.0) * ds[k] + R(4.0));
        int i, j, n = 30;
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real alpha = -R(0.1) * top + R(1.1) * top * (zw_real)i / (zw_real)n;
                zw_real beta = -R(1.5) * (ds[k] + R(1.0)) + R(3.0) * (ds[k] + R(2.0)) * (zw_real)j / (zw_real)n;
                long double want = ref_radius(&c, alpha, beta);
                zw_real got = radius(&c, alpha, beta);
                EXPECT_TRUE_MSG(fabsl((long double)got - want) <= 16.0L * sqrtl(TOLL(1)) * (1.0L + want),
                                "delta %g alpha %g beta %g: rho %.12Lg, roots say %.12Lg",
                                (double)ds[k], (double)alpha, (double)beta, (long double)got, want);
            }
        }
    }
}

static void test_radius_errors(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0)), cinf = zwt_coeffs((zw_real)INFINITY);
    zw_real rho = R(7.0);
    (void)state;
    EXPECT_STATUS(zw_spectral_radius(NULL, R(1.0), R(0.0), &rho), ZW_ERR_NULL);
    EXPECT_STATUS(zw_spectral_radius(&c, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_spectral_radius(&c, (zw_real)NAN, R(0.0), &rho), ZW_ERR_NAN);
    EXPECT_STATUS(zw_spectral_radius(&c, R(0.0), (zw_real)NAN, &rho), ZW_ERR_NAN);
    EXPECT_STATUS(zw_spectral_radius(&c, (zw_real)INFINITY, R(0.0), &rho), ZW_ERR_INF);
    EXPECT_STATUS(zw_spectral_radius(&c, R(0.0), -(zw_real)INFINITY, &rho), ZW_ERR_INF);
    EXPECT_STATUS(zw_spectral_radius(&cinf, R(1.0), R(0.0), &rho), ZW_ERR_INF);
    EXPECT_STATUS(zw_spectral_radius(&c, ZW_REAL_MAX, ZW_REAL_MAX, &rho), ZW_ERR_RANGE);
    assert_true(isinf(rho) && rho > R(0.0)); /* fail-safe: certifies nothing */
}

/* ---- Jury test on p(r z) ------------------------------------------------------------------ */

/* Never "within r" when rho >= r (1 + 1e-9); always within when rho is clearly below r. */
static void test_radius_within_consistent(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    static const zw_real rs[] = {R(0.5), R(0.9), R(0.99), R(1.0), R(1.1), R(2.0), R(10.0)};
    const long double outside = 1e-9L, inside = PREC(1e-6L, 1e-4L);
    size_t k, m;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real top = R(1.3) * (R(4.0) * ds[k] + R(4.0));
        int i, j, n = 24, n_in = 0, n_out = 0;
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real alpha = -R(0.1) * top + R(1.1) * top * (zw_real)i / (zw_real)n;
                zw_real beta = -R(1.2) * (ds[k] + R(0.5)) + R(2.5) * (ds[k] + R(1.5)) * (zw_real)j / (zw_real)n;
                long double rho = radius(&c, alpha, beta);
                for (m = 0; m < ZWT_ARRAY_LEN(rs); ++m) {
                    bool within = false;
                    long double r = rs[m];
                    EXPECT_OK(zw_radius_within(&c, alpha, beta, rs[m], &within));
                    if (within) {
                        ++n_in;
                        EXPECT_TRUE_MSG(rho < r * (1.0L + outside),
                                        "within %g but rho %.12Lg (delta %g alpha %g beta %g)",
                                        (double)rs[m], rho, (double)ds[k], (double)alpha, (double)beta);
                    } else {
                        ++n_out;
                        EXPECT_TRUE_MSG(rho > r * (1.0L - inside),
                                        "not within %g but rho %.12Lg (delta %g alpha %g beta %g)",
                                        (double)rs[m], rho, (double)ds[k], (double)alpha, (double)beta);
                    }
                }
                /* r = 1 agrees with the exact region wherever that one is sure */
                {
                    bool within = false;
                    zw_verdict v;
                    EXPECT_OK(zw_radius_within(&c, alpha, beta, R(1.0), &within));
                    EXPECT_OK(zw_check(&c, alpha, beta, &v));
                    if (within) assert_true(v.stable || v.marginal);
                    if (v.stable) assert_true(within || rho > 1.0L - inside);
                }
            }
        }
        assert_true(n_in > 50 && n_out > 50);
    }
}

/* The open loop at delta > 0 has rho = 1 exactly: not within 1, within 1 + a little,
 * not within 1 - a little. */
static void test_radius_within_exact_boundary(void **state)
{
    static const zw_real ds[] = {R(0.5), R(1.0), R(5.1224)};
    const zw_real eps = R(PREC(1e-6, 1e-3));
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        bool within = true;
        EXPECT_OK(zw_radius_within(&c, R(0.0), R(0.0), R(1.0), &within));
        assert_false(within);
        EXPECT_OK(zw_radius_within(&c, R(0.0), R(0.0), R(1.0) - eps, &within));
        assert_false(within);
        EXPECT_OK(zw_radius_within(&c, R(0.0), R(0.0), R(1.0) + eps, &within));
        assert_true(within);
    }
    {
        /* roots {0.6, 0.5 +- 0.5i} at delta = 0: rho = 0.7071 */
        zw_coeffs c0 = zwt_coeffs(R(0.0));
        bool within = false;
        EXPECT_OK(zw_radius_within(&c0, R(0.2), R(0.6), R(0.72), &within));
        assert_true(within);
        EXPECT_OK(zw_radius_within(&c0, R(0.2), R(0.6), R(0.70), &within));
        assert_false(within);
    }
}

static void test_radius_within_errors(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0));
    bool within = true;
    (void)state;
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), R(0.0), &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), -R(0.0), &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), R(-1.0), &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), (zw_real)INFINITY, &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), (zw_real)NAN, &within), ZW_ERR_NAN);
    EXPECT_STATUS(zw_radius_within(&c, (zw_real)NAN, R(0.0), R(1.0), &within), ZW_ERR_NAN);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), (zw_real)INFINITY, R(1.0), &within), ZW_ERR_INF);
    EXPECT_STATUS(zw_radius_within(NULL, R(1.0), R(0.0), R(1.0), &within), ZW_ERR_NULL);
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), R(1.0), NULL), ZW_ERR_NULL);
    assert_false(within); /* fail-safe */
    within = false;
    EXPECT_STATUS(zw_radius_within(&c, R(1.0), R(0.0), R(-1.0), &within), ZW_ERR_ARG);
    assert_false(within);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_char_poly_definition),
        cmocka_unit_test(test_char_poly_errors),
        cmocka_unit_test(test_radius_open_loop),
        cmocka_unit_test(test_radius_closed_forms),
        cmocka_unit_test(test_radius_vs_independent_roots),
        cmocka_unit_test(test_radius_errors),
        cmocka_unit_test(test_radius_within_consistent),
        cmocka_unit_test(test_radius_within_exact_boundary),
        cmocka_unit_test(test_radius_within_errors),
    };
    printf("zwidth C tests: margin (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("margin_" ZW_REAL_NAME, tests, NULL, NULL);
}
