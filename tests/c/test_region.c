/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Stability verdicts in the normalized space: the exact region (10), the legacy region,
 * the special regions (14)-(18), the deciding constraint, input errors, and a sweep that
 * the verdict never calls a point stable whose closed-loop poles leave the unit circle. */
#include "zw_test.h"

/* Verdict of one region; fails the test on any status other than ZW_OK. */
static zw_verdict verdict(zw_region region, const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_verdict v;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_check_region(region, c, alpha, beta, &v));
    return v;
}

static zw_verdict exact(const zw_coeffs *c, zw_real alpha, zw_real beta)
{
    zw_verdict v, w;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_check(c, alpha, beta, &v));
    w = verdict(ZW_REGION_EXACT, c, alpha, beta); /* zw_check is the exact region */
    assert_true(zwt_same_verdict(&v, &w));
    return v;
}

/* Internal consistency every verdict must have, whatever the point. */
static void expect_well_formed(const zw_verdict *v)
{
    if (v->stable) {
        assert_false(v->marginal);
        assert_int_equal(v->deciding, ZW_BOUND_NONE);
        assert_int_equal(v->violated, 0);
    } else {
        assert_int_not_equal(v->violated, 0);
        assert_int_not_equal(v->deciding, ZW_BOUND_NONE);
        /* the deciding constraint is one of the violated ones */
        assert_int_not_equal(v->violated & (unsigned)v->deciding, 0);
        /* when not marginal it is the first violated one in the order of the enum */
        if (!v->marginal) assert_int_equal(v->violated & ((unsigned)v->deciding - 1u), 0);
    }
}

static zw_real f_hyperbola(const zw_coeffs *c, zw_real beta)
{
    /* f(beta) = s (beta + delta)(2 - c2 beta) / ((c1 beta + 2) c2), paper (10), in long double */
    long double x = (long double)beta + c->delta, b = beta;
    return (zw_real)(((long double)c->s * x * (2.0L - (long double)c->c2 * b)) /
                     (((long double)c->c1 * b + 2.0L) * (long double)c->c2));
}

/* ---- the paper's points ---------------------------------------------------------------- */

/* Fig. 18/19, delta = 5.1224 > delta0: the three diamond points (beta, alpha) =
 * (-1.5, 23), (4, 15), (10, 5) lie inside the legacy boundary but were unstable in the
 * experiment (Fig. 19): exact region unstable by the line, legacy region "stable". */
static void test_paper_fig19_points(void **state)
{
    static const zw_real pts[3][2] = {{R(-1.5), R(23.0)}, {R(4.0), R(15.0)}, {R(10.0), R(5.0)}};
    zw_coeffs c = zwt_coeffs(R(5.1224));
    size_t i;
    (void)state;
    for (i = 0; i < 3; ++i) {
        zw_real beta = pts[i][0], alpha = pts[i][1], rho;
        zw_verdict v = exact(&c, alpha, beta), leg = verdict(ZW_REGION_LEGACY, &c, alpha, beta);
        expect_well_formed(&v);
        assert_false(v.stable);
        assert_false(v.marginal);
        assert_int_equal(v.deciding, ZW_BOUND_LINE);
        assert_int_equal(v.violated, ZW_BOUND_LINE); /* inside the hyperbola */
        assert_true(leg.stable);
        EXPECT_OK(zw_spectral_radius(&c, alpha, beta, &rho));
        assert_true(rho > R(1.5)); /* clearly unstable (1.83, 1.90, 1.80) */
    }
}

/* Table 2: the experimentally reached maxima (stable, inside the theoretical region). */
static void test_paper_table2_points(void **state)
{
    static const zw_real pts[][3] = {
        /* delta, beta, alpha */
        {R(0.013), R(0.826), R(0.656)}, {R(0.013), R(0.0), R(0.026)},
        {R(2.049), R(0.421), R(5.847)}, {R(2.049), R(0.0), R(5.611)},
        {R(5.122), R(-3.162), R(19.858)}, {R(5.122), R(0.0), R(14.154)},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(pts); ++i) {
        zw_coeffs c = zwt_coeffs(pts[i][0]);
        zw_verdict v = exact(&c, pts[i][2], pts[i][1]);
        zw_real rho;
        expect_well_formed(&v);
        EXPECT_TRUE_MSG(v.stable, "Table 2 point %zu (delta %g, beta %g, alpha %g)", i,
                        (double)pts[i][0], (double)pts[i][1], (double)pts[i][2]);
        EXPECT_OK(zw_spectral_radius(&c, pts[i][2], pts[i][1], &rho));
        assert_true(rho < R(1.0));
    }
}

