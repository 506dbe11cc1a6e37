/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Real units (paper Section IV, V): the paper's worked example to its printed digits,
 * the influence of m, b, T on K_mmax and B_mmax (Table 1, Fig. 21), every error path of
 * zw_device_init, and that real-unit verdicts agree with the normalized ones. */
#include "zw_test.h"

/* The paper's drive (Section V-B): Maxon EC-4pole 30 pair, load motor short-circuited or
 * open, inertia J1. */
#define J1 R(85.78e-7)        /* kg m^2 */
#define B_SHORT R(2.197e-3)   /* N m s/rad */
#define B_OPEN R(13.93e-6)    /* N m s/rad */

static zw_device device(zw_real m, zw_real b, zw_real T)
{
    zw_device d;
    memset(&d, 0, sizeof d);
    EXPECT_OK(zw_device_init(&d, m, b, T));
    return d;
}

static zw_device_extremes dext(const zw_device *d)
{
    zw_device_extremes x;
    memset(&x, 0, sizeof x);
    EXPECT_OK(zw_device_extremes_compute(d, &x));
    return x;
}

static zw_influence influence(const zw_device *d)
{
    zw_influence r;
    memset(&r, 0, sizeof r);
    EXPECT_OK(zw_device_influence(d, &r));
    return r;
}

static zw_verdict dcheck(const zw_device *d, zw_real K, zw_real B)
{
    zw_verdict v;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_device_check(d, K, B, &v));
    return v;
}

static zw_verdict dcheck_region(zw_region region, const zw_device *d, zw_real K, zw_real B)
{
    zw_verdict v;
    memset(&v, 0, sizeof v);
    EXPECT_OK(zw_device_check_region(region, d, K, B, &v));
    return v;
}

static zw_real extremes_beta_mmax(zw_real delta)
{
    zw_coeffs c = zwt_coeffs(delta);
    zw_extremes x;
    EXPECT_OK(zw_extremes_compute(&c, &x));
    return x.beta_mmax;
}

static zw_real kmax_of(zw_real m, zw_real b, zw_real T)
{
    zw_device d = device(m, b, T);
    return dext(&d).K_mmax;
}

static zw_real bmax_of(zw_real m, zw_real b, zw_real T)
{
    zw_device d = device(m, b, T);
    return dext(&d).B_mmax;
}

/* ---- the paper's numbers, to the printed digits ------------------------------------------ */

/* Section V-B-2 and V-B-4: T = 0.02 s, delta = 5.1224, K_mmax = 0.4934 N m/rad at
 * B = -1.357e-3 N m s/rad (the knob switch: "0.49 Nm/rad ... VD -1.36e-3"); the legacy
 * region's optimum 0.5806 N m/rad at B = 3.46e-5 is unstable. */
static void test_worked_example_T20ms(void **state)
{
    zw_device d = device(J1, B_SHORT, R(0.02));
    zw_device_extremes x = dext(&d);
    zw_real a1, b1;
    zw_verdict v;
    (void)state;
    EXPECT_ABS(d.co.delta, 5.1224L, 0.00005L);
    EXPECT_ABS(x.K_mmax, 0.4934L, 0.00005L);
    EXPECT_ABS(x.B_at_K_mmax, -1.357e-3L, 0.0005e-3L);
    assert_true(x.at_corner);
    EXPECT_ABS(x.B_mmin, -2.197e-3L, 1e-9L);
    assert_true(x.K_mmin == R(0.0));
    /* the legacy region's optimum, in real units */
    EXPECT_OK(zw_hyperbola_top(&d.co, &a1, &b1));
    EXPECT_ABS(a1 * d.k_scale, 0.5806L, 0.00005L);
    EXPECT_ABS(b1 * d.b_scale, 3.46e-5L, 0.005e-5L);
    /* just below it (0.58, the paper's knob-switch value): legacy stable, exact unstable
     * by the line alone */
    v = dcheck(&d, R(0.58), R(3.46e-5));
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_BOUND_LINE);
    assert_int_equal(v.violated, ZW_BOUND_LINE);
    assert_true(dcheck_region(ZW_REGION_LEGACY, &d, R(0.58), R(3.46e-5)).stable);
    /* at 0.5806 itself (a hair above the top, 0.58056) both curves are violated */
    assert_false(dcheck(&d, R(0.5806), R(3.46e-5)).stable);
    /* K_mmax is the boundary */
    assert_true(dcheck(&d, x.K_mmax * R(0.999), x.B_at_K_mmax).stable);
    assert_false(dcheck(&d, x.K_mmax * R(1.001), x.B_at_K_mmax).stable);
    /* the knob switch (Fig. 23): end stiffness 0.4 and peak 0.25 N m/rad at B = -1.36e-3
     * are stable; the legacy-based design (0.46 and 0.29 N m/rad at B = 0.03e-3) is stable
     * in the intermediate stiffness but its end stiffness is not (the wall oscillated). */
    assert_true(dcheck(&d, R(0.4), R(-1.36e-3)).stable);
    assert_true(dcheck(&d, R(0.25), R(-1.36e-3)).stable);
    assert_true(dcheck(&d, R(0.29), R(0.03e-3)).stable);
    v = dcheck(&d, R(0.46), R(0.03e-3));
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_BOUND_LINE);
    assert_true(dcheck_region(ZW_REGION_LEGACY, &d, R(0.46), R(0.03e-3)).stable);
}

