/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Achievable extremes in the normalized space (paper Section III, eqs (19)-(32)): the
 * limits delta -> 0 and delta -> inf, the branch switch at delta1, the sign change at
 * delta2, the critical constants against their defining equations, and that every
 * boundary the functions report is the boundary zw_check sees. */
#include "zw_test.h"

static zw_extremes extremes(zw_real delta)
{
    zw_coeffs c = zwt_coeffs(delta);
    zw_extremes x;
    memset(&x, 0, sizeof x);
    EXPECT_OK(zw_extremes_compute(&c, &x));
    return x;
}

static zw_real alpha_max(const zw_coeffs *c, zw_real beta)
{
    zw_real a = R(-1.0);
    EXPECT_OK(zw_alpha_max(c, beta, &a));
    return a;
}

static zw_verdict check(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_verdict v;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_check(c, alpha, beta, &v));
    return v;
}

/* The paper's f(beta) and L(beta), eq (10), in long double from the plant's fields. */
static long double f_of(const zw_coeffs *c, long double beta)
{
    return (long double)c->s * (beta + c->delta) * (2.0L - (long double)c->c2 * beta) /
           (((long double)c->c1 * beta + 2.0L) * (long double)c->c2);
}
static long double line_of(const zw_coeffs *c, long double beta)
{
    return 4.0L * (1.0L + (long double)c->e) / (long double)c->d12 - 2.0L * beta;
}

/* Relative step "just inside / just outside" a boundary: well above the verdict's
 * rounding band (a few tens of ulps), well below anything the tests resolve. */
#define JUST TOL(1000)

/* ---- limits ---------------------------------------------------------------------------------- */

/* delta -> 0: alpha_mmax -> 12 - 8 sqrt 2 at beta -> 2 sqrt 2 - 2, beta_mmax -> 2 (~ 2 +
 * 4 delta / 3), alpha_p_max -> 0 (no proportional control without damping). */
static void test_limit_delta_to_zero(void **state)
{
    const long double a0 = 12.0L - 8.0L * sqrtl(2.0L), b0 = 2.0L * sqrtl(2.0L) - 2.0L;
    static const zw_real ds[] = {R(0.0), ZWT_TRUE_MIN, R(1e-12), R(1e-9), R(1e-6), R(1e-4)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        long double d = ds[i];
        zw_extremes x = extremes(ds[i]);
        EXPECT_NEAR(x.alpha_mmax, a0, 4.0L * d, TOLL(64));
        EXPECT_NEAR(x.beta_at_alpha_mmax, b0, 4.0L * d, TOLL(64));
        EXPECT_NEAR(x.beta_mmax, 2.0L + 4.0L * d / 3.0L, d * d, TOLL(16));
        EXPECT_NEAR(x.alpha_p_max, 2.0L * d, 2.0L * d * d, TOLL(16)); /* 2 (1-e)/c2 ~ 2 delta */
        assert_false(x.at_corner);
        assert_true(x.alpha_mmin == R(0.0));
        assert_true(x.beta_mmin == -ds[i]);
    }
}

/* delta -> inf: alpha_mmax ~ 4 delta + 4 (relative error ~ 4/delta^3), beta at it ~ -delta
 * (~ 4/delta^2), beta_mmax ~ delta + 2, alpha_p_max ~ 2 delta + 4; corner branch. */
static void test_limit_delta_large(void **state)
{
    static const zw_real ds[] = {R(1e3), R(1e6), R(1e12), R(PREC(1e300, 1e30))};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        long double d = ds[i], tail = 5.0L / (d * d);
        zw_extremes x = extremes(ds[i]);
        assert_true(x.at_corner);
        EXPECT_REL(x.alpha_mmax / (4.0L * d + 4.0L), 1.0L, tail + TOLL(64));
        EXPECT_REL(x.beta_at_alpha_mmax / -d, 1.0L, tail + TOLL(64));
        EXPECT_REL(x.beta_mmax / (d + 2.0L), 1.0L, tail + TOLL(64));
        EXPECT_REL(x.alpha_p_max / (2.0L * d + 4.0L), 1.0L, 5.0L / d + TOLL(64));
        assert_true(x.beta_mmin == -ds[i]);
    }
}