/* ---- legacy against exact ------------------------------------------------------------------ */

/* A box of (alpha, beta) around the interesting part of the plane.  tight: around the
 * exact region (alpha_mmax, beta_mmax); else around everything the legacy region (the
 * whole hyperbola, up to its top and to beta = 2/c2) calls stable. */
static void grid_bounds(zw_real delta, bool tight, zw_real *a_lo, zw_real *a_hi, zw_real *b_lo,
                        zw_real *b_hi)
{
    zw_coeffs c = zwt_coeffs(delta);
    zw_extremes x;
    zw_real top_a, top_b;
    EXPECT_OK(zw_extremes_compute(&c, &x));
    EXPECT_OK(zw_hyperbola_top(&c, &top_a, &top_b));
    *a_hi = R(1.25) * (tight || x.alpha_mmax > top_a ? x.alpha_mmax : top_a) + R(0.05);
    *a_lo = -R(0.05) * *a_hi;
    *b_lo = -delta - R(0.1) * (delta + R(1.0));
    *b_hi = (tight ? x.beta_mmax : R(2.0) / c.c2) + R(0.1) * (delta + R(1.0));
    if (*b_hi > x.beta_mmax + R(3.0) * (delta + R(2.0))) *b_hi = x.beta_mmax + R(3.0) * (delta + R(2.0));
}

/* Above delta0 the legacy region calls unstable points stable, and each such point is
 * decided by the line; the exact region is a subset of the legacy one. */
static void test_legacy_wrong_above_delta0(void **state)
{
    static const zw_real ds[] = {R(2.4), R(3.0), R(5.1224), R(20.0), R(1e4)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real a_lo, a_hi, b_lo, b_hi;
        int i, j, wrong = 0, n = 80;
        grid_bounds(ds[k], false, &a_lo, &a_hi, &b_lo, &b_hi);
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real alpha = a_lo + (a_hi - a_lo) * (zw_real)i / (zw_real)n;
                zw_real beta = b_lo + (b_hi - b_lo) * (zw_real)j / (zw_real)n;
                zw_verdict v = exact(&c, alpha, beta), leg = verdict(ZW_REGION_LEGACY, &c, alpha, beta);
                expect_well_formed(&v);
                expect_well_formed(&leg);
                if (v.stable) assert_true(leg.stable);
                if (leg.stable && !v.stable) {
                    ++wrong;
                    assert_int_equal(v.deciding, ZW_BOUND_LINE);
                }
            }
        }
        EXPECT_TRUE_MSG(wrong > 0, "delta %g: no point where legacy is wrong", (double)ds[k]);
    }
}

/* Below delta0 the line never bites: legacy and exact agree everywhere. */
static void test_legacy_agrees_below_delta0(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-6), R(0.013), R(1.0), R(2.0), R(2.3)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real a_lo, a_hi, b_lo, b_hi;
        int i, j, n = 80;
        grid_bounds(ds[k], false, &a_lo, &a_hi, &b_lo, &b_hi);
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real alpha = a_lo + (a_hi - a_lo) * (zw_real)i / (zw_real)n;
                zw_real beta = b_lo + (b_hi - b_lo) * (zw_real)j / (zw_real)n;
                zw_verdict v = exact(&c, alpha, beta), leg = verdict(ZW_REGION_LEGACY, &c, alpha, beta);
                EXPECT_TRUE_MSG(v.stable == leg.stable, "delta %g alpha %g beta %g: exact %d legacy %d",
                                (double)ds[k], (double)alpha, (double)beta, v.stable, leg.stable);
                /* the line is never the only reason below delta0 */
                if (!v.stable && !v.marginal)
                    assert_true((v.violated & ~(unsigned)ZW_BOUND_LINE) != 0);
            }
        }
    }
}

/* The legacy region's own optimum (top of the hyperbola) is cut off by the line above
 * delta1: the legacy region calls it stable, the exact region unstable by the line. */