/* Section V-B-4: reducing J to J'_K2 = 76.09e-7 raises K_mmax; raising J needs at least
 * 1943.5e-7 ("1943 x 10^-7") to match it.  J sits on the falling stretch. */
static void test_worked_example_inertia_advice(void **state)
{
    zw_device d = device(J1, B_SHORT, R(0.02));
    zw_influence r = influence(&d);
    zw_real k_now = dext(&d).K_mmax, k_at_k2, k_at_match;
    (void)state;
    EXPECT_ABS(r.m_K2, 76.09e-7L, 0.005e-7L);
    EXPECT_ABS(r.m_K_match, 1943.5e-7L, 0.05e-7L);
    assert_int_equal(r.K_vs_m, ZW_FALLS);
    assert_true(r.best_m_for_K == r.m_K2);
    assert_true(r.m_K2 < J1 && J1 < r.m_K1 && r.m_K1 < r.m_K_match);
    /* the critical inertias really are what they claim */
    k_at_k2 = kmax_of(r.m_K2, B_SHORT, R(0.02));
    k_at_match = kmax_of(r.m_K_match, B_SHORT, R(0.02));
    EXPECT_REL(k_at_k2, r.K_mmax_at_m_K2, TOLL(1000));
    EXPECT_REL(k_at_match, r.K_mmax_at_m_K2, TOLL(1000));
    EXPECT_REL(kmax_of(r.m_K1, B_SHORT, R(0.02)), r.K_mmax_at_m_K1, TOLL(1000));
    EXPECT_REL(r.K_mmax_at_m_K2, 4.508675168782248L * 2.197e-3L / 0.02L, TOLL(64));
    EXPECT_REL(r.K_mmax_at_m_K1, 2.637422468249545L * 2.197e-3L / 0.02L, TOLL(64));
    assert_true(k_at_k2 > k_now);
    assert_true(kmax_of(r.m_K2 * R(0.9), B_SHORT, R(0.02)) < k_at_k2);  /* "further reduction negatively impacts" */
    assert_true(kmax_of(r.m_K2 * R(1.1), B_SHORT, R(0.02)) < k_at_k2);
    assert_true(kmax_of(r.m_K_match * R(0.95), B_SHORT, R(0.02)) < k_at_k2);
    assert_true(kmax_of(r.m_K_match * R(1.05), B_SHORT, R(0.02)) > k_at_k2);
    EXPECT_REL(r.K_mmax, k_now, 0);
}

/* Section V-B-1/3: T = 0.008 s, delta = 2.049, J_K2 = 30.44e-7, J_K1 = 168.43e-7
 * (shared/notes/math.md; the paper's text prints 30.43 and 168.40), and Fig. 21: with the
 * load shorted K_mmax goes J1 > J2 > J3 < J4 (increase-decrease-increase), with it open
 * (J_K1 = 1.07e-7) it rises throughout. */
static void test_worked_example_T8ms(void **state)
{
    static const zw_real J[4] = {R(85.78e-7), R(102.29e-7), R(172.43e-7), R(283.21e-7)};
    zw_device d = device(J1, B_SHORT, R(0.008)), o = device(J1, B_OPEN, R(0.008));
    zw_influence r = influence(&d), ro = influence(&o);
    zw_real ks[4], ko[4];
    int i;
    (void)state;
    EXPECT_ABS(d.co.delta, 2.049L, 0.0005L);
    EXPECT_ABS(r.m_K2, 30.44e-7L, 0.005e-7L);
    EXPECT_ABS(r.m_K1, 168.43e-7L, 0.005e-7L);
    EXPECT_ABS(ro.m_K1, 1.07e-7L, 0.005e-7L);
    assert_int_equal(r.K_vs_m, ZW_FALLS);
    assert_int_equal(ro.K_vs_m, ZW_RISES);
    for (i = 0; i < 4; ++i) {
        ks[i] = kmax_of(J[i], B_SHORT, R(0.008));
        ko[i] = kmax_of(J[i], B_OPEN, R(0.008));
    }
    assert_true(ks[0] > ks[1] && ks[1] > ks[2] && ks[2] < ks[3]);
    assert_true(ko[0] < ko[1] && ko[1] < ko[2] && ko[2] < ko[3]);
}

/* Section V-B-1: load open, T = 0.008 s: delta = 0.01299 (paper: 0.013), K_mmax = 0.0943. */
static void test_worked_example_open_circuit(void **state)
{
    zw_device d = device(J1, B_OPEN, R(0.008));
    zw_device_extremes x = dext(&d);
    zw_influence r = influence(&d);
    (void)state;
    EXPECT_ABS(d.co.delta, 0.01299L, 0.000005L);
    EXPECT_ABS(x.K_mmax, 0.0943L, 0.00005L);
    assert_false(x.at_corner);
    assert_true(x.B_at_K_mmax > R(0.0));
    assert_int_equal(r.K_vs_m, ZW_RISES);
    assert_true(r.best_m_for_K == J1);
    /* Table 2, delta = 0.013: the experimental optimum alpha 0.656 at beta 0.826 is stable */
    assert_true(dcheck(&d, R(0.656) * d.k_scale, R(0.826) * d.b_scale).stable);
}

/* ---- influence: trends against finite differences, Table 1 ---------------------------- */

typedef enum { KMAX, BMAX } which_limit;
typedef enum { BY_M, BY_B, BY_T } which_param;