/* ---- the critical constants against the maths ---------------------------------------------- */

/* delta0: (1 + d)(1 + e^-d)^2 = 4, and there 2/c2 = 2 (1 + e)/d12 (beta_mmax's two
 * branches, eq (32), meet); beta_mmax is 2/c2 below and 2 (1 + e)/d12 above. */
static void test_delta0(void **state)
{
    long double d0 = ZW_DELTA0, e0 = expl(-d0);
    zw_coeffs c = zwt_coeffs(ZW_DELTA0), lo = zwt_coeffs(R(2.0)), hi = zwt_coeffs(R(3.0));
    zw_extremes xl = extremes(R(2.0)), xh = extremes(R(3.0));
    (void)state;
    EXPECT_REL((1.0L + d0) * (1.0L + e0) * (1.0L + e0), 4.0L, 1e-20L + TOLL(1));
    EXPECT_REL(2.0L / (long double)c.c2, 2.0L * (1.0L + c.e) / (long double)c.d12, TOLL(64));
    assert_true(2.0L / (long double)lo.c2 < 2.0L * (1.0L + lo.e) / (long double)lo.d12);
    assert_true(2.0L / (long double)hi.c2 > 2.0L * (1.0L + hi.e) / (long double)hi.d12);
    EXPECT_REL(xl.beta_mmax, 2.0L / (long double)lo.c2, TOLL(16));
    EXPECT_REL(xh.beta_mmax, 2.0L * (1.0L + hi.e) / (long double)hi.d12, TOLL(16));
}

/* delta1: the top of the hyperbola and the corner coincide; alpha_mmax switches branch
 * there (at_corner) and stays continuous. */
static void test_delta1_branch_switch(void **state)
{
    zw_coeffs c = zwt_coeffs(ZW_DELTA1);
    zw_real a1, b1, a2, b2;
    const zw_real eps = R(PREC(1e-6, 1e-3));
    zw_extremes below = extremes(ZW_DELTA1 * (R(1.0) - eps)), above = extremes(ZW_DELTA1 * (R(1.0) + eps));
    (void)state;
    EXPECT_OK(zw_hyperbola_top(&c, &a1, &b1));
    EXPECT_OK(zw_corner(&c, &a2, &b2));
    EXPECT_REL(a1, a2, TOLL(1000));
    EXPECT_ABS(b1, b2, TOLL(1000) * (1.0L + fabsl(b1)));
    assert_false(below.at_corner);
    assert_true(above.at_corner);
    assert_false(extremes(ZW_DELTA1).at_corner); /* "alpha1 if delta <= delta1" */
    EXPECT_REL(below.alpha_mmax, above.alpha_mmax, 20.0L * eps);
    EXPECT_ABS(below.beta_at_alpha_mmax, above.beta_at_alpha_mmax, 20.0L * eps);
    assert_false(extremes(R(3.5)).at_corner);
    assert_true(extremes(R(4.0)).at_corner);
}

/* Below delta1 the top of the hyperbola is inside the line (stable just below it); above
 * delta1 the line cuts it off (eq (24)). */
static void test_top_cut_off_above_delta1(void **state)
{
    zw_coeffs c35 = zwt_coeffs(R(3.5)), c4 = zwt_coeffs(R(4.0));
    zw_real a, b;
    zw_verdict v;
    (void)state;
    EXPECT_OK(zw_hyperbola_top(&c35, &a, &b));
    assert_true(check(&c35, a * (R(1.0) - JUST), b).stable);
    assert_false(check(&c35, a * (R(1.0) + JUST), b).stable);
    EXPECT_OK(zw_hyperbola_top(&c4, &a, &b));
    v = check(&c4, a * (R(1.0) - JUST), b);
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_BOUND_LINE);
}

/* delta2: beta at alpha_mmax changes sign; there (29)'s two bounds 2 (1 - e)/c2 and
 * 4 (1 + e)/d12 meet, the second being the smaller above. */