static void test_legacy_optimum_unstable(void **state)
{
    static const zw_real ds[] = {R(4.0), R(5.1224), R(20.0)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real a1, b1;
        zw_verdict v, leg;
        EXPECT_OK(zw_hyperbola_top(&c, &a1, &b1));
        a1 *= R(1.0) - R(PREC(1e-6, 1e-3));
        v = exact(&c, a1, b1);
        leg = verdict(ZW_REGION_LEGACY, &c, a1, b1);
        assert_true(leg.stable);
        assert_false(v.stable);
        assert_int_equal(v.deciding, ZW_BOUND_LINE);
    }
}

/* ---- the deciding constraint ---------------------------------------------------------- */

static void test_deciding_constraint(void **state)
{
    static const zw_real ds[] = {R(0.013), R(1.0), R(2.049), R(5.1224), R(20.0)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_verdict v;
        zw_real h = R(2.0) / c.c2;

        /* below -delta (B < -b): add damping */
        v = exact(&c, R(0.1) * (d + R(0.01)), -d - R(0.5) * (d + R(0.1)));
        expect_well_formed(&v);
        assert_false(v.stable);
        assert_false(v.marginal);
        assert_int_equal(v.deciding, ZW_BOUND_DAMPING);
        /* exactly at -delta: not stable (strict inequality), decided by damping */
        v = exact(&c, R(0.1) * d, -d);
        assert_false(v.stable);
        assert_int_equal(v.deciding, ZW_BOUND_DAMPING);
        /* alpha <= 0 with admissible beta */
        v = exact(&c, R(-0.5), R(0.0));
        expect_well_formed(&v);
        assert_false(v.stable);
        assert_false(v.marginal);
        assert_int_equal(v.deciding, ZW_BOUND_STIFFNESS);
        assert_int_equal(v.violated, ZW_BOUND_STIFFNESS);
        v = exact(&c, R(0.0), R(0.0));
        assert_false(v.stable);
        assert_int_equal(v.deciding, ZW_BOUND_STIFFNESS);
        /* both damping and stiffness: damping comes first, both are reported */
        v = exact(&c, R(-1.0), -R(2.0) * d - R(1.0));
        expect_well_formed(&v);
        assert_false(v.stable);
        assert_int_equal(v.deciding, ZW_BOUND_DAMPING);
        assert_true((v.violated & ZW_BOUND_STIFFNESS) != 0);
        /* beyond the hyperbola's right end beta >= 2/c2, tiny alpha: hyperbola (below
         * delta0, where the line lies outside) */
        if (d < ZW_DELTA0) {
            v = exact(&c, R(1e-3), h * R(1.01));
            expect_well_formed(&v);
            assert_false(v.stable);
            assert_int_equal(v.deciding, ZW_BOUND_HYPERBOLA);
            assert_int_equal(v.violated, ZW_BOUND_HYPERBOLA);
        }
        /* above the hyperbola where the line does not bite: hyperbola only */
        {
            zw_real beta = d < ZW_DELTA0 ? R(0.0) : -d + R(0.01) * (d + R(1.0));
            zw_real f = f_hyperbola(&c, beta);
            zw_real alpha = R(1.05) * f;
            long double line = c.d12 > R(0.0) ? 4.0L * (1.0L + c.e) / (long double)c.d12 - 2.0L * beta
                                              : (long double)INFINITY;
            assert_true((long double)alpha < line); /* the line does not bite here */
            v = exact(&c, alpha, beta);
            expect_well_formed(&v);
            assert_false(v.stable);
            assert_false(v.marginal);
            assert_int_equal(v.deciding, ZW_BOUND_HYPERBOLA);
            assert_int_equal(v.violated, ZW_BOUND_HYPERBOLA);
            v = exact(&c, R(0.95) * f, beta);
            assert_true(v.stable);
        }
    }
}

/* Above delta0 at beta = -4 (left of the corner, delta 5.1224) the hyperbola decides, and
 * above both curves (beta = 0, alpha = 30) both are reported, hyperbola first. */
static void test_deciding_both_curves(void **state)
{
    zw_coeffs c = zwt_coeffs(R(5.1224));
    zw_verdict v;
    (void)state;
    v = exact(&c, R(21.0), R(-4.0)); /* f(-4) = 18.4 < 21 < L(-4) = 24.7 */
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_BOUND_HYPERBOLA);
    assert_int_equal(v.violated, ZW_BOUND_HYPERBOLA);
    v = exact(&c, R(30.0), R(0.0)); /* f(0) = 27.07, L(0) = 16.68 */
    expect_well_formed(&v);
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_BOUND_HYPERBOLA);
    assert_int_equal(v.violated, ZW_BOUND_HYPERBOLA | ZW_BOUND_LINE);
}