/* Sign of the change of K_mmax or B_mmax when one parameter grows by a factor 1 +- h. */
static zw_trend numeric_trend(zw_real m, zw_real b, zw_real T, which_limit lim, which_param p)
{
    const zw_real h = R(PREC(1e-4, 1e-2));
    zw_real lo_m = m, hi_m = m, lo_b = b, hi_b = b, lo_T = T, hi_T = T, lo, hi;
    if (p == BY_M) { lo_m = m * (R(1.0) - h); hi_m = m * (R(1.0) + h); }
    if (p == BY_B) { lo_b = b * (R(1.0) - h); hi_b = b * (R(1.0) + h); }
    if (p == BY_T) { lo_T = T * (R(1.0) - h); hi_T = T * (R(1.0) + h); }
    lo = lim == KMAX ? kmax_of(lo_m, lo_b, lo_T) : bmax_of(lo_m, lo_b, lo_T);
    hi = lim == KMAX ? kmax_of(hi_m, hi_b, hi_T) : bmax_of(hi_m, hi_b, hi_T);
    assert_true(ZW_FABS(hi - lo) > TOL(100) * ZW_FABS(hi)); /* resolvable */
    return hi > lo ? ZW_RISES : ZW_FALLS;
}

/* The stated intervals, whatever the plant (Section IV, Table 1). */
static void expect_intervals_consistent(const zw_device *d, const zw_influence *r)
{
    zw_real m = d->m, T = d->T;
    if (m < r->m_K2 || m > r->m_K1) assert_int_equal(r->K_vs_m, ZW_RISES);
    if (m > r->m_K2 && m < r->m_K1) assert_int_equal(r->K_vs_m, ZW_FALLS);
    if (T < r->T_B || T > r->T_0) assert_int_equal(r->B_vs_T, ZW_FALLS);
    if (T > r->T_B && T < r->T_0) assert_int_equal(r->B_vs_T, ZW_RISES);
    if (m < r->m_0 || m > r->m_B) assert_int_equal(r->B_vs_m, ZW_RISES);
    if (m > r->m_0 && m < r->m_B) assert_int_equal(r->B_vs_m, ZW_FALLS);
    if (d->b < r->b_0 || d->b > r->b_BB) assert_int_equal(r->B_vs_b, ZW_RISES);
    if (d->b > r->b_0 && d->b < r->b_BB) assert_int_equal(r->B_vs_b, ZW_FALLS);
    /* K_mmax always rises with b and falls with T (paper (33), (36)); B_mmax against b is
     * not monotonic (test_B_vs_b_increase_decrease_increase) */
    assert_int_equal(r->K_vs_b, ZW_RISES);
    assert_int_equal(r->K_vs_T, ZW_FALLS);
    assert_true(r->best_m_for_K == (r->K_vs_m == ZW_FALLS ? r->m_K2 : m));
}

static void test_influence_trends(void **state)
{
    static const zw_real ds[] = {R(0.013), R(0.5), R(1.4), R(2.0), R(3.0), R(5.1224), R(8.0), R(50.0)};
    const zw_real m = R(1.0), T = R(0.01);
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_real b = ds[k] * m / T;
        zw_device d = device(m, b, T);
        zw_influence r = influence(&d);
        long double bT = (long double)b * T;
        zw_device_extremes x = dext(&d);
        expect_intervals_consistent(&d, &r);
#define ZWT_TREND(field, lim, par)                                                               \
    do {                                                                                         \
        zw_trend seen = numeric_trend(m, b, T, lim, par);                                        \
        EXPECT_TRUE_MSG(r.field == seen, "delta %g: %s = %d but the finite difference says %d",  \
                        (double)ds[k], #field, (int)r.field, (int)seen);                         \
    } while (0)
        ZWT_TREND(K_vs_m, KMAX, BY_M);
        ZWT_TREND(K_vs_b, KMAX, BY_B);
        ZWT_TREND(K_vs_T, KMAX, BY_T);
        ZWT_TREND(B_vs_m, BMAX, BY_M);
        ZWT_TREND(B_vs_T, BMAX, BY_T);
        ZWT_TREND(B_vs_b, BMAX, BY_B);
#undef ZWT_TREND
        /* the critical values are their definitions */
        EXPECT_REL(r.delta, d.co.delta, 0);
        EXPECT_REL(r.m_K1, bT / (long double)ZW_DELTA_K1, TOLL(8));
        EXPECT_REL(r.m_K2, bT / (long double)ZW_DELTA_K2, TOLL(8));
        EXPECT_REL(r.m_K_match, bT / (long double)ZW_DELTA_KM, TOLL(8));
        EXPECT_REL(r.m_0, bT / (long double)ZW_DELTA0, TOLL(8));
        EXPECT_REL(r.m_B, bT / (long double)ZW_DELTA_B, TOLL(8));
        EXPECT_REL(r.T_B, (long double)m * ZW_DELTA_B / (long double)b, TOLL(8));
        EXPECT_REL(r.T_0, (long double)m * ZW_DELTA0 / (long double)b, TOLL(8));
        EXPECT_REL(r.b_0, (long double)m * ZW_DELTA0 / (long double)T, TOLL(8));
        EXPECT_REL(r.b_BB, (long double)m * ZW_DELTA_BB / (long double)T, TOLL(8));
        EXPECT_REL(r.K_mmax, x.K_mmax, 0);
        EXPECT_REL(r.B_mmax, x.B_mmax, 0);
    }
}

/* Table 1: B_mmax against T falls on (0, T_B), rises on (T_B, T_0), falls beyond; against m
 * rises on (0, m_0), falls on (m_0, m_B), rises beyond. */