static void test_delta2_sign_change(void **state)
{
    const zw_real eps = R(PREC(1e-6, 1e-3));
    zw_extremes below = extremes(ZW_DELTA2 * (R(1.0) - eps)), above = extremes(ZW_DELTA2 * (R(1.0) + eps));
    zw_extremes at = extremes(ZW_DELTA2);
    zw_coeffs c = zwt_coeffs(ZW_DELTA2), c3 = zwt_coeffs(R(3.0)), c5 = zwt_coeffs(R(5.0));
    zw_extremes x3 = extremes(R(3.0)), x5 = extremes(R(5.0));
    (void)state;
    assert_true(below.beta_at_alpha_mmax > R(0.0));
    assert_true(above.beta_at_alpha_mmax < R(0.0));
    EXPECT_ABS(at.beta_at_alpha_mmax, 0.0L, TOLL(2000));
    assert_true(below.at_corner && above.at_corner); /* delta2 > delta1 */
    EXPECT_REL(2.0L * (1.0L - c.e) / (long double)c.c2, 4.0L * (1.0L + c.e) / (long double)c.d12, TOLL(64));
    EXPECT_REL(x3.alpha_p_max, 2.0L * (1.0L - c3.e) / (long double)c3.c2, TOLL(32));
    EXPECT_REL(x5.alpha_p_max, 4.0L * (1.0L + c5.e) / (long double)c5.d12, TOLL(32));
    assert_true(extremes(R(3.0)).beta_at_alpha_mmax > R(0.0));
    assert_true(extremes(R(5.1224)).beta_at_alpha_mmax < R(0.0));
}

/* delta_K1, delta_K2: local min / max of alpha_mmax / delta with the stated values;
 * delta_KM: where it climbs back to the local max.  delta_B: local min of beta_mmax / delta
 * with B_mmax(delta_B) = 3.350918871511673 b; B_mmax(delta0) = 3.440519785624598 b
 * (shared/notes/math.md). */
static long double kratio(zw_real d)
{
    return (long double)extremes(d).alpha_mmax / (long double)d;
}
static long double bratio(zw_real d)
{
    return (long double)extremes(d).beta_mmax / (long double)d;
}

static void test_influence_constants(void **state)
{
    const zw_real h = R(1e-2);
    (void)state;
    EXPECT_REL(kratio(ZW_DELTA_K1), 2.637422468249545L, TOLL(1000));
    EXPECT_REL(kratio(ZW_DELTA_K2), 4.508675168782248L, TOLL(1000));
    EXPECT_REL((long double)ZW_KMAX_LOCAL_MIN, 2.637422468249545L, TOLL(2));
    EXPECT_REL((long double)ZW_KMAX_LOCAL_MAX, 4.508675168782248L, TOLL(2));
    assert_true(kratio(ZW_DELTA_K1 * (R(1.0) - h)) > kratio(ZW_DELTA_K1));
    assert_true(kratio(ZW_DELTA_K1 * (R(1.0) + h)) > kratio(ZW_DELTA_K1));
    assert_true(kratio(ZW_DELTA_K2 * (R(1.0) - h)) < kratio(ZW_DELTA_K2));
    assert_true(kratio(ZW_DELTA_K2 * (R(1.0) + h)) < kratio(ZW_DELTA_K2));
    EXPECT_REL(kratio(ZW_DELTA_KM), kratio(ZW_DELTA_K2), TOLL(1000));
    assert_true(ZW_DELTA_KM < ZW_DELTA_K1);
    EXPECT_REL(bratio(ZW_DELTA_B), 3.350918871511673L, TOLL(1000));
    EXPECT_REL(bratio(ZW_DELTA0), 3.440519785624598L, TOLL(1000));
    assert_true(bratio(ZW_DELTA_B * (R(1.0) - h)) > bratio(ZW_DELTA_B));
    assert_true(bratio(ZW_DELTA_B * (R(1.0) + h)) > bratio(ZW_DELTA_B));
    /* delta_BB: local min of beta_mmax itself above delta0 (where 2 (1 + e)/d12 is least;
     * 3.2122305976055347 by root finding at 40 digits, independently of the header) and
     * local max at delta0 */
    EXPECT_REL((long double)ZW_DELTA_BB, 3.2122305976055347282L, TOLL(2));
    assert_true(extremes(ZW_DELTA_BB * (R(1.0) - h)).beta_mmax > extremes(ZW_DELTA_BB).beta_mmax);
    assert_true(extremes(ZW_DELTA_BB * (R(1.0) + h)).beta_mmax > extremes(ZW_DELTA_BB).beta_mmax);
    assert_true(extremes(ZW_DELTA0 * (R(1.0) - h)).beta_mmax < extremes(ZW_DELTA0).beta_mmax);
    assert_true(extremes(ZW_DELTA0 * (R(1.0) + h)).beta_mmax < extremes(ZW_DELTA0).beta_mmax);
    /* B_mmax(inf) = b: beta_mmax / delta -> 1 */
    EXPECT_REL(bratio(R(1e6)), 1.0L, 3e-6L + TOLL(64));
}