/* ---- delta = 0, eq (17) ----------------------------------------------------------------- */

/* alpha < (-2 beta^2 + 4 beta) / (beta + 2), beta > 0: just inside stable, just outside
 * unstable, both with delta = 0 coefficients (exact region) and through ZW_REGION_DELTA0
 * (which ignores the plant's delta). */
static void test_delta_zero_closed_form(void **state)
{
    const zw_real margin = R(PREC(1e-4, 1e-2));
    zw_coeffs c0 = zwt_coeffs(R(0.0)), c3 = zwt_coeffs(R(3.0));
    int j, n = 400;
    (void)state;
    for (j = 1; j < n; ++j) {
        zw_real beta = R(2.0) * (zw_real)j / (zw_real)n;
        long double b = beta;
        zw_real bound = (zw_real)((-2.0L * b * b + 4.0L * b) / (b + 2.0L));
        zw_real in = bound * (R(1.0) - margin), out = bound * (R(1.0) + margin);
        zw_verdict v;
        v = exact(&c0, in, beta);
        EXPECT_TRUE_MSG(v.stable, "delta 0, beta %g, alpha %g (bound %g)", (double)beta,
                        (double)in, (double)bound);
        v = exact(&c0, out, beta);
        assert_false(v.stable);
        assert_int_equal(v.deciding, ZW_BOUND_HYPERBOLA);
        assert_true(verdict(ZW_REGION_DELTA0, &c3, in, beta).stable);
        assert_false(verdict(ZW_REGION_DELTA0, &c3, out, beta).stable);
        assert_true(verdict(ZW_REGION_DELTA0, &c0, in, beta).stable);
    }
    /* beta must be positive at delta = 0; beta >= 2 admits no alpha */
    assert_int_equal(exact(&c0, R(0.1), R(0.0)).deciding, ZW_BOUND_DAMPING);
    assert_int_equal(exact(&c0, R(0.1), R(-0.1)).deciding, ZW_BOUND_DAMPING);
    assert_false(exact(&c0, R(1e-3), R(2.0)).stable);
    assert_false(exact(&c0, R(1e-6), R(2.5)).stable);
    assert_false(verdict(ZW_REGION_DELTA0, &c3, R(1e-3), R(2.5)).stable);
    assert_false(verdict(ZW_REGION_DELTA0, &c3, R(0.1), R(-0.1)).stable);
}

/* ---- passivity (16) and the linear regions (14)-(15), (18) --------------------------- */

/* Every point of the passivity region 0 < alpha/2 < delta - |beta| is exact-stable. */
static void test_passivity_implies_stable(void **state)
{
    static const zw_real ds[] = {R(1e-6), R(0.013), R(1.0), R(2.3), R(3.0), R(5.12), R(20.0), R(1e4)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        int i, j, n = 60, passive = 0;
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real alpha = R(2.0) * d * (zw_real)i / (zw_real)n;
                zw_real beta = -d + R(2.0) * d * (zw_real)j / (zw_real)n;
                zw_verdict p = verdict(ZW_REGION_PASSIVITY, &c, alpha, beta);
                expect_well_formed(&p);
                if (p.stable) {
                    ++passive;
                    EXPECT_TRUE_MSG(exact(&c, alpha, beta).stable,
                                    "passive but not stable: delta %g alpha %g beta %g",
                                    (double)d, (double)alpha, (double)beta);
                } else {
                    assert_true(p.deciding == ZW_BOUND_STIFFNESS || p.deciding == ZW_BOUND_PASSIVITY);
                }
            }
        }
        assert_true(passive > n); /* the region is not empty on this grid */
    }
}

