/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Fail-safe outputs (status.h): a caller that ignores the status never reads "stable".
 *
 * For every public function of coeffs.h, region.h, margin.h, extremes.h, device.h and
 * batch.h, each output is pre-filled with a "stable" state (verdict stable, limits 1e9,
 * ranges wide, rho 0.5, flags true, a valid plant), then every error path is driven (each
 * NULL pointer with the other outputs present, NaN, +-inf, m/T <= 0, b < 0, delta < 0,
 * bad r, bad region, overflow, a plant left NaN by a failed init) and the outputs must hold
 * the documented fail-safe values: verdicts not stable (ZW_BOUND_INVALID), flags false,
 * limits 0, ranges empty, rho +inf, plants, coefficients and gains NaN.
 * (zw_sim_judge: tests/c/test_sim.c, test_judge_errors.) */
#include "zw_test.h"

#define BIG R(1e9)

static zw_verdict stable_verdict(void)
{
    zw_verdict v;
    v.stable = true;
    v.marginal = false;
    v.deciding = ZW_BOUND_NONE;
    v.violated = 0u;
    return v;
}

static void expect_failsafe_verdict(const zw_verdict *v, const char *what)
{
    EXPECT_TRUE_MSG(zwt_failsafe_verdict(v), "%s: stable %d marginal %d deciding %d violated %u",
                    what, (int)v->stable, (int)v->marginal, (int)v->deciding,
                    (unsigned)v->violated);
}

static bool is_pos_inf(zw_real x)
{
    return isinf(x) && x > R(0.0);
}

/* ---- the bad plants ----------------------------------------------------------------------- */

/* A coefficient set every check refuses: want is the status; hs_only: only the functions
 * that use hs (exact and legacy regions, extremes, batch) refuse it. */
typedef struct bad_coeffs {
    const char *what;
    zw_coeffs c;
    zw_status want;
    bool hs_only;
} bad_coeffs;

enum { N_BAD_COEFFS = 7 };

static void make_bad_coeffs(bad_coeffs out[N_BAD_COEFFS])
{
    zw_coeffs failed = zwt_coeffs(R(1.0));
    EXPECT_STATUS(zw_coeffs_init(&failed, (zw_real)NAN), ZW_ERR_NAN);
    out[0].what = "failed zw_coeffs_init (NaN)";
    out[0].c = failed;
    out[0].want = ZW_ERR_NAN;
    out[0].hs_only = false;
    out[1].what = "delta = +inf";
    out[1].c = zwt_coeffs((zw_real)INFINITY);
    out[1].want = ZW_ERR_INF;
    out[1].hs_only = false;
    out[2].what = "delta_relerr < 0";
    out[2].c = zwt_coeffs(R(1.0));
    out[2].c.delta_relerr = R(-1e-3);
    out[2].want = ZW_ERR_ARG;
    out[2].hs_only = false;
    out[3].what = "delta_relerr NaN";
    out[3].c = zwt_coeffs(R(1.0));
    out[3].c.delta_relerr = (zw_real)NAN;
    out[3].want = ZW_ERR_ARG;
    out[3].hs_only = false;
    out[4].what = "delta_relerr +inf";
    out[4].c = zwt_coeffs(R(1.0));
    out[4].c.delta_relerr = (zw_real)INFINITY;
    out[4].want = ZW_ERR_ARG;
    out[4].hs_only = false;
    out[5].what = "delta = max (hs = +inf)";
    out[5].c = zwt_coeffs(ZW_REAL_MAX);
    out[5].want = ZW_ERR_RANGE;
    out[5].hs_only = true;
    out[6].what = "failed zw_coeffs_init (delta < 0)";
    out[6].c = zwt_coeffs(R(1.0));
    EXPECT_STATUS(zw_coeffs_init(&out[6].c, R(-1.0)), ZW_ERR_DELTA);
    out[6].want = ZW_ERR_NAN;
    out[6].hs_only = false;
    assert_true(isinf(out[5].c.hs));
}

/* Gains refused by every check: bad_gain(i), with status k_bad_gain_status[i]. */
static const zw_status k_bad_gain_status[] = {ZW_ERR_NAN, ZW_ERR_INF, ZW_ERR_INF};

static zw_real bad_gain(size_t i)
{
    switch (i) {
    case 0: return (zw_real)NAN;
    case 1: return (zw_real)INFINITY;
    default: return -(zw_real)INFINITY;
    }
}

#define N_BAD_GAINS ZWT_ARRAY_LEN(k_bad_gain_status)

/* ---- coeffs.h ------------------------------------------------------------------------------ */