/* ---- the corner and the top ------------------------------------------------------------ */

/* zw_corner: ZW_ERR_DOMAIN unless delta > delta0 (outputs fail-safe 0); above, the corner
 * lies on both the line and the hyperbola; it starts at (alpha, beta) = (0, 2/c2). */
static void test_corner(void **state)
{
    static const zw_real none[] = {R(0.0), R(1.0), R(2.3), ZW_DELTA0};
    static const zw_real some[] = {R(2.5), R(3.0), ZW_DELTA1, R(5.1224), R(20.0), R(1e4)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(none); ++i) {
        zw_coeffs c = zwt_coeffs(none[i]);
        zw_real a = R(7.0), b = R(7.0);
        EXPECT_STATUS(zw_corner(&c, &a, &b), ZW_ERR_DOMAIN);
        assert_true(a == R(0.0) && b == R(0.0));
    }
    {
        zw_coeffs c = zwt_coeffs(ZWT_DOWN(ZW_DELTA0));
        zw_real a = R(7.0), b = R(7.0);
        EXPECT_STATUS(zw_corner(&c, &a, &b), ZW_ERR_DOMAIN);
        assert_true(a == R(0.0) && b == R(0.0));
    }
    for (i = 0; i < ZWT_ARRAY_LEN(some); ++i) {
        zw_coeffs c = zwt_coeffs(some[i]);
        zw_real a, b;
        long double scale;
        EXPECT_OK(zw_corner(&c, &a, &b));
        scale = fabsl(a) + 2.0L * fabsl(b) + 1.0L;
        EXPECT_ABS(a, line_of(&c, b), TOLL(256) * scale);
        /* f is steep at the corner for large delta (slope ~ delta^2): allow for beta's
         * own rounding, f(b +- 4 ulp) */
        EXPECT_ABS(a, f_of(&c, b),
                   TOLL(256) * scale + fabsl(f_of(&c, b + 4.0L * zwt_ulp(b)) - f_of(&c, b - 4.0L * zwt_ulp(b))));
        assert_true(a > R(0.0));
    }
    {
        /* just above delta0 the corner sits at the right end of the hyperbola */
        zw_coeffs c = zwt_coeffs(ZW_DELTA0 * (R(1.0) + R(PREC(1e-6, 1e-3))));
        zw_real a, b;
        EXPECT_OK(zw_corner(&c, &a, &b));
        EXPECT_ABS(a, 0.0L, PREC(1e-4L, 1e-1L));
        EXPECT_REL(b, 2.0L / (long double)c.c2, PREC(1e-5L, 1e-2L));
    }
}