/* Each linear region against its own definition, well inside and well outside. */
static void test_linear_regions(void **state)
{
    static const zw_real ds[] = {R(0.013), R(1.0), R(5.1224), R(20.0)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        int j;
        for (j = -9; j <= 9; ++j) {
            zw_real beta = d * (zw_real)j / R(10.0);
            zw_real lim_pass = R(2.0) * (d - ZW_FABS(beta));   /* (16) */
            zw_real lim_inf = R(2.0) * (d - beta);             /* (14), (15) */
            zw_real lim_small = R(2.0) * (d + beta);           /* (18) */
            zw_verdict v;
            assert_true(verdict(ZW_REGION_PASSIVITY, &c, R(0.9) * lim_pass, beta).stable);
            v = verdict(ZW_REGION_PASSIVITY, &c, R(1.1) * lim_pass, beta);
            assert_false(v.stable);
            assert_int_equal(v.deciding, ZW_BOUND_PASSIVITY);
            assert_true(verdict(ZW_REGION_DELTA_INF, &c, R(0.9) * lim_inf, beta).stable);
            v = verdict(ZW_REGION_DELTA_INF, &c, R(1.1) * lim_inf, beta);
            assert_false(v.stable);
            assert_int_equal(v.deciding, ZW_BOUND_LINE);
            assert_true(verdict(ZW_REGION_SMALL, &c, R(0.9) * lim_small, beta).stable);
            assert_false(verdict(ZW_REGION_SMALL, &c, R(1.1) * lim_small, beta).stable);
        }
        /* alpha <= 0 is outside all three; beta <= -delta outside (14)-(15) */
        assert_int_equal(verdict(ZW_REGION_PASSIVITY, &c, R(-0.1), R(0.0)).deciding, ZW_BOUND_STIFFNESS);
        assert_int_equal(verdict(ZW_REGION_DELTA_INF, &c, R(-0.1), R(0.0)).deciding, ZW_BOUND_STIFFNESS);
        assert_int_equal(verdict(ZW_REGION_SMALL, &c, R(-0.1), R(0.0)).deciding, ZW_BOUND_STIFFNESS);
        assert_int_equal(verdict(ZW_REGION_DELTA_INF, &c, R(0.1) * d, -d * R(1.5)).deciding,
                         ZW_BOUND_DAMPING);
    }
    /* delta = 0: the passivity region is empty */
    {
        zw_coeffs c0 = zwt_coeffs(R(0.0));
        assert_false(verdict(ZW_REGION_PASSIVITY, &c0, R(1e-6), R(0.0)).stable);
    }
}

/* ---- proportional control ------------------------------------------------------------- */

static void test_proportional_is_beta_zero(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        int i, n = 400;
        zw_real top = R(3.0) * (R(4.0) * ds[k] + R(4.0));
        for (i = -5; i <= n; ++i) {
            zw_real alpha = top * (zw_real)i / (zw_real)n;
            zw_verdict p, v = exact(&c, alpha, R(0.0));
            memset(&p, 0, sizeof p);
            EXPECT_OK(zw_check_proportional(&c, alpha, &p));
            assert_true(zwt_same_verdict(&p, &v));
        }
    }
}

/* ---- errors ------------------------------------------------------------------------------ */

static void expect_check_error(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_status want)
{
    zw_verdict out;
    int r;
    memset(&out, ZWT_SENTINEL, sizeof out);
    EXPECT_STATUS(zw_check(c, alpha, beta, &out), want);
    assert_true(zwt_failsafe_verdict(&out));
    for (r = ZW_REGION_EXACT; r <= ZW_REGION_SMALL; ++r) {
        /* hs = +inf (ZW_ERR_RANGE) matters only to the regions that use it, exact and legacy */
        if (want == ZW_ERR_RANGE && r != ZW_REGION_EXACT && r != ZW_REGION_LEGACY) {
            zw_verdict other;
            EXPECT_OK(zw_check_region((zw_region)r, c, alpha, beta, &other));
            continue;
        }
        memset(&out, ZWT_SENTINEL, sizeof out);
        EXPECT_STATUS(zw_check_region((zw_region)r, c, alpha, beta, &out), want);
        assert_true(zwt_failsafe_verdict(&out));
    }
    if (beta == R(0.0)) {
        memset(&out, ZWT_SENTINEL, sizeof out);
        EXPECT_STATUS(zw_check_proportional(c, alpha, &out), want);
        assert_true(zwt_failsafe_verdict(&out));
    }
}