static void test_coeffs(void **state)
{
    static const struct {
        zw_real delta;
        zw_status want;
    } cases[] = {{(zw_real)NAN, ZW_ERR_NAN}, {R(-1.0), ZW_ERR_DELTA},
                 {-(zw_real)INFINITY, ZW_ERR_DELTA}, {-ZWT_TRUE_MIN, ZW_ERR_DELTA}};
    size_t i, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_coeffs c = zwt_coeffs(R(1.0));
        zw_real out[3];
        EXPECT_STATUS(zw_coeffs_init(&c, cases[i].delta), cases[i].want);
        assert_true(zwt_all_nan_coeffs(&c));
        out[0] = out[1] = out[2] = R(0.5);
        EXPECT_STATUS(zw_coeffs_literal(cases[i].delta, &out[0], &out[1], &out[2]), cases[i].want);
        assert_true(isnan(out[0]) && isnan(out[1]) && isnan(out[2]));
    }
    EXPECT_STATUS(zw_coeffs_init(NULL, R(1.0)), ZW_ERR_NULL);
    /* zw_coeffs_literal: each NULL, the other two still written */
    for (k = 0; k < 3; ++k) {
        zw_real out[3] = {R(0.5), R(0.5), R(0.5)};
        zw_real *p[3];
        p[0] = &out[0];
        p[1] = &out[1];
        p[2] = &out[2];
        p[k] = NULL;
        EXPECT_STATUS(zw_coeffs_literal(R(1.0), p[0], p[1], p[2]), ZW_ERR_NULL);
        for (i = 0; i < 3; ++i)
            if (i != k) assert_true(isnan(out[i]));
    }
}

/* ---- region.h ------------------------------------------------------------------------------ */

/* zw_check, every zw_check_region and zw_check_proportional (when beta = 0) on (c, alpha,
 * beta): status want (hs_only: only for the regions that use hs, the others must pass). */
static void expect_check_errors(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_status want,
                                bool hs_only, const char *what)
{
    zw_verdict v;
    int r;
    v = stable_verdict();
    EXPECT_STATUS(zw_check(c, alpha, beta, &v), want);
    expect_failsafe_verdict(&v, what);
    for (r = ZW_REGION_EXACT; r <= ZW_REGION_SMALL; ++r) {
        v = stable_verdict();
        if (hs_only && r != ZW_REGION_EXACT && r != ZW_REGION_LEGACY) {
            EXPECT_OK(zw_check_region((zw_region)r, c, alpha, beta, &v));
            continue;
        }
        EXPECT_STATUS(zw_check_region((zw_region)r, c, alpha, beta, &v), want);
        expect_failsafe_verdict(&v, what);
    }
    if (beta == R(0.0)) {
        v = stable_verdict();
        EXPECT_STATUS(zw_check_proportional(c, alpha, &v), want);
        expect_failsafe_verdict(&v, what);
    }
}