/* zw_hyperbola_top: the maximum of f (f(beta1) = alpha1 >= f nearby). */
static void test_hyperbola_top(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-6), R(0.013), R(1.0), R(2.049), R(3.0), R(5.1224), R(20.0)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        zw_coeffs c = zwt_coeffs(ds[i]);
        zw_real a, b;
        long double step = 1e-2L * (1.0L + ds[i]), top;
        EXPECT_OK(zw_hyperbola_top(&c, &a, &b));
        EXPECT_REL(a, f_of(&c, b), TOLL(64));
        /* f is flat at its top: compare with a's own rounding allowed for */
        top = (long double)a * (1.0L + TOLL(8));
        assert_true(f_of(&c, (long double)b - step) <= top);
        assert_true(f_of(&c, (long double)b + step) <= top);
        assert_true(f_of(&c, (long double)b - step) < f_of(&c, b));
        assert_true(f_of(&c, (long double)b + step) < f_of(&c, b));
        if (ds[i] <= ZW_DELTA1) {
            zw_extremes x = extremes(ds[i]);
            assert_true(x.alpha_mmax == a && x.beta_at_alpha_mmax == b);
        }
    }
}

/* ---- boundaries: alpha_max(beta) and the beta interval --------------------------------- */

static void test_alpha_max_is_the_boundary(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_extremes x = extremes(d);
        int j, n = 200, tested = 0;
        for (j = 1; j < n; ++j) {
            zw_real beta = -d + (x.beta_mmax + d) * (zw_real)j / (zw_real)n;
            zw_real am = alpha_max(&c, beta);
            /* "just": JUST relative to the scale of alpha in this plane (alpha_mmax), not to
             * alpha_max(beta) itself, which vanishes at both ends of the beta range, where
             * a few ulps of the coefficients move it by a large relative amount */
            zw_real step = JUST * (am + x.alpha_mmax);
            zw_verdict in, out;
            assert_true(am > R(0.0));
            assert_true(am <= x.alpha_mmax * (R(1.0) + TOL(8)));
            if (am < R(4.0) * step) continue;
            in = check(&c, am - step, beta);
            out = check(&c, am + step, beta);
            EXPECT_TRUE_MSG(in.stable, "delta %g beta %.9g: just below alpha_max %.9g not stable",
                            (double)d, (double)beta, (double)am);
            EXPECT_TRUE_MSG(!out.stable, "delta %g beta %.9g: just above alpha_max %.9g stable",
                            (double)d, (double)beta, (double)am);
            ++tested;
        }
        assert_true(tested > 100);
        /* at the beta of the maximum it is the maximum */
        {
            /* the corner is steep on its hyperbola side (slope ~ 2/c2 + delta): allow for
             * the rounding of beta itself */
            zw_real b = x.beta_at_alpha_mmax;
            long double slope_err = fabsl((long double)alpha_max(&c, ZWT_UP(ZWT_UP(b))) -
                                          (long double)alpha_max(&c, ZWT_DOWN(ZWT_DOWN(b))));
            EXPECT_NEAR(alpha_max(&c, b), x.alpha_mmax, slope_err, TOLL(64));
        }
        /* outside (-delta, beta_mmax) there is none */
        assert_true(alpha_max(&c, -d) == R(0.0));
        assert_true(alpha_max(&c, -d - R(1.0)) == R(0.0));
        assert_true(alpha_max(&c, x.beta_mmax) == R(0.0));
        assert_true(alpha_max(&c, x.beta_mmax * R(1.5) + R(1.0)) == R(0.0));
    }
}

/* The beta interval at a given alpha: its ends are on the boundary (stable just inside,
 * unstable just outside); empty for alpha <= 0 and alpha >= alpha_mmax. */