static void test_input_errors(void **state)
{
    const zw_real nan = (zw_real)NAN, inf = (zw_real)INFINITY;
    zw_coeffs c = zwt_coeffs(R(1.0)), cinf = zwt_coeffs(inf), cnan = zwt_coeffs(R(1.0)),
              cbig = zwt_coeffs(ZW_REAL_MAX);
    (void)state;
    cnan.delta = nan;
    expect_check_error(&c, nan, R(0.0), ZW_ERR_NAN);
    expect_check_error(&c, R(1.0), nan, ZW_ERR_NAN);
    expect_check_error(&c, inf, R(0.0), ZW_ERR_INF);
    expect_check_error(&c, -inf, R(0.0), ZW_ERR_INF);
    expect_check_error(&c, R(1.0), inf, ZW_ERR_INF);
    expect_check_error(&c, R(1.0), -inf, ZW_ERR_INF);
    expect_check_error(&cinf, R(1.0), R(0.0), ZW_ERR_INF);
    expect_check_error(&cnan, R(1.0), R(0.0), ZW_ERR_NAN);
    /* delta so large that hs is +inf (coeffs.h): the checks answer ZW_ERR_RANGE */
    assert_true(isinf(cbig.hs));
    expect_check_error(&cbig, R(1.0), R(0.0), ZW_ERR_RANGE);
    expect_check_error(NULL, R(1.0), R(0.0), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check(&c, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_region(ZW_REGION_LEGACY, &c, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_proportional(&c, R(1.0), NULL), ZW_ERR_NULL);
}

/* A negative or non-finite delta uncertainty would shrink every guard (review finding S2:
 * delta_relerr = -1e-3 once made beta < -delta "stable"): refused with ZW_ERR_ARG. */
static void test_bad_delta_relerr(void **state)
{
    zw_coeffs c = zwt_coeffs(R(5.0));
    (void)state;
    c.delta_relerr = R(-1e-3);
    expect_check_error(&c, R(1.0), R(-5.001), ZW_ERR_ARG);
    c.delta_relerr = (zw_real)INFINITY;
    expect_check_error(&c, R(1.0), R(0.0), ZW_ERR_ARG);
    c.delta_relerr = (zw_real)NAN;
    expect_check_error(&c, R(1.0), R(0.0), ZW_ERR_ARG);
}

static void test_bad_region(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0));
    zw_verdict out;
    static const int bad[] = {ZW_REGION_SMALL + 1, 42, -1};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(bad); ++i) {
        memset(&out, ZWT_SENTINEL, sizeof out);
        EXPECT_STATUS(zw_check_region((zw_region)bad[i], &c, R(0.5), R(0.5), &out), ZW_ERR_ARG);
        assert_true(zwt_failsafe_verdict(&out));
    }
}

/* ---- safety sweep against the poles ------------------------------------------------- */

/* Across the brief's deltas, a few thousand points each: the verdict never says stable
 * where the spectral radius exceeds 1 + 1e-6, and (the region being exact, not merely
 * sufficient) never says surely unstable where it is below 1 - 1e-6.  Besides a uniform
 * grid, points a few ulps either side of alpha_max(beta) probe the boundary itself. */
static void sweep_point(const zw_coeffs *c, zw_real alpha, zw_real beta, int *n_stable,
                        int *n_unstable)
{
    const zw_real slack = R(1e-6);
    zw_real rho;
    zw_verdict v = exact(c, alpha, beta);
    zw_status st = zw_spectral_radius(c, alpha, beta, &rho);
    expect_well_formed(&v);
    EXPECT_OK(st);
    if (v.stable) {
        ++*n_stable;
        EXPECT_TRUE_MSG(rho <= R(1.0) + slack,
                        "STABLE verdict but rho = %.9g: delta %.9g alpha %.9g beta %.9g",
                        (double)rho, (double)c->delta, (double)alpha, (double)beta);
    } else if (!v.marginal) {
        ++*n_unstable;
        EXPECT_TRUE_MSG(rho >= R(1.0) - slack,
                        "surely unstable (bound %d) but rho = %.9g: delta %.9g alpha %.9g beta %.9g",
                        (int)v.deciding, (double)rho, (double)c->delta, (double)alpha, (double)beta);
    }
}