static void test_table1_pattern(void **state)
{
    const zw_real m = R(1.0), b = R(10.0); /* Fig. 12: b = 10 N s/m, m = 1 kg */
    zw_device ref = device(m, b, R(0.01));
    zw_influence r = influence(&ref);
    /* factors that keep T_B f inside (0, T_0) and T_0 f inside (T_B, inf) */
    static const zw_real f_T[] = {R(0.85), R(0.93), R(1.07), R(1.15)};
    size_t i;
    (void)state;
    EXPECT_REL(r.T_B, 0.1793282132900761L, TOLL(8)); /* m delta_B / b */
    EXPECT_REL(r.T_0, 0.2310571356753694L, TOLL(8));
    for (i = 0; i < ZWT_ARRAY_LEN(f_T); ++i) {
        zw_real T_lo = r.T_B * f_T[i]; /* around T_B */
        zw_real T_hi = r.T_0 * f_T[i]; /* around T_0 */
        zw_device dl = device(m, b, T_lo), dh = device(m, b, T_hi);
        zw_influence il = influence(&dl), ih = influence(&dh);
        assert_int_equal(il.B_vs_T, f_T[i] < R(1.0) ? ZW_FALLS : ZW_RISES);
        assert_int_equal(ih.B_vs_T, f_T[i] < R(1.0) ? ZW_RISES : ZW_FALLS);
        assert_int_equal(il.B_vs_T, numeric_trend(m, b, T_lo, BMAX, BY_T));
        assert_int_equal(ih.B_vs_T, numeric_trend(m, b, T_hi, BMAX, BY_T));
        assert_int_equal(il.B_vs_m, (zw_trend)(-(int)il.B_vs_T));
        assert_int_equal(ih.B_vs_m, (zw_trend)(-(int)ih.B_vs_T));
    }
    {
        /* m, T fixed at 0.01 s: m_0 = b T / delta0, m_B = b T / delta_B */
        static const zw_real f_m[] = {R(0.85), R(0.93), R(1.07), R(1.15)};
        zw_real m_0 = r.m_0, m_B = r.m_B;
        EXPECT_REL(m_0, 0.1L / 2.310571356753694L, TOLL(8));
        EXPECT_REL(m_B, 0.1L / 1.793282132900761L, TOLL(8));
        for (i = 0; i < ZWT_ARRAY_LEN(f_m); ++i) {
            zw_device a = device(m_0 * f_m[i], b, R(0.01)), c = device(m_B * f_m[i], b, R(0.01));
            assert_int_equal(influence(&a).B_vs_m, f_m[i] < R(1.0) ? ZW_RISES : ZW_FALLS);
            assert_int_equal(influence(&c).B_vs_m, f_m[i] < R(1.0) ? ZW_FALLS : ZW_RISES);
            assert_int_equal(influence(&a).B_vs_m, numeric_trend(m_0 * f_m[i], b, R(0.01), BMAX, BY_M));
            assert_int_equal(influence(&c).B_vs_m, numeric_trend(m_B * f_m[i], b, R(0.01), BMAX, BY_M));
        }
    }
    /* B_mmax(T -> inf) -> b ("no more than the PD"); B_mmax at delta_B, delta0 */
    EXPECT_REL(bmax_of(m, b, R(1e5)), 10.0L, 3e-5L); /* delta = 1e6 */
    EXPECT_REL(bmax_of(m, b, r.T_B), 3.350918871511673L * 10.0L, TOLL(1000));
    EXPECT_REL(bmax_of(m, b, r.T_0), 3.440519785624598L * 10.0L, TOLL(1000));
}

/* B_mmax against b (m, T fixed) has the shape of beta_mmax against delta (paper eq (42),
 * Fig. 10(a), Fig. 12(a)): beta_mmax = min{2/c2, 2 (1 + e)/d12} rises up to delta0, then
 * "decreases a little bit" (the line's crossing 2 (1 + e)/d12 falls until its minimum near
 * delta = 3.2122), then rises again: the "increase-decrease-increase" influence of b on the
 * mmax-VD that the abstract and the conclusion state. */
static void test_B_vs_b_increase_decrease_increase(void **state)
{
    static const struct {
        zw_real delta;
        zw_trend want;
    } cases[] = {{R(0.5), ZW_RISES}, {R(2.0), ZW_RISES}, {R(2.6), ZW_FALLS},
                 {R(3.0), ZW_FALLS}, {R(4.0), ZW_RISES}, {R(20.0), ZW_RISES}};
    const zw_real m = R(1.0), T = R(0.01);
    size_t i;
    (void)state;
    /* the maths first: beta_mmax(delta) at 2.3106 (delta0) > at 3 < at 4 */
    assert_true(extremes_beta_mmax(ZW_DELTA0) > extremes_beta_mmax(R(3.0)));
    assert_true(extremes_beta_mmax(R(3.0)) < extremes_beta_mmax(R(4.0)));
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_real b = cases[i].delta * m / T;
        zw_device d = device(m, b, T);
        zw_influence r = influence(&d);
        zw_trend seen = numeric_trend(m, b, T, BMAX, BY_B);
        EXPECT_TRUE_MSG(seen == cases[i].want, "delta %g: B_mmax(b) numerically %d, expected %d",
                        (double)cases[i].delta, (int)seen, (int)cases[i].want);
        EXPECT_TRUE_MSG(r.B_vs_b == cases[i].want,
                        "delta %g: zw_device_influence says B_vs_b = %d, B_mmax(b) %s",
                        (double)cases[i].delta, (int)r.B_vs_b,
                        cases[i].want == ZW_RISES ? "rises" : "falls");
    }
}