static void test_beta_interval_is_the_boundary(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    static const zw_real fractions[] = {R(1e-3), R(0.1), R(0.5), R(0.9), R(0.999)};
    size_t k, i;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_extremes x = extremes(d);
        for (i = 0; i < ZWT_ARRAY_LEN(fractions); ++i) {
            zw_real alpha = x.alpha_mmax * fractions[i], lo = R(7.0), hi = R(7.0), s_lo, s_hi;
            bool nonempty = false;
            EXPECT_OK(zw_beta_interval(&c, alpha, &lo, &hi, &nonempty));
            assert_true(nonempty);
            assert_true(lo < hi);
            /* (non-strict: in float at delta = 1e4 the corner, at beta = -delta + 4e-4, is
             * closer to -delta than one ulp of delta) */
            assert_true(lo >= -d);
            assert_true(hi < x.beta_mmax);
            assert_true(lo <= x.beta_at_alpha_mmax && x.beta_at_alpha_mmax <= hi);
            /* steps: relative to the scale of the ends, never more than a tenth of the width */
            s_lo = JUST * (ZW_FABS(lo) + d + R(1.0));
            s_hi = JUST * (ZW_FABS(hi) + d + R(1.0));
            if (s_lo > (hi - lo) / R(10.0)) s_lo = (hi - lo) / R(10.0);
            if (s_hi > (hi - lo) / R(10.0)) s_hi = (hi - lo) / R(10.0);
            EXPECT_TRUE_MSG(check(&c, alpha, lo + s_lo).stable, "delta %g alpha %g: lo %.9g + step",
                            (double)d, (double)alpha, (double)lo);
            EXPECT_TRUE_MSG(!check(&c, alpha, lo - s_lo).stable, "delta %g alpha %g: lo %.9g - step",
                            (double)d, (double)alpha, (double)lo);
            EXPECT_TRUE_MSG(check(&c, alpha, hi - s_hi).stable, "delta %g alpha %g: hi %.9g - step",
                            (double)d, (double)alpha, (double)hi);
            EXPECT_TRUE_MSG(!check(&c, alpha, hi + s_hi).stable, "delta %g alpha %g: hi %.9g + step",
                            (double)d, (double)alpha, (double)hi);
            assert_true(check(&c, alpha, lo + (hi - lo) / R(2.0)).stable);
        }
        {
            static const zw_real bad_fraction[] = {R(-1.0), R(0.0), R(1.001), R(2.0)};
            for (i = 0; i < ZWT_ARRAY_LEN(bad_fraction); ++i) {
                zw_real lo = R(7.0), hi = R(7.0);
                bool nonempty = true;
                EXPECT_OK(zw_beta_interval(&c, x.alpha_mmax * bad_fraction[i], &lo, &hi, &nonempty));
                assert_false(nonempty);
                assert_true(lo == R(0.0) && hi == R(0.0));
            }
        }
    }
}

/* alpha_p_max: alpha_max(0), eq (29) min{2 (1 - e)/c2, 4 (1 + e)/d12}, and the boundary of
 * zw_check_proportional. */
static void test_alpha_p_max(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_extremes x = extremes(d);
        zw_verdict v;
        long double e = c.e, want;
        assert_true(x.alpha_p_max == alpha_max(&c, R(0.0)));
        if (d == R(0.0)) {
            assert_true(x.alpha_p_max == R(0.0));
            continue;
        }
        want = -2.0L * expm1l(-(long double)d) / (long double)c.c2;
        if (4.0L * (1.0L + e) / (long double)c.d12 < want) want = 4.0L * (1.0L + e) / (long double)c.d12;
        EXPECT_REL(x.alpha_p_max, want, TOLL(32));
        EXPECT_OK(zw_check_proportional(&c, x.alpha_p_max * (R(1.0) - JUST), &v));
        assert_true(v.stable);
        EXPECT_OK(zw_check_proportional(&c, x.alpha_p_max * (R(1.0) + JUST), &v));
        assert_false(v.stable);
        assert_true(x.alpha_p_max <= x.alpha_mmax);
    }
}

/* beta_mmax, eq (32): min{2/c2, 2 (1 + e)/d12}; the right end of the region at alpha -> 0+. */
static void test_beta_mmax(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_extremes x = extremes(d);
        long double want = 2.0L / (long double)c.c2;
        zw_real tiny = R(PREC(1e-9, 1e-5)) * (x.alpha_mmax);
        if (c.d12 > R(0.0) && 2.0L * (1.0L + c.e) / (long double)c.d12 < want)
            want = 2.0L * (1.0L + c.e) / (long double)c.d12;
        EXPECT_REL(x.beta_mmax, want, TOLL(16));
        assert_true(check(&c, tiny, x.beta_mmax * (R(1.0) - R(PREC(1e-6, 1e-2)))).stable);
        assert_false(check(&c, tiny, x.beta_mmax * (R(1.0) + JUST)).stable);
        assert_false(check(&c, tiny, x.beta_mmax).stable);
    }
}