static void test_never_stable_outside_unit_circle(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_real a_lo, a_hi, b_lo, b_hi;
        int i, j, n = 60, n_stable = 0, n_unstable = 0;
        grid_bounds(d, true, &a_lo, &a_hi, &b_lo, &b_hi);
        for (i = 0; i <= n; ++i)
            for (j = 0; j <= n; ++j)
                sweep_point(&c, a_lo + (a_hi - a_lo) * (zw_real)i / (zw_real)n,
                            b_lo + (b_hi - b_lo) * (zw_real)j / (zw_real)n, &n_stable, &n_unstable);
        for (j = 0; j <= 4 * n; ++j) {
            zw_real beta = b_lo + (b_hi - b_lo) * (zw_real)j / (zw_real)(4 * n), am, a;
            int u;
            EXPECT_OK(zw_alpha_max(&c, beta, &am));
            if (!(am > R(0.0))) continue;
            for (u = -3; u <= 3; ++u) {
                a = am * (R(1.0) + TOL(64) * (zw_real)u);
                sweep_point(&c, a, beta, &n_stable, &n_unstable);
            }
            sweep_point(&c, ZWT_UP(am), beta, &n_stable, &n_unstable);
            sweep_point(&c, ZWT_DOWN(am), beta, &n_stable, &n_unstable);
        }
        EXPECT_TRUE_MSG(n_stable > 100 && n_unstable > 100, "delta %g: %d stable, %d unstable",
                        (double)d, n_stable, n_unstable);
    }
}

/* ---- the safety claim at the ulp level ----------------------------------------------- */

/* The boundary of the exact region, min{f(beta), L(beta)}, from the true coefficient
 * functions (the long-double reference, not the library's fields). */
static long double true_alpha_max(zw_real delta, zw_real beta)
{
    zwt_ref r = zwt_reference((long double)delta);
    long double x = (long double)beta + (long double)delta, b = beta;
    long double f = r.s * x * (2.0L - r.c2 * b) / ((r.c1 * x + r.s) * r.c2);
    if (delta > R(0.0)) {
        long double line = 4.0L * (1.0L + r.e) / r.d12 - 2.0L * b;
        if (line < f) f = line;
    }
    return f;
}

/* Points a few ulps either side of the true boundary: none at or beyond it is called
 * stable (region.h: "an unstable point is never called stable"), and the band of
 * "could not prove stable" below it is narrow (a few ulps of the inputs, here at most
 * 2000 u of alpha in the well-conditioned middle of the beta range). */
static void test_ulp_level_safety(void **state)
{
    static const zw_real ds[] = ZWT_SWEEP_DELTAS;
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real d = ds[k];
        zw_coeffs c = zwt_coeffs(d);
        zw_extremes x;
        int j, n = 400, beyond = 0;
        EXPECT_OK(zw_extremes_compute(&c, &x));
        for (j = 1; j < n; ++j) {
            zw_real beta = -d + (x.beta_mmax + d) * (zw_real)j / (zw_real)n, a;
            long double A = true_alpha_max(d, beta);
            int u;
            if (!(A > 0.1L * (long double)x.alpha_mmax)) continue; /* ill-conditioned ends */
            a = (zw_real)A;
            for (u = 0; u < 12; ++u) a = ZWT_DOWN(a);
            for (u = 0; u < 24; ++u, a = ZWT_UP(a)) {
                zw_verdict v = exact(&c, a, beta);
                if ((long double)a >= A * (1.0L + 1e-17L)) {
                    ++beyond;
                    EXPECT_TRUE_MSG(!v.stable,
                                    "delta %g beta %.17g: alpha %.17Lg >= true boundary %.21Lg called stable",
                                    (double)d, (double)beta, (long double)a, A);
                }
            }
            a = (zw_real)(A * (1.0L - TOLL(2000)));
            EXPECT_TRUE_MSG(exact(&c, a, beta).stable,
                            "delta %g beta %.17g: alpha %.17Lg, 2000 u below the boundary %.21Lg, not stable",
                            (double)d, (double)beta, (long double)a, A);
        }
        assert_true(beyond > 100);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper_fig19_points),
        cmocka_unit_test(test_paper_table2_points),
        cmocka_unit_test(test_legacy_wrong_above_delta0),
        cmocka_unit_test(test_legacy_agrees_below_delta0),
        cmocka_unit_test(test_legacy_optimum_unstable),
        cmocka_unit_test(test_deciding_constraint),
        cmocka_unit_test(test_deciding_both_curves),
        cmocka_unit_test(test_delta_zero_closed_form),
        cmocka_unit_test(test_passivity_implies_stable),
        cmocka_unit_test(test_linear_regions),
        cmocka_unit_test(test_proportional_is_beta_zero),
        cmocka_unit_test(test_input_errors),
        cmocka_unit_test(test_bad_region),
        cmocka_unit_test(test_bad_delta_relerr),
        cmocka_unit_test(test_never_stable_outside_unit_circle),
        cmocka_unit_test(test_ulp_level_safety),
    };
    printf("zwidth C tests: region (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("region_" ZW_REAL_NAME, tests, NULL, NULL);
}