/* b = 0: delta = 0 for every m and T, no turning points: K_mmax = (m/T^2)(12 - 8 sqrt 2)
 * rises with m, B_mmax = 2 m / T falls with T and rises with m. */
static void test_influence_zero_damping(void **state)
{
    zw_device d = device(R(0.1), R(0.0), R(0.01));
    zw_influence r = influence(&d);
    zw_device_extremes x = dext(&d);
    (void)state;
    assert_true(d.co.delta == R(0.0));
    EXPECT_REL(x.K_mmax, (12.0L - 8.0L * sqrtl(2.0L)) * 0.1L / 1e-4L, TOLL(64));
    EXPECT_REL(x.B_mmax, 2.0L * 0.1L / 0.01L, TOLL(16));
    assert_true(x.K_p_max == R(0.0));
    assert_int_equal(r.K_vs_m, ZW_RISES);
    assert_int_equal(r.B_vs_T, ZW_FALLS);
    assert_int_equal(r.B_vs_m, ZW_RISES);
    assert_true(isinf(r.T_B) && r.T_B > R(0.0));
    assert_true(isinf(r.T_0) && r.T_0 > R(0.0));
    assert_true(r.best_m_for_K == d.m);
    expect_intervals_consistent(&d, &r);
}

/* ---- zw_device_init errors ---------------------------------------------------------------- */

/* b T overflowing while delta = b T / m is an ordinary number is a valid plant (review
 * finding: it used to be refused with ZW_ERR_RANGE). */
static void test_init_large_b_and_T(void **state)
{
    zw_device d;
    (void)state;
    EXPECT_OK(zw_device_init(&d, R(PREC(1e300, 1e30)), R(PREC(1e200, 1e20)), R(PREC(1e110, 1e19))));
    assert_true(d.co.delta > R(PREC(9.9e9, 9.9e8)) && d.co.delta < R(PREC(1.01e10, 1.01e9)));
}

/* Review finding S1: b T underflowing to a subnormal while delta is normal gave a delta
 * off by 30 % and a false "stable".  delta is now b (T / m), accurate here, and the
 * reviewer's points (exact spectral radius > 1) are not called stable. */
static void test_init_tiny_b_times_T(void **state)
{
    zw_device d;
    zw_verdict v;
    const zw_real m = R(PREC(1e-290, 2e-38)), b = R(PREC(1.014070351758794e-160, 1e-30));
    const zw_real T = R(PREC(1e-160, 1e-15));
    const zw_real K = R(PREC(1e-40, 3.9728529e-17));
    const zw_real B = R(PREC(-1.0141935613354365e-160, -1.3812335e-30));
    const long double want_delta = (long double)b * (long double)T / (long double)m;
    (void)state;
    EXPECT_OK(zw_device_init(&d, m, b, T));
    assert_true(fabsl((long double)d.co.delta - want_delta) <= 8.0L * (long double)ZW_UNIT_ROUNDOFF * want_delta);
    EXPECT_OK(zw_device_check(&d, K, B, &v));
    assert_false(v.stable);
}