/* ---- errors ------------------------------------------------------------------------------ */

static void test_errors(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0)), cinf = zwt_coeffs((zw_real)INFINITY),
              cbig = zwt_coeffs(ZW_REAL_MAX);
    zw_extremes x;
    zw_real a = R(7.0), b = R(7.0);
    bool ne = true;
    (void)state;
    memset(&x, ZWT_SENTINEL, sizeof x);
    EXPECT_STATUS(zw_extremes_compute(NULL, &x), ZW_ERR_NULL);
    EXPECT_STATUS(zw_extremes_compute(&c, NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_extremes_compute(&cinf, &x), ZW_ERR_INF);
    assert_true(isinf(cbig.hs)); /* coeffs.h: beyond max/2 */
    EXPECT_STATUS(zw_extremes_compute(&cbig, &x), ZW_ERR_RANGE);
    assert_true(x.alpha_mmax == R(0.0) && x.alpha_p_max == R(0.0) && x.beta_mmax == R(0.0) &&
                x.beta_mmin == R(0.0) && !x.at_corner); /* fail-safe; test_failsafe.c has all */

    EXPECT_STATUS(zw_hyperbola_top(NULL, &a, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_hyperbola_top(&c, NULL, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_hyperbola_top(&c, &a, NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_hyperbola_top(&cinf, &a, &b), ZW_ERR_INF);
    EXPECT_STATUS(zw_corner(NULL, &a, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_corner(&cinf, &a, &b), ZW_ERR_INF);
    EXPECT_STATUS(zw_alpha_max(NULL, R(0.0), &a), ZW_ERR_NULL);
    EXPECT_STATUS(zw_alpha_max(&c, R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_alpha_max(&c, (zw_real)NAN, &a), ZW_ERR_NAN);
    EXPECT_STATUS(zw_alpha_max(&c, (zw_real)INFINITY, &a), ZW_ERR_INF);
    EXPECT_STATUS(zw_alpha_max(&c, -(zw_real)INFINITY, &a), ZW_ERR_INF);
    EXPECT_STATUS(zw_alpha_max(&cinf, R(0.0), &a), ZW_ERR_INF);
    EXPECT_STATUS(zw_beta_interval(NULL, R(0.1), &a, &b, &ne), ZW_ERR_NULL);
    EXPECT_STATUS(zw_beta_interval(&c, R(0.1), NULL, &b, &ne), ZW_ERR_NULL);
    EXPECT_STATUS(zw_beta_interval(&c, R(0.1), &a, NULL, &ne), ZW_ERR_NULL);
    EXPECT_STATUS(zw_beta_interval(&c, R(0.1), &a, &b, NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_beta_interval(&c, (zw_real)NAN, &a, &b, &ne), ZW_ERR_NAN);
    EXPECT_STATUS(zw_beta_interval(&c, (zw_real)INFINITY, &a, &b, &ne), ZW_ERR_INF);
    EXPECT_STATUS(zw_beta_interval(&cinf, R(0.1), &a, &b, &ne), ZW_ERR_INF);
    assert_true(a == R(0.0) && b == R(0.0) && !ne); /* fail-safe: empty */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limit_delta_to_zero),
        cmocka_unit_test(test_limit_delta_large),
        cmocka_unit_test(test_delta0),
        cmocka_unit_test(test_delta1_branch_switch),
        cmocka_unit_test(test_top_cut_off_above_delta1),
        cmocka_unit_test(test_delta2_sign_change),
        cmocka_unit_test(test_influence_constants),
        cmocka_unit_test(test_corner),
        cmocka_unit_test(test_hyperbola_top),
        cmocka_unit_test(test_alpha_max_is_the_boundary),
        cmocka_unit_test(test_beta_interval_is_the_boundary),
        cmocka_unit_test(test_alpha_p_max),
        cmocka_unit_test(test_beta_mmax),
        cmocka_unit_test(test_errors),
    };
    printf("zwidth C tests: extremes (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("extremes_" ZW_REAL_NAME, tests, NULL, NULL);
}