static void test_region(void **state)
{
    bad_coeffs bad[N_BAD_COEFFS];
    const zw_coeffs c = zwt_coeffs(R(1.0));
    static const int bad_regions[] = {-1, ZW_REGION_SMALL + 1, 42};
    zw_verdict v;
    size_t i;
    (void)state;
    make_bad_coeffs(bad);
    /* the point is stable on the good plant: only the error makes it not stable */
    EXPECT_OK(zw_check(&c, R(0.1), R(0.0), &v));
    assert_true(v.stable);
    for (i = 0; i < N_BAD_COEFFS; ++i)
        expect_check_errors(&bad[i].c, R(0.1), R(0.0), bad[i].want, bad[i].hs_only, bad[i].what);
    expect_check_errors(NULL, R(0.1), R(0.0), ZW_ERR_NULL, false, "c NULL");
    for (i = 0; i < N_BAD_GAINS; ++i) {
        expect_check_errors(&c, bad_gain(i), R(0.0), k_bad_gain_status[i], false, "bad alpha");
        expect_check_errors(&c, R(0.1), bad_gain(i), k_bad_gain_status[i], false, "bad beta");
    }
    for (i = 0; i < ZWT_ARRAY_LEN(bad_regions); ++i) {
        v = stable_verdict();
        EXPECT_STATUS(zw_check_region((zw_region)bad_regions[i], &c, R(0.1), R(0.0), &v), ZW_ERR_ARG);
        expect_failsafe_verdict(&v, "bad region");
        /* the region is checked after the plant: a NaN plant reports NaN, still fail-safe */
        v = stable_verdict();
        EXPECT_STATUS(zw_check_region((zw_region)bad_regions[i], &bad[0].c, R(0.1), R(0.0), &v),
                      ZW_ERR_NAN);
        expect_failsafe_verdict(&v, "bad region, NaN plant");
    }
    EXPECT_STATUS(zw_check(&c, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_region(ZW_REGION_EXACT, &c, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_check_proportional(&c, R(0.1), NULL), ZW_ERR_NULL);
}

/* ---- margin.h ------------------------------------------------------------------------------ */

/* zw_char_poly, zw_spectral_radius and zw_radius_within (r = 1) on (c, alpha, beta). */
static void expect_margin_errors(const zw_coeffs *c, zw_real alpha, zw_real beta, zw_status want,
                                 const char *what)
{
    zw_real p[4] = {R(2.0), R(0.0), R(0.0), R(0.0)}, rho = R(0.5);
    bool within = true;
    EXPECT_STATUS(zw_char_poly(c, alpha, beta, p), want);
    EXPECT_TRUE_MSG(isnan(p[0]) && isnan(p[1]) && isnan(p[2]) && isnan(p[3]), "%s: p", what);
    EXPECT_STATUS(zw_spectral_radius(c, alpha, beta, &rho), want);
    EXPECT_TRUE_MSG(is_pos_inf(rho), "%s: rho %g", what, (double)rho);
    EXPECT_STATUS(zw_radius_within(c, alpha, beta, R(1.0), &within), want);
    EXPECT_TRUE_MSG(!within, "%s: within", what);
}

static void test_margin(void **state)
{
    bad_coeffs bad[N_BAD_COEFFS];
    const zw_coeffs c = zwt_coeffs(R(1.0));
    static const struct {
        zw_real r;
        zw_status want;
    } bad_r[] = {{(zw_real)NAN, ZW_ERR_NAN}, {R(0.0), ZW_ERR_ARG},       {-R(0.0), ZW_ERR_ARG},
                 {R(-1.0), ZW_ERR_ARG},      {(zw_real)INFINITY, ZW_ERR_ARG},
                 {-(zw_real)INFINITY, ZW_ERR_ARG}};
    zw_real p[4], rho;
    bool within;
    size_t i;
    (void)state;
    make_bad_coeffs(bad);
    for (i = 0; i < N_BAD_COEFFS; ++i)
        if (!bad[i].hs_only) expect_margin_errors(&bad[i].c, R(0.1), R(0.0), bad[i].want, bad[i].what);
    expect_margin_errors(NULL, R(0.1), R(0.0), ZW_ERR_NULL, "c NULL");
    for (i = 0; i < N_BAD_GAINS; ++i) {
        expect_margin_errors(&c, bad_gain(i), R(0.0), k_bad_gain_status[i], "bad alpha");
        expect_margin_errors(&c, R(0.1), bad_gain(i), k_bad_gain_status[i], "bad beta");
    }
    /* overflow of a coefficient: ZW_ERR_RANGE (the Jury test bounds it instead: not stable) */
    p[0] = R(2.0);
    p[1] = p[2] = p[3] = R(0.0);
    EXPECT_STATUS(zw_char_poly(&c, ZW_REAL_MAX, ZW_REAL_MAX, p), ZW_ERR_RANGE);
    assert_true(isnan(p[0]) && isnan(p[1]) && isnan(p[2]) && isnan(p[3]));
    rho = R(0.5);
    EXPECT_STATUS(zw_spectral_radius(&c, ZW_REAL_MAX, ZW_REAL_MAX, &rho), ZW_ERR_RANGE);
    assert_true(is_pos_inf(rho));
    for (i = 0; i < ZWT_ARRAY_LEN(bad_r); ++i) {
        within = true;
        EXPECT_STATUS(zw_radius_within(&c, R(0.1), R(0.0), bad_r[i].r, &within), bad_r[i].want);
        assert_false(within);
    }
    /* the radius is checked after the gains and the plant */
    within = true;
    EXPECT_STATUS(zw_radius_within(&bad[0].c, R(0.1), R(0.0), R(-1.0), &within), ZW_ERR_NAN);
    assert_false(within);
    EXPECT_STATUS(zw_char_poly(&c, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_spectral_radius(&c, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_radius_within(&c, R(0.1), R(0.0), R(1.0), NULL), ZW_ERR_NULL);
}

/* ---- extremes.h ---------------------------------------------------------------------------- */

static zw_extremes big_extremes(void)
{
    zw_extremes x;
    x.alpha_mmax = x.beta_at_alpha_mmax = x.alpha_p_max = x.beta_mmax = BIG;
    x.beta_mmin = -BIG;
    x.alpha_mmin = R(0.0);
    x.at_corner = true;
    return x;
}

static void expect_zero_extremes(const zw_extremes *x, const char *what)
{
    EXPECT_TRUE_MSG(x->alpha_mmax == R(0.0) && x->beta_at_alpha_mmax == R(0.0) &&
                        x->alpha_p_max == R(0.0) && x->beta_mmax == R(0.0) &&
                        x->beta_mmin == R(0.0) && x->alpha_mmin == R(0.0) && !x->at_corner,
                    "%s: extremes not all 0", what);
}

/* Every function of extremes.h on c (gain 0.1 where one is taken): status want. */
static void expect_extremes_errors(const zw_coeffs *c, zw_status want, const char *what)
{
    zw_extremes x = big_extremes();
    zw_real a = BIG, b = BIG, lo = -BIG, hi = BIG;
    bool ne = true;
    EXPECT_STATUS(zw_extremes_compute(c, &x), want);
    expect_zero_extremes(&x, what);
    EXPECT_STATUS(zw_hyperbola_top(c, &a, &b), want);
    EXPECT_TRUE_MSG(a == R(0.0) && b == R(0.0), "%s: top", what);
    a = b = BIG;
    EXPECT_STATUS(zw_corner(c, &a, &b), want);
    EXPECT_TRUE_MSG(a == R(0.0) && b == R(0.0), "%s: corner", what);
    a = BIG;
    EXPECT_STATUS(zw_alpha_max(c, R(0.0), &a), want);
    EXPECT_TRUE_MSG(a == R(0.0), "%s: alpha_max", what);
    EXPECT_STATUS(zw_beta_interval(c, R(0.1), &lo, &hi, &ne), want);
    EXPECT_TRUE_MSG(lo == R(0.0) && hi == R(0.0) && !ne, "%s: beta interval", what);
}

static void test_extremes(void **state)
{
    bad_coeffs bad[N_BAD_COEFFS];
    const zw_coeffs c = zwt_coeffs(R(5.0));
    zw_extremes x;
    zw_real a, b, lo, hi;
    bool ne;
    size_t i, k;
    (void)state;
    make_bad_coeffs(bad);
    for (i = 0; i < N_BAD_COEFFS; ++i) expect_extremes_errors(&bad[i].c, bad[i].want, bad[i].what);
    expect_extremes_errors(NULL, ZW_ERR_NULL, "c NULL");
    /* each NULL output: the others still written */
    EXPECT_STATUS(zw_extremes_compute(&c, NULL), ZW_ERR_NULL);
    a = b = BIG;
    EXPECT_STATUS(zw_hyperbola_top(&c, NULL, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_hyperbola_top(&c, &a, NULL), ZW_ERR_NULL);
    assert_true(a == R(0.0) && b == R(0.0));
    a = b = BIG;
    EXPECT_STATUS(zw_corner(&c, NULL, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_corner(&c, &a, NULL), ZW_ERR_NULL);
    assert_true(a == R(0.0) && b == R(0.0));
    EXPECT_STATUS(zw_alpha_max(&c, R(0.0), NULL), ZW_ERR_NULL);
    for (k = 0; k < 3; ++k) {
        lo = -BIG;
        hi = BIG;
        ne = true;
        EXPECT_STATUS(zw_beta_interval(&c, R(0.1), k == 0 ? NULL : &lo, k == 1 ? NULL : &hi,
                                       k == 2 ? NULL : &ne),
                      ZW_ERR_NULL);
        assert_true((k == 0 || lo == R(0.0)) && (k == 1 || hi == R(0.0)) && (k == 2 || !ne));
    }
    /* bad gains */
    for (i = 0; i < N_BAD_GAINS; ++i) {
        a = BIG;
        EXPECT_STATUS(zw_alpha_max(&c, bad_gain(i), &a), k_bad_gain_status[i]);
        assert_true(a == R(0.0));
        lo = -BIG;
        hi = BIG;
        ne = true;
        EXPECT_STATUS(zw_beta_interval(&c, bad_gain(i), &lo, &hi, &ne), k_bad_gain_status[i]);
        assert_true(lo == R(0.0) && hi == R(0.0) && !ne);
    }
    /* the corner does not exist for delta <= delta0 */
    {
        const zw_coeffs c1 = zwt_coeffs(R(1.0)), c0 = zwt_coeffs(ZW_DELTA0);
        a = b = BIG;
        EXPECT_STATUS(zw_corner(&c1, &a, &b), ZW_ERR_DOMAIN);
        assert_true(a == R(0.0) && b == R(0.0));
        a = b = BIG;
        EXPECT_STATUS(zw_corner(&c0, &a, &b), ZW_ERR_DOMAIN);
        assert_true(a == R(0.0) && b == R(0.0));
    }
    /* results that overflow with hs finite: the top ~2 delta^2, the corner ~4 delta, the
     * line 2 (lambda - beta) far left */
    {
        const zw_coeffs ctop = zwt_coeffs(R(PREC(1e160, 1e20)));
        const zw_coeffs chuge = zwt_coeffs(ZW_REAL_MAX / R(3.0));
        assert_true(!isinf(ctop.hs) && !isinf(chuge.hs));
        a = b = BIG;
        EXPECT_STATUS(zw_hyperbola_top(&ctop, &a, &b), ZW_ERR_RANGE);
        assert_true(a == R(0.0) && b == R(0.0));
        x = big_extremes();
        EXPECT_STATUS(zw_extremes_compute(&chuge, &x), ZW_ERR_RANGE);
        expect_zero_extremes(&x, "extremes overflow");
        a = b = BIG;
        EXPECT_STATUS(zw_corner(&chuge, &a, &b), ZW_ERR_RANGE);
        assert_true(a == R(0.0) && b == R(0.0));
        a = BIG;
        EXPECT_STATUS(zw_alpha_max(&chuge, -ZW_REAL_MAX / R(4.0), &a), ZW_ERR_RANGE);
        assert_true(a == R(0.0));
    }
}

/* ---- device.h ------------------------------------------------------------------------------ */

static zw_device good_device(void)
{
    zw_device d;
    EXPECT_OK(zw_device_init(&d, R(0.12), R(0.8), R(0.02)));
    return d;
}

/* k_scale = m / T^2 = 0.25 < 1: the largest K overflows alpha. */
static zw_device small_device(void)
{
    zw_device d;
    EXPECT_OK(zw_device_init(&d, R(1e-4), R(1e-3), R(0.02)));
    return d;
}

static void expect_nan_device(const zw_device *d, const char *what)
{
    EXPECT_TRUE_MSG(isnan(d->m) && isnan(d->b) && isnan(d->T) && isnan(d->k_scale) &&
                        isnan(d->b_scale) && zwt_all_nan_coeffs(&d->co),
                    "%s: device not all NaN", what);
}

static void test_device_init(void **state)
{
    const zw_real nan = (zw_real)NAN, inf = (zw_real)INFINITY;
    const struct {
        zw_real m, b, T;
        zw_status want;
    } cases[] = {
        {nan, R(1.0), R(0.01), ZW_ERR_NAN},       {R(1.0), nan, R(0.01), ZW_ERR_NAN},
        {R(1.0), R(1.0), nan, ZW_ERR_NAN},        {inf, R(1.0), R(0.01), ZW_ERR_INF},
        {R(1.0), inf, R(0.01), ZW_ERR_INF},       {R(1.0), R(1.0), inf, ZW_ERR_INF},
        {-inf, R(1.0), R(0.01), ZW_ERR_INF},      {R(1.0), R(1.0), -inf, ZW_ERR_INF},
        {R(0.0), R(1.0), R(0.01), ZW_ERR_MASS},   {-R(0.0), R(1.0), R(0.01), ZW_ERR_MASS},
        {R(-1.0), R(1.0), R(0.01), ZW_ERR_MASS},  {R(1.0), R(1.0), R(0.0), ZW_ERR_PERIOD},
        {R(1.0), R(1.0), R(-0.01), ZW_ERR_PERIOD}, {R(1.0), R(-1.0), R(0.01), ZW_ERR_DAMPING},
        {R(1.0), -ZWT_TRUE_MIN, R(0.01), ZW_ERR_DAMPING},
        {ZWT_TRUE_MIN, R(1.0), R(0.01), ZW_ERR_RANGE}, {R(1.0), ZWT_TRUE_MIN, R(0.01), ZW_ERR_RANGE},
        {R(1.0), R(1.0), ZWT_TRUE_MIN, ZW_ERR_RANGE},
        {R(1.0), R(0.0), R(PREC(1e-200, 1e-25)), ZW_ERR_RANGE},  /* m / T^2 overflows */
        {R(PREC(1e-300, 1e-30)), R(0.0), R(1e10), ZW_ERR_RANGE}, /* m / T underflows */
        {R(1.0), ZW_REAL_MAX / R(2.0), R(10.0), ZW_ERR_RANGE},    /* delta overflows */
        {R(1.0), ZW_REAL_MIN, R(1e-3), ZW_ERR_RANGE},             /* delta subnormal */
        {R(1.0), ZW_REAL_MAX * R(0.75), R(1.0), ZW_ERR_RANGE},    /* hs = +inf */
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_device d = good_device(); /* an older, valid plant: must not survive */
        zw_verdict v = stable_verdict();
        zw_real kmax = BIG;
        zw_status st = zw_device_init(&d, cases[i].m, cases[i].b, cases[i].T);
        EXPECT_TRUE_MSG(st == cases[i].want, "case %zu: %s, expected %s", i, zw_status_name(st),
                        zw_status_name(cases[i].want));
        expect_nan_device(&d, "zw_device_init");
        /* and a caller that ignored the status is refused at the next call */
        EXPECT_STATUS(zw_device_check(&d, R(1.0), R(0.0), &v), ZW_ERR_NAN);
        expect_failsafe_verdict(&v, "check on a failed device");
        EXPECT_STATUS(zw_device_k_max(&d, R(0.0), &kmax), ZW_ERR_NAN);
        assert_true(kmax == R(0.0));
    }
    EXPECT_STATUS(zw_device_init(NULL, R(1.0), R(1.0), R(0.01)), ZW_ERR_NULL);
}

/* A device every call refuses. */
typedef struct bad_device {
    const char *what;
    zw_device d;
    zw_status want;
    bool hs_only; /* refused only by calls that use hs (checks, extremes, influence) */
} bad_device;

enum { N_BAD_DEVICES = 4 };

static void make_bad_devices(bad_device out[N_BAD_DEVICES])
{
    out[0].what = "failed zw_device_init";
    out[0].d = good_device();
    EXPECT_STATUS(zw_device_init(&out[0].d, R(-1.0), R(1.0), R(0.01)), ZW_ERR_MASS);
    out[0].want = ZW_ERR_NAN;
    out[0].hs_only = false;
    out[1].what = "delta_relerr < 0";
    out[1].d = good_device();
    out[1].d.co.delta_relerr = R(-1e-3);
    out[1].want = ZW_ERR_ARG;
    out[1].hs_only = false;
    out[2].what = "delta = +inf";
    out[2].d = good_device();
    out[2].d.co = zwt_coeffs((zw_real)INFINITY);
    out[2].want = ZW_ERR_INF;
    out[2].hs_only = false;
    out[3].what = "hs = +inf";
    out[3].d = good_device();
    out[3].d.co = zwt_coeffs(ZW_REAL_MAX);
    out[3].want = ZW_ERR_RANGE;
    out[3].hs_only = true;
}

static zw_device_extremes big_device_extremes(void)
{
    zw_device_extremes x;
    x.K_mmax = x.B_at_K_mmax = x.K_p_max = x.B_mmax = BIG;
    x.B_mmin = -BIG;
    x.K_mmin = R(0.0);
    x.at_corner = true;
    return x;
}

static void expect_zero_device_extremes(const zw_device_extremes *x, const char *what)
{
    EXPECT_TRUE_MSG(x->K_mmax == R(0.0) && x->B_at_K_mmax == R(0.0) && x->K_p_max == R(0.0) &&
                        x->B_mmax == R(0.0) && x->B_mmin == R(0.0) && x->K_mmin == R(0.0) &&
                        !x->at_corner,
                    "%s: device extremes not all 0", what);
}

static zw_influence big_influence(void)
{
    zw_influence f;
    f.delta = f.K_mmax = f.B_mmax = f.m_K1 = f.m_K2 = f.K_mmax_at_m_K2 = f.K_mmax_at_m_K1 = BIG;
    f.m_K_match = f.T_B = f.T_0 = f.m_0 = f.m_B = f.b_0 = f.b_BB = f.best_m_for_K = BIG;
    f.K_vs_m = f.K_vs_b = f.K_vs_T = f.B_vs_m = f.B_vs_b = f.B_vs_T = ZW_RISES;
    return f;
}

static void expect_failsafe_influence(const zw_influence *f, const char *what)
{
    const zw_real positions[] = {f->delta, f->m_K1, f->m_K2, f->m_K_match, f->T_B, f->T_0,
                                 f->m_0, f->m_B, f->b_0, f->b_BB, f->best_m_for_K};
    const zw_trend trends[] = {f->K_vs_m, f->K_vs_b, f->K_vs_T, f->B_vs_m, f->B_vs_b, f->B_vs_T};
    size_t i;
    EXPECT_TRUE_MSG(f->K_mmax == R(0.0) && f->B_mmax == R(0.0) && f->K_mmax_at_m_K2 == R(0.0) &&
                        f->K_mmax_at_m_K1 == R(0.0),
                    "%s: influence limits not 0", what);
    for (i = 0; i < ZWT_ARRAY_LEN(positions); ++i)
        EXPECT_TRUE_MSG(isnan(positions[i]), "%s: influence position %zu not NaN", what, i);
    for (i = 0; i < ZWT_ARRAY_LEN(trends); ++i)
        EXPECT_TRUE_MSG(trends[i] == ZW_TREND_UNKNOWN, "%s: trend %zu", what, i);
}

/* Every gain function of device.h at (K, B) (r = 1): status want.  hs_only: the plant is
 * refused only by the calls that use hs (the exact and legacy checks). */
static void expect_device_gain_errors(const zw_device *d, zw_real K, zw_real B, zw_status want,
                                      bool hs_only, const char *what)
{
    zw_verdict v;
    zw_real alpha = BIG, beta = BIG, rho = R(0.5), kmax = BIG, lo = -BIG, hi = BIG;
    bool within = true, ne = true;
    int r;
    v = stable_verdict();
    EXPECT_STATUS(zw_device_check(d, K, B, &v), want);
    expect_failsafe_verdict(&v, what);
    for (r = ZW_REGION_EXACT; r <= ZW_REGION_SMALL; ++r) {
        v = stable_verdict();
        if (hs_only && r != ZW_REGION_EXACT && r != ZW_REGION_LEGACY) continue;
        EXPECT_STATUS(zw_device_check_region((zw_region)r, d, K, B, &v), want);
        expect_failsafe_verdict(&v, what);
    }
    if (hs_only) return; /* the rest do not use hs */
    EXPECT_STATUS(zw_device_normalize(d, K, B, &alpha, &beta), want);
    EXPECT_TRUE_MSG(isnan(alpha) && isnan(beta), "%s: normalize", what);
    EXPECT_STATUS(zw_device_spectral_radius(d, K, B, &rho), want);
    EXPECT_TRUE_MSG(is_pos_inf(rho), "%s: rho", what);
    EXPECT_STATUS(zw_device_radius_within(d, K, B, R(1.0), &within), want);
    EXPECT_TRUE_MSG(!within, "%s: within", what);
    if (K == R(0.0)) { /* k_max reads only B */
        EXPECT_STATUS(zw_device_k_max(d, B, &kmax), want);
        EXPECT_TRUE_MSG(kmax == R(0.0), "%s: k_max", what);
    }
    if (B == R(0.0)) { /* b_range reads only K */
        EXPECT_STATUS(zw_device_b_range(d, K, &lo, &hi, &ne), want);
        EXPECT_TRUE_MSG(lo == R(0.0) && hi == R(0.0) && !ne, "%s: b_range", what);
    }
}

static void expect_device_plant_errors(const zw_device *d, zw_status want, const char *what)
{
    zw_device_extremes x = big_device_extremes();
    zw_influence f = big_influence();
    EXPECT_STATUS(zw_device_extremes_compute(d, &x), want);
    expect_zero_device_extremes(&x, what);
    EXPECT_STATUS(zw_device_influence(d, &f), want);
    expect_failsafe_influence(&f, what);
}

static void test_device_calls(void **state)
{
    bad_device bad[N_BAD_DEVICES];
    const zw_device d = good_device();
    zw_device zeroed;
    static const struct {
        zw_real r;
        zw_status want;
    } bad_r[] = {{(zw_real)NAN, ZW_ERR_NAN}, {R(0.0), ZW_ERR_ARG}, {R(-1.0), ZW_ERR_ARG},
                 {(zw_real)INFINITY, ZW_ERR_ARG}};
    zw_verdict v;
    zw_real a, b, lo, hi;
    bool w, ne;
    size_t i, k;
    (void)state;
    make_bad_devices(bad);
    memset(&zeroed, 0, sizeof zeroed);
    /* the gains are stable on the good device: only the error makes them not stable */
    EXPECT_OK(zw_device_check(&d, R(1.0), R(0.0), &v));
    assert_true(v.stable);
    for (i = 0; i < N_BAD_DEVICES; ++i) {
        expect_device_gain_errors(&bad[i].d, R(0.0), R(0.0), bad[i].want, bad[i].hs_only, bad[i].what);
        expect_device_gain_errors(&bad[i].d, R(1.0), R(0.0), bad[i].want, bad[i].hs_only, bad[i].what);
        expect_device_plant_errors(&bad[i].d, bad[i].want, bad[i].what);
    }
    expect_device_gain_errors(NULL, R(0.0), R(0.0), ZW_ERR_NULL, false, "d NULL");
    expect_device_plant_errors(NULL, ZW_ERR_NULL, "d NULL");
    /* a zeroed struct (never initialized): K / 0 is not finite */
    expect_device_gain_errors(&zeroed, R(1.0), R(0.0), ZW_ERR_RANGE, false, "zeroed device");
    for (i = 0; i < N_BAD_GAINS; ++i) {
        expect_device_gain_errors(&d, bad_gain(i), R(0.0), k_bad_gain_status[i], false, "bad K");
        expect_device_gain_errors(&d, R(0.0), bad_gain(i), k_bad_gain_status[i], false, "bad B");
    }
    /* normalized gains that overflow (k_scale = 0.25, b_scale = 0.005) */
    {
        const zw_device small = small_device();
        expect_device_gain_errors(&small, ZW_REAL_MAX, R(0.0), ZW_ERR_RANGE, false, "K overflow");
        expect_device_gain_errors(&small, R(0.0), -ZW_REAL_MAX, ZW_ERR_RANGE, false, "B overflow");
    }
    /* limits that overflow in real units: delta = 10, k_scale = max / 4, alpha_mmax > 4 */
    {
        zw_device huge;
        zw_real kmax = BIG;
        EXPECT_OK(zw_device_init(&huge, ZW_REAL_MAX / R(400.0), ZW_REAL_MAX / R(4.0), R(0.1)));
        expect_device_plant_errors(&huge, ZW_ERR_RANGE, "K_mmax overflow");
        EXPECT_STATUS(zw_device_k_max(&huge, R(0.0), &kmax), ZW_ERR_RANGE);
        assert_true(kmax == R(0.0));
    }
    for (i = 0; i < ZWT_ARRAY_LEN(bad_r); ++i) {
        w = true;
        EXPECT_STATUS(zw_device_radius_within(&d, R(1.0), R(0.0), bad_r[i].r, &w), bad_r[i].want);
        assert_false(w);
    }
    for (i = 0; i < 3; ++i) {
        const zw_region bad_region = (zw_region)(i == 0 ? -1 : i == 1 ? ZW_REGION_SMALL + 1 : 42);
        v = stable_verdict();
        EXPECT_STATUS(zw_device_check_region(bad_region, &d, R(1.0), R(0.0), &v), ZW_ERR_ARG);
        expect_failsafe_verdict(&v, "bad region");
    }
    /* each NULL output: the others still written */
    a = b = BIG;
    EXPECT_STATUS(zw_device_normalize(&d, R(1.0), R(0.0), NULL, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_normalize(&d, R(1.0), R(0.0), &a, NULL), ZW_ERR_NULL);
    assert_true(isnan(a) && isnan(b));
    for (k = 0; k < 3; ++k) {
        lo = -BIG;
        hi = BIG;
        ne = true;
        EXPECT_STATUS(zw_device_b_range(&d, R(1.0), k == 0 ? NULL : &lo, k == 1 ? NULL : &hi,
                                        k == 2 ? NULL : &ne),
                      ZW_ERR_NULL);
        assert_true((k == 0 || lo == R(0.0)) && (k == 1 || hi == R(0.0)) && (k == 2 || !ne));
    }
    EXPECT_STATUS(zw_device_check(&d, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_check_region(ZW_REGION_EXACT, &d, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_spectral_radius(&d, R(1.0), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_radius_within(&d, R(1.0), R(0.0), R(1.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_k_max(&d, R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_extremes_compute(&d, NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_influence(&d, NULL), ZW_ERR_NULL);
}

/* ---- batch.h ------------------------------------------------------------------------------- */

#define NP 8u

/* stable[0 .. NP-1] all false after a failed call that was handed all-true flags. */
static void expect_all_false(const bool *stable, const char *what)
{
    size_t i;
    for (i = 0; i < NP; ++i) EXPECT_TRUE_MSG(!stable[i], "%s: stable[%zu]", what, i);
}

static void fill_true(bool *stable)
{
    size_t i;
    for (i = 0; i < NP; ++i) stable[i] = true;
}

static void test_batch(void **state)
{
    bad_coeffs bad[N_BAD_COEFFS];
    bad_device badd[N_BAD_DEVICES];
    const zw_coeffs c = zwt_coeffs(R(1.0));
    const zw_device d = good_device();
    zw_real a[NP], b[NP], K[NP], B[NP];
    bool stable[NP];
    size_t i, k, fi;
    (void)state;
    make_bad_coeffs(bad);
    make_bad_devices(badd);
    for (i = 0; i < NP; ++i) {
        a[i] = R(0.1); /* every pair stable on c and, as K, B, on d */
        b[i] = R(0.0);
        K[i] = R(1.0);
        B[i] = R(0.0);
    }
    EXPECT_OK(zw_check_many(&c, NP, a, 1, b, 1, stable, NULL));
    for (i = 0; i < NP; ++i) assert_true(stable[i]);
    EXPECT_OK(zw_device_check_many(&d, NP, K, 1, B, 1, stable, NULL));
    for (i = 0; i < NP; ++i) assert_true(stable[i]);

    for (i = 0; i < N_BAD_COEFFS; ++i) {
        fill_true(stable);
        fi = 99;
        EXPECT_STATUS(zw_check_many(&bad[i].c, NP, a, 1, b, 1, stable, &fi), bad[i].want);
        expect_all_false(stable, bad[i].what);
        assert_true(fi == 0);
    }
    for (i = 0; i < N_BAD_DEVICES; ++i) {
        fill_true(stable);
        fi = 99;
        EXPECT_STATUS(zw_device_check_many(&badd[i].d, NP, K, 1, B, 1, stable, &fi), badd[i].want);
        expect_all_false(stable, badd[i].what);
        assert_true(fi == 0);
    }
    /* NULL plant or gains, the flags still written; first_invalid 0 */
    for (k = 0; k < 3; ++k) {
        fill_true(stable);
        fi = 99;
        EXPECT_STATUS(zw_check_many(k == 0 ? NULL : &c, NP, k == 1 ? NULL : a, 1, k == 2 ? NULL : b,
                                    1, stable, &fi),
                      ZW_ERR_NULL);
        expect_all_false(stable, "check_many NULL");
        assert_true(fi == 0);
        fill_true(stable);
        fi = 99;
        EXPECT_STATUS(zw_device_check_many(k == 0 ? NULL : &d, NP, k == 1 ? NULL : K, 1,
                                           k == 2 ? NULL : B, 1, stable, &fi),
                      ZW_ERR_NULL);
        expect_all_false(stable, "device_check_many NULL");
        assert_true(fi == 0);
    }
    fi = 99;
    EXPECT_STATUS(zw_check_many(&c, NP, a, 1, b, 1, NULL, &fi), ZW_ERR_NULL);
    assert_true(fi == 0);
    fi = 99;
    EXPECT_STATUS(zw_device_check_many(&d, NP, K, 1, B, 1, NULL, &fi), ZW_ERR_NULL);
    assert_true(fi == 0);
    /* one bad pair (last, so every earlier pair would be stable): every flag false */
    for (i = 0; i < N_BAD_GAINS; ++i) {
        for (k = 0; k < 2; ++k) {
            zw_real *x = k == 0 ? a : b, *X = k == 0 ? K : B;
            const zw_real keep = x[NP - 1], keepX = X[NP - 1];
            x[NP - 1] = bad_gain(i);
            X[NP - 1] = bad_gain(i);
            fill_true(stable);
            fi = 99;
            EXPECT_STATUS(zw_check_many(&c, NP, a, 1, b, 1, stable, &fi), k_bad_gain_status[i]);
            expect_all_false(stable, "bad pair");
            assert_true(fi == NP - 1);
            fill_true(stable);
            fi = 99;
            EXPECT_STATUS(zw_device_check_many(&d, NP, K, 1, B, 1, stable, &fi), k_bad_gain_status[i]);
            expect_all_false(stable, "bad device pair");
            assert_true(fi == NP - 1);
            x[NP - 1] = keep;
            X[NP - 1] = keepX;
        }
    }
    /* a gain whose normalized value overflows */
    {
        const zw_device small = small_device();
        K[NP - 1] = ZW_REAL_MAX;
        fill_true(stable);
        EXPECT_STATUS(zw_device_check_many(&small, NP, K, 1, B, 1, stable, NULL), ZW_ERR_RANGE);
    }
    expect_all_false(stable, "K overflow");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_coeffs),       cmocka_unit_test(test_region),
        cmocka_unit_test(test_margin),       cmocka_unit_test(test_extremes),
        cmocka_unit_test(test_device_init),  cmocka_unit_test(test_device_calls),
        cmocka_unit_test(test_batch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