static void test_init_errors(void **state)
{
    const zw_real nan = (zw_real)NAN, inf = (zw_real)INFINITY;
    const struct {
        zw_real m, b, T;
        zw_status want;
        const char *what;
    } cases[] = {
        {nan, R(1.0), R(0.01), ZW_ERR_NAN, "m NaN"},
        {R(1.0), nan, R(0.01), ZW_ERR_NAN, "b NaN"},
        {R(1.0), R(1.0), nan, ZW_ERR_NAN, "T NaN"},
        {inf, R(1.0), R(0.01), ZW_ERR_INF, "m inf"},
        {-inf, R(1.0), R(0.01), ZW_ERR_INF, "m -inf"},
        {R(1.0), inf, R(0.01), ZW_ERR_INF, "b inf"},
        {R(1.0), R(1.0), inf, ZW_ERR_INF, "T inf"},
        {R(1.0), R(1.0), -inf, ZW_ERR_INF, "T -inf"},
        {R(0.0), R(1.0), R(0.01), ZW_ERR_MASS, "m 0"},
        {-R(0.0), R(1.0), R(0.01), ZW_ERR_MASS, "m -0"},
        {R(-1.0), R(1.0), R(0.01), ZW_ERR_MASS, "m < 0"},
        {-ZWT_TRUE_MIN, R(1.0), R(0.01), ZW_ERR_MASS, "m tiny < 0"},
        {R(1.0), R(1.0), R(0.0), ZW_ERR_PERIOD, "T 0"},
        {R(1.0), R(1.0), R(-0.01), ZW_ERR_PERIOD, "T < 0"},
        {R(1.0), R(-1.0), R(0.01), ZW_ERR_DAMPING, "b < 0"},
        {R(1.0), -ZWT_TRUE_MIN, R(0.01), ZW_ERR_DAMPING, "b tiny < 0"},
        /* m / T overflows */
        {ZW_REAL_MAX / R(2.0), R(0.0), R(1e-3), ZW_ERR_RANGE, "m/T overflow"},
        /* m / T^2 overflows */
        {R(1.0), R(0.0), R(PREC(1e-200, 1e-25)), ZW_ERR_RANGE, "m/T^2 overflow"},
        /* m / T underflows (not a normal number) */
        {R(PREC(1e-300, 1e-30)), R(0.0), R(1e10), ZW_ERR_RANGE, "m/T underflow"},
        /* m / T^2 underflows */
        {R(PREC(1e-290, 1e-25)), R(0.0), R(PREC(1e10, 1e7)), ZW_ERR_RANGE, "m/T^2 underflow"},
        /* b T overflows: delta infinite */
        {R(1.0), ZW_REAL_MAX / R(2.0), R(10.0), ZW_ERR_RANGE, "delta overflow"},
        /* b T / m underflows: delta subnormal */
        {R(1.0), ZW_REAL_MIN, R(1e-3), ZW_ERR_RANGE, "delta underflow"},
        /* delta finite but beyond max/2: hs infinite */
        {R(1.0), ZW_REAL_MAX * R(0.75), R(1.0), ZW_ERR_RANGE, "delta > max/2"},
        /* subnormal inputs carry unbounded relative error (review finding S1: a subnormal
         * b*T once gave delta 2.0 for a true 1.52 and a false "stable") */
        {ZWT_TRUE_MIN, R(1.0), R(0.01), ZW_ERR_RANGE, "m subnormal"},
        {R(1.0), ZWT_TRUE_MIN, R(0.01), ZW_ERR_RANGE, "b subnormal"},
        {R(1.0), R(1.0), ZWT_TRUE_MIN, ZW_ERR_RANGE, "T subnormal"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(cases); ++i) {
        zw_device out = device(J1, B_SHORT, R(0.02)); /* a valid plant must not survive */
        zw_status st;
        st = zw_device_init(&out, cases[i].m, cases[i].b, cases[i].T);
        EXPECT_TRUE_MSG(st == cases[i].want, "%s: got %s, expected %s", cases[i].what,
                        zw_status_name(st), zw_status_name(cases[i].want));
        EXPECT_TRUE_MSG(isnan(out.m) && isnan(out.b) && isnan(out.T) && isnan(out.k_scale) &&
                            isnan(out.b_scale) && zwt_all_nan_coeffs(&out.co),
                        "%s: device not NaN on error", cases[i].what);
    }
    EXPECT_STATUS(zw_device_init(NULL, R(1.0), R(1.0), R(0.01)), ZW_ERR_NULL);
    {
        /* b = 0 and b = -0 are fine (no damping) */
        zw_device d = device(R(1.0), -R(0.0), R(0.01));
        assert_true(d.co.delta == R(0.0));
    }
}

/* The ranges of shared/notes/math.md: m in [1e-8, 1e3], T in [1e-6, 1], K up to 1e9 and
 * beyond: every plant initializes, and its K_mmax is alpha_mmax m / T^2 and is the
 * boundary of zw_device_check. */
static void test_wide_ranges(void **state)
{
    static const zw_real ms[] = {R(1e-8), R(1e-3), R(1.0), R(1e3)};
    static const zw_real Ts[] = {R(1e-6), R(1e-3), R(1.0)};
    static const zw_real deltas[] = {R(0.013), R(2.0), R(50.0)};
    size_t i, j, k;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ms); ++i)
        for (j = 0; j < ZWT_ARRAY_LEN(Ts); ++j)
            for (k = 0; k < ZWT_ARRAY_LEN(deltas); ++k) {
                zw_real m = ms[i], T = Ts[j], b = deltas[k] * m / T;
                zw_device d = device(m, b, T);
                zw_device_extremes x = dext(&d);
                zw_coeffs c = zwt_coeffs(d.co.delta);
                zw_extremes xn;
                EXPECT_OK(zw_extremes_compute(&c, &xn));
                EXPECT_REL(d.co.delta, deltas[k], TOLL(8));
                EXPECT_REL(x.K_mmax, (long double)xn.alpha_mmax * m / ((long double)T * T), TOLL(8));
                EXPECT_REL(x.B_mmax, (long double)xn.beta_mmax * m / T, TOLL(8));
                assert_true(dcheck(&d, x.K_mmax * R(0.999), x.B_at_K_mmax).stable);
                assert_false(dcheck(&d, x.K_mmax * R(1.001), x.B_at_K_mmax).stable);
            }
}

/* ---- real-unit verdicts against normalized ones ------------------------------------------ */

/* Away from the boundary (all neighbours agree, none marginal), zw_device_check says what
 * zw_check says at alpha = K T^2/m, beta = B T/m; spectral radius and Jury test likewise. */
static void test_device_matches_normalized(void **state)
{
    static const zw_real plants[][3] = {
        {R(85.78e-7), R(2.197e-3), R(0.02)},
        {R(85.78e-7), R(2.197e-3), R(0.008)},
        {R(85.78e-7), R(13.93e-6), R(0.008)},
        {R(1.0), R(10.0), R(0.01)},
        {R(0.1), R(50.0), R(0.01)},
        {R(0.1), R(0.0), R(0.01)},
    };
    static const zw_region regions[] = {ZW_REGION_EXACT, ZW_REGION_LEGACY, ZW_REGION_PASSIVITY,
                                        ZW_REGION_DELTA_INF};
    const zw_real eps = R(PREC(1e-9, 1e-4));
    size_t p, q;
    (void)state;
    for (p = 0; p < ZWT_ARRAY_LEN(plants); ++p) {
        zw_real m = plants[p][0], b = plants[p][1], T = plants[p][2];
        zw_device d = device(m, b, T);
        zw_device_extremes x = dext(&d);
        zw_coeffs c = zwt_coeffs((zw_real)((long double)b * T / m));
        int i, j, n = 30, compared = 0;
        EXPECT_REL(d.k_scale, (long double)m / ((long double)T * T), TOLL(4));
        EXPECT_REL(d.b_scale, (long double)m / T, TOLL(2));
        for (i = 0; i <= n; ++i) {
            for (j = 0; j <= n; ++j) {
                zw_real K = x.K_mmax * (R(-0.1) + R(1.4) * (zw_real)i / (zw_real)n);
                zw_real B = -R(1.3) * b - R(0.1) * x.B_mmax +
                            (R(1.3) * (x.B_mmax + b)) * (zw_real)j / (zw_real)n;
                zw_real alpha = (zw_real)((long double)K * T * T / m);
                zw_real beta = (zw_real)((long double)B * T / m);
                zw_real an, bn, rho_d, rho_n;
                bool wd = false, wn = false;
                EXPECT_OK(zw_device_normalize(&d, K, B, &an, &bn));
                EXPECT_NEAR(an, alpha, ZW_REAL_MIN, TOLL(6));
                EXPECT_NEAR(bn, beta, ZW_REAL_MIN, TOLL(4));
                for (q = 0; q < ZWT_ARRAY_LEN(regions); ++q) {
                    zw_verdict vd = dcheck_region(regions[q], &d, K, B), v[5];
                    int s, agree = 1;
                    EXPECT_OK(zw_check_region(regions[q], &c, alpha, beta, &v[0]));
                    EXPECT_OK(zw_check_region(regions[q], &c, alpha * (R(1.0) + eps), beta, &v[1]));
                    EXPECT_OK(zw_check_region(regions[q], &c, alpha * (R(1.0) - eps), beta, &v[2]));
                    EXPECT_OK(zw_check_region(regions[q], &c, alpha, beta + eps * (ZW_FABS(beta) + c.delta + R(1.0)), &v[3]));
                    EXPECT_OK(zw_check_region(regions[q], &c, alpha, beta - eps * (ZW_FABS(beta) + c.delta + R(1.0)), &v[4]));
                    for (s = 1; s < 5; ++s)
                        if (!zwt_same_verdict(&v[s], &v[0])) agree = 0;
                    if (!agree || v[0].marginal) continue;
                    ++compared;
                    EXPECT_TRUE_MSG(vd.stable == v[0].stable && vd.deciding == v[0].deciding,
                                    "plant %zu region %d K %g B %g: device %d/%d, normalized %d/%d", p,
                                    (int)regions[q], (double)K, (double)B, vd.stable, (int)vd.deciding,
                                    v[0].stable, (int)v[0].deciding);
                }
                EXPECT_OK(zw_device_spectral_radius(&d, K, B, &rho_d));
                EXPECT_OK(zw_spectral_radius(&d.co, an, bn, &rho_n));
                assert_true(rho_d == rho_n);
                EXPECT_OK(zw_device_radius_within(&d, K, B, R(1.0), &wd));
                EXPECT_OK(zw_radius_within(&c, alpha, beta, R(1.0), &wn));
                if (wd) assert_true(rho_d < R(1.0) + R(1e-6));
                if (rho_d < R(1.0) - R(PREC(1e-6, 1e-3))) assert_true(wd && wn);
            }
        }
        assert_true(compared > 1000);
    }
}

/* K_max(B) and the B range at K in real units: the normalized answers, scaled, and the
 * boundary of zw_device_check. */
static void test_device_kmax_and_b_range(void **state)
{
    zw_device d = device(J1, B_SHORT, R(0.02));
    zw_device_extremes x = dext(&d);
    static const zw_real fB[] = {R(-0.9), R(-0.5), R(0.0), R(0.5), R(0.9)};
    static const zw_real fK[] = {R(0.05), R(0.5), R(0.95)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(fB); ++i) {
        zw_real B = fB[i] < R(0.0) ? -fB[i] * x.B_mmin : fB[i] * x.B_mmax;
        zw_real K = R(-1.0), am, alpha0, beta;
        EXPECT_OK(zw_device_normalize(&d, R(0.0), B, &alpha0, &beta));
        EXPECT_REL(beta, (long double)B * d.T / d.m, TOLL(4));
        EXPECT_OK(zw_device_k_max(&d, B, &K));
        EXPECT_OK(zw_alpha_max(&d.co, beta, &am));
        EXPECT_REL(K, (long double)am * d.k_scale, TOLL(2));
        assert_true(K > R(0.0));
        assert_true(dcheck(&d, K - R(1e-3) * x.K_mmax, B).stable);
        assert_false(dcheck(&d, K + R(1e-3) * x.K_mmax, B).stable);
    }
    for (i = 0; i < ZWT_ARRAY_LEN(fK); ++i) {
        zw_real K = fK[i] * x.K_mmax, lo = R(7.0), hi = R(7.0), step;
        bool ne = false;
        EXPECT_OK(zw_device_b_range(&d, K, &lo, &hi, &ne));
        assert_true(ne);
        assert_true(lo < x.B_at_K_mmax && x.B_at_K_mmax < hi);
        step = R(1e-3) * (hi - lo);
        assert_true(dcheck(&d, K, lo + step).stable);
        assert_false(dcheck(&d, K, lo - step).stable);
        assert_true(dcheck(&d, K, hi - step).stable);
        assert_false(dcheck(&d, K, hi + step).stable);
    }
    {
        zw_real K = R(9.0), lo = R(7.0), hi = R(7.0);
        bool ne = true;
        EXPECT_OK(zw_device_k_max(&d, -R(2.0) * d.b, &K)); /* B below -b: nothing stable */
        assert_true(K == R(0.0));
        EXPECT_OK(zw_device_b_range(&d, x.K_mmax * R(1.01), &lo, &hi, &ne));
        assert_false(ne);
    }
}

static void test_device_call_errors(void **state)
{
    zw_device d = device(J1, B_SHORT, R(0.02));
    zw_verdict v;
    zw_real a = R(7.0), b = R(7.0), rho = R(7.0);
    bool w = true;
    zw_device_extremes x;
    zw_influence r;
    (void)state;
    memset(&v, ZWT_SENTINEL, sizeof v);
    EXPECT_STATUS(zw_device_check(NULL, R(0.1), R(0.0), &v), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_check(&d, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_check(&d, (zw_real)NAN, R(0.0), &v), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_check(&d, R(0.1), (zw_real)NAN, &v), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_check(&d, (zw_real)INFINITY, R(0.0), &v), ZW_ERR_INF);
    EXPECT_STATUS(zw_device_check(&d, R(0.1), -(zw_real)INFINITY, &v), ZW_ERR_INF);
    /* K / k_scale overflows (k_scale = 0.0214) */
    EXPECT_STATUS(zw_device_check(&d, ZW_REAL_MAX, R(0.0), &v), ZW_ERR_RANGE);
    EXPECT_STATUS(zw_device_check_region((zw_region)99, &d, R(0.1), R(0.0), &v), ZW_ERR_ARG);
    assert_true(zwt_failsafe_verdict(&v)); /* each call's outputs: test_failsafe.c */
    EXPECT_STATUS(zw_device_normalize(&d, ZW_REAL_MAX, R(0.0), &a, &b), ZW_ERR_RANGE);
    EXPECT_STATUS(zw_device_normalize(&d, R(0.1), (zw_real)NAN, &a, &b), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_normalize(NULL, R(0.1), R(0.0), &a, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_normalize(&d, R(0.1), R(0.0), NULL, &b), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_normalize(&d, R(0.1), R(0.0), &a, NULL), ZW_ERR_NULL);
    assert_true(isnan(a) && isnan(b));
    EXPECT_STATUS(zw_device_spectral_radius(&d, (zw_real)NAN, R(0.0), &rho), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_spectral_radius(NULL, R(0.1), R(0.0), &rho), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_spectral_radius(&d, R(0.1), R(0.0), NULL), ZW_ERR_NULL);
    assert_true(isinf(rho) && rho > R(0.0));
    EXPECT_STATUS(zw_device_radius_within(&d, R(0.1), R(0.0), R(0.0), &w), ZW_ERR_ARG);
    EXPECT_STATUS(zw_device_radius_within(&d, R(0.1), R(0.0), (zw_real)NAN, &w), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_radius_within(&d, (zw_real)INFINITY, R(0.0), R(1.0), &w), ZW_ERR_INF);
    EXPECT_STATUS(zw_device_radius_within(NULL, R(0.1), R(0.0), R(1.0), &w), ZW_ERR_NULL);
    assert_false(w);
    memset(&x, ZWT_SENTINEL, sizeof x);
    EXPECT_STATUS(zw_device_extremes_compute(NULL, &x), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_extremes_compute(&d, NULL), ZW_ERR_NULL);
    assert_true(x.K_mmax == R(0.0) && x.B_mmax == R(0.0) && !x.at_corner);
    memset(&r, ZWT_SENTINEL, sizeof r);
    EXPECT_STATUS(zw_device_influence(NULL, &r), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_influence(&d, NULL), ZW_ERR_NULL);
    assert_true(r.K_mmax == R(0.0) && r.B_mmax == R(0.0) && r.K_vs_m == ZW_TREND_UNKNOWN);
    a = R(7.0);
    EXPECT_STATUS(zw_device_k_max(&d, (zw_real)NAN, &a), ZW_ERR_NAN);
    EXPECT_STATUS(zw_device_k_max(&d, R(0.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_k_max(NULL, R(0.0), &a), ZW_ERR_NULL);
    assert_true(a == R(0.0));
    a = b = R(7.0);
    w = true;
    EXPECT_STATUS(zw_device_b_range(&d, (zw_real)INFINITY, &a, &b, &w), ZW_ERR_INF);
    EXPECT_STATUS(zw_device_b_range(NULL, R(0.1), &a, &b, &w), ZW_ERR_NULL);
    EXPECT_STATUS(zw_device_b_range(&d, R(0.1), NULL, &b, &w), ZW_ERR_NULL);
    assert_true(a == R(0.0) && b == R(0.0) && !w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_worked_example_T20ms),
        cmocka_unit_test(test_worked_example_inertia_advice),
        cmocka_unit_test(test_worked_example_T8ms),
        cmocka_unit_test(test_worked_example_open_circuit),
        cmocka_unit_test(test_influence_trends),
        cmocka_unit_test(test_table1_pattern),
        cmocka_unit_test(test_B_vs_b_increase_decrease_increase),
        cmocka_unit_test(test_influence_zero_damping),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_wide_ranges),
        cmocka_unit_test(test_device_matches_normalized),
        cmocka_unit_test(test_device_kmax_and_b_range),
        cmocka_unit_test(test_device_call_errors),
        cmocka_unit_test(test_init_large_b_and_T),
        cmocka_unit_test(test_init_tiny_b_times_T),
    };
    printf("zwidth C tests: device (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("device_" ZW_REAL_NAME, tests, NULL, NULL);
}
