/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The general loop (loop.h): delay, low-pass, moving average, Tustin.  References here are
 * the note's closed formula (shared/notes/general-loop.md) and the paper's cubic, written
 * out in long double from zwt_reference; the independent state-space construction at 50
 * digits is tests/py/test_loop_reference.py. */
#include "zw_test.h"

/* The checks' scratch (loop.h): static, as a drive keeps it; tests run one at a time. */
static zw_loop_workspace g_ws;

static zw_loop_spec spec_of(unsigned d, zw_differentiator diff, zw_velocity_filter filt, zw_real a,
                            unsigned n)
{
    zw_loop_spec s;
    memset(&s, 0, sizeof s);
    s.delay = d;
    s.differentiator = diff;
    s.filter = filt;
    s.filter_pole = a;
    s.average = n;
    return s;
}

static zw_loop *new_loop(zw_real delta, const zw_loop_spec *spec)
{
    static zw_loop loop; /* large: not on cmocka's stack */
    zw_coeffs c = zwt_coeffs(delta);
    EXPECT_OK(zw_loop_init(&loop, &c, spec));
    return &loop;
}

/* ---- polynomial multiplication in long double ---------------------------------------- */

/* r = p * q (highest power first), degrees dp, dq. */
static void lmul(const long double *p, unsigned dp, const long double *q, unsigned dq, long double *r)
{
    unsigned i, j;
    for (i = 0; i <= dp + dq; ++i) r[i] = 0.0L;
    for (i = 0; i <= dp; ++i)
        for (j = 0; j <= dq; ++j) r[i + j] += p[i] * q[j];
}

/* The note's formula for delay d and the first-order filter a (backward difference):
 *   2 z^d (z - 1)(z - e)(z - a) + (c1 z + c2)(alpha (z - a) + beta (1 - a)(z - 1)). */
static unsigned note_lowpass_poly(zw_real delta, unsigned d, long double a, long double alpha,
                                  long double beta, long double *p)
{
    zwt_ref r = zwt_reference(delta);
    long double base[4] = {1.0L, -(1.0L + r.e) - a, r.e + a * (1.0L + r.e), -a * r.e}; /* (z-1)(z-e)(z-a) */
    long double plant[2] = {r.c1, r.c2};
    long double ctl[2] = {alpha + beta * (1.0L - a), -alpha * a - beta * (1.0L - a)};
    long double nb[3];
    unsigned n = d + 3u, i;
    for (i = 0; i <= n; ++i) p[i] = 0.0L;
    for (i = 0; i < 4; ++i) p[i] = 2.0L * base[i];
    lmul(plant, 1, ctl, 1, nb); /* degree 2, at the bottom */
    for (i = 0; i < 3; ++i) p[n - 2u + i] += nb[i];
    return n;
}

static void expect_poly_near(const zw_loop *loop, zw_real alpha, zw_real beta, const long double *ref,
                             unsigned n)
{
    zw_real p[ZW_LOOP_MAX_DEGREE + 1u];
    unsigned deg = 99u, i;
    long double scale = 0.0L;
    EXPECT_OK(zw_loop_poly(loop, alpha, beta, p, &deg));
    assert_int_equal(deg, n);
    for (i = 0; i <= n; ++i) scale += fabsl(ref[i]);
    for (i = 0; i <= n; ++i) EXPECT_ABS(p[i], ref[i], TOLL(64) * scale + ZW_REAL_MIN);
    /* the parts' bounds hold against the reference */
    for (i = 0; i <= n; ++i) {
        long double bound = loop->D_err[i] + fabsl((long double)alpha) * loop->Na_err[i] +
                            fabsl((long double)beta) * loop->Nb_err[i];
        long double got = (long double)loop->D[i] + (long double)alpha * loop->Na[i] +
                          (long double)beta * loop->Nb[i];
        EXPECT_TRUE_MSG(fabsl(got - ref[i]) <= bound * (1.0L + TOLL(8)) + TOLL(4) * fabsl(ref[i]),
                        "coef %u: |%.20Lg - %.20Lg| > %.3Lg", i, got, ref[i], bound);
    }
}

static void test_note_formula_lowpass(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-6), R(0.013), R(1.0), R(5.1224), R(1e3)};
    static const zw_real as[] = {R(0.0), R(0.3), R(0.8), R(0.999)};
    static const zw_real ab[][2] = {{R(0.0), R(0.0)}, {R(0.7), R(-0.2)}, {R(3.0), R(2.5)}};
    size_t k, j, i;
    unsigned d;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k)
        for (d = 0; d <= ZW_LOOP_MAX_DELAY; d += 2u)
            for (j = 0; j < ZWT_ARRAY_LEN(as); ++j)
                for (i = 0; i < ZWT_ARRAY_LEN(ab); ++i) {
                    long double ref[ZW_LOOP_MAX_DEGREE + 1u];
                    zw_loop_spec s = spec_of(d, ZW_DIFF_BACKWARD,
                                             as[j] == R(0.0) ? ZW_VFILTER_NONE : ZW_VFILTER_LOWPASS,
                                             as[j], 0u);
                    const zw_loop *loop = new_loop(ds[k], &s);
                    unsigned n = note_lowpass_poly(ds[k], d, as[j], ab[i][0], ab[i][1], ref);
                    expect_poly_near(loop, ab[i][0], ab[i][1], ref, n);
                }
}

/* d = 0, backward: z times the paper's cubic (zw_char_poly). */
static void test_ideal_is_paper_cubic(void **state)
{
    static const zw_real ds[] = {R(0.0), R(0.013), R(2.049), R(20.0)};
    size_t k;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_loop_spec s = spec_of(0u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
        const zw_loop *loop = new_loop(ds[k], &s);
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_real cubic[4], p[ZW_LOOP_MAX_DEGREE + 1u];
        unsigned deg, i;
        EXPECT_OK(zw_char_poly(&c, R(1.5), R(0.25), cubic));
        EXPECT_OK(zw_loop_poly(loop, R(1.5), R(0.25), p, &deg));
        assert_int_equal(deg, 3);
        for (i = 0; i < 4; ++i) EXPECT_ABS(p[i], cubic[i], TOL(16) * 8);
    }
}

/* The bilinear parts are (1 - s)^n p((1 + s)/(1 - s)) of the z parts, at a few s. */
static void test_bilinear_parts(void **state)
{
    static const zw_loop_spec specs[] = {
        {0u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, 0, 0u},   {3u, ZW_DIFF_TUSTIN, ZW_VFILTER_NONE, 0, 0u},
        {1u, ZW_DIFF_BACKWARD, ZW_VFILTER_LOWPASS, R(0.8), 0u},
        {2u, ZW_DIFF_TUSTIN, ZW_VFILTER_LOWPASS, R(0.3), 0u},
        {8u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, 0, 16u}, {5u, ZW_DIFF_TUSTIN, ZW_VFILTER_AVERAGE, 0, 7u}};
    static const long double ss[] = {-0.7L, 0.1L, 0.45L};
    size_t k, j;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(specs); ++k) {
        const zw_loop *loop = new_loop(R(0.5), &specs[k]);
        const unsigned n = loop->degree;
        for (j = 0; j < ZWT_ARRAY_LEN(ss); ++j) {
            long double s = ss[j], z = (1.0L + s) / (1.0L - s), f = powl(1.0L - s, (long double)n);
            long double zs[3] = {0, 0, 0}, ss_[3] = {0, 0, 0}, mag = 0.0L;
            unsigned i;
            for (i = 0; i <= n; ++i) {
                zs[0] = zs[0] * z + loop->D[i];
                zs[1] = zs[1] * z + loop->Na[i];
                zs[2] = zs[2] * z + loop->Nb[i];
                ss_[0] = ss_[0] * s + loop->Ds[i];
                ss_[1] = ss_[1] * s + loop->Nas[i];
                ss_[2] = ss_[2] * s + loop->Nbs[i];
                mag = mag * fabsl(s) + fabsl(loop->Ds[i]) + fabsl(loop->Nas[i]) + fabsl(loop->Nbs[i]);
            }
            for (i = 0; i < 3; ++i) EXPECT_ABS(zs[i] * f, ss_[i], TOLL(256) * mag * 4);
        }
    }
}

/* Each kind's degree and the velocity estimate's gain: Nv(1)/Dv(1)... p(1) = alpha Na(1). */
static void test_degrees(void **state)
{
    zw_loop_spec s;
    (void)state;
    s = spec_of(0u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
    assert_int_equal(new_loop(R(1.0), &s)->degree, 3);
    s = spec_of(8u, ZW_DIFF_TUSTIN, ZW_VFILTER_NONE, R(0.0), 0u);
    assert_int_equal(new_loop(R(1.0), &s)->degree, 11);
    s = spec_of(2u, ZW_DIFF_TUSTIN, ZW_VFILTER_LOWPASS, R(0.5), 0u);
    assert_int_equal(new_loop(R(1.0), &s)->degree, 6);
    s = spec_of(8u, ZW_DIFF_TUSTIN, ZW_VFILTER_AVERAGE, R(0.0), 16u);
    assert_int_equal(new_loop(R(1.0), &s)->degree, ZW_LOOP_MAX_DEGREE - 1u); /* the ideal plant: no lag */
}

/* ---- errors and fail-safe outputs --------------------------------------------------------- */

static void test_lowpass_pole(void **state)
{
    zw_real a = R(7.0);
    (void)state;
    EXPECT_OK(zw_loop_lowpass_pole(R(100.0), R(1e-3), &a));
    EXPECT_REL(a, expl(-2.0L * 3.14159265358979323846L * 0.1L), TOL(8));
    EXPECT_STATUS(zw_loop_lowpass_pole(R(0.0), R(1e-3), &a), ZW_ERR_FILTER);
    assert_true(a == R(0.0));
    a = R(7.0);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(-1.0), R(1e-3), &a), ZW_ERR_FILTER);
    assert_true(a == R(0.0));
    /* T = 2^-10 s exactly: Nyquist at 512 Hz */
    EXPECT_STATUS(zw_loop_lowpass_pole(R(512.0), R(0.0009765625), &a), ZW_ERR_FILTER);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(1e30), R(0.0009765625), &a), ZW_ERR_FILTER);
    EXPECT_OK(zw_loop_lowpass_pole(ZWT_DOWN(R(512.0)), R(0.0009765625), &a));
    EXPECT_REL(a, expl(-3.14159265358979323846L * (long double)ZWT_DOWN(R(512.0)) / 512.0L), TOL(8));
    EXPECT_STATUS(zw_loop_lowpass_pole(R(1e-30), R(1e-3), &a), ZW_ERR_FILTER); /* a rounds to 1 */
    EXPECT_STATUS(zw_loop_lowpass_pole((zw_real)NAN, R(1e-3), &a), ZW_ERR_NAN);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(10.0), (zw_real)NAN, &a), ZW_ERR_NAN);
    EXPECT_STATUS(zw_loop_lowpass_pole((zw_real)INFINITY, R(1e-3), &a), ZW_ERR_INF);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(10.0), R(0.0), &a), ZW_ERR_PERIOD);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(10.0), R(-1.0), &a), ZW_ERR_PERIOD);
    EXPECT_STATUS(zw_loop_lowpass_pole(R(10.0), R(1e-3), NULL), ZW_ERR_NULL);
}

static void expect_init_error(const zw_coeffs *c, const zw_loop_spec *s, zw_status want)
{
    static zw_loop loop;
    zw_real p[ZW_LOOP_MAX_DEGREE + 1u];
    unsigned deg = 5u;
    memset(&loop, ZWT_SENTINEL, sizeof loop);
    EXPECT_STATUS(zw_loop_init(&loop, c, s), want);
    assert_int_equal(loop.degree, 0);
    EXPECT_STATUS(zw_loop_poly(&loop, R(1.0), R(0.0), p, &deg), ZW_ERR_ARG);
    assert_int_equal(deg, 0);
}

static void test_init_errors(void **state)
{
    zw_coeffs c = zwt_coeffs(R(1.0)), bad;
    zw_loop_spec s;
    (void)state;
    s = spec_of(9u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
    expect_init_error(&c, &s, ZW_ERR_DELAY);
    s = spec_of(0u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, R(0.0), 0u);
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s.average = 17u;
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s = spec_of(0u, ZW_DIFF_BACKWARD, ZW_VFILTER_LOWPASS, R(-0.1), 0u);
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s.filter_pole = R(1.0);
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s.filter_pole = (zw_real)INFINITY;
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s.filter_pole = (zw_real)NAN;
    expect_init_error(&c, &s, ZW_ERR_NAN);
    s = spec_of(0u, (zw_differentiator)7, ZW_VFILTER_NONE, R(0.0), 0u);
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s = spec_of(0u, ZW_DIFF_BACKWARD, (zw_velocity_filter)3, R(0.0), 0u);
    expect_init_error(&c, &s, ZW_ERR_FILTER);
    s = spec_of(0u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
    expect_init_error(NULL, &s, ZW_ERR_NULL);
    expect_init_error(&c, NULL, ZW_ERR_NULL);
    bad = c;
    bad.delta = (zw_real)NAN;
    expect_init_error(&bad, &s, ZW_ERR_NAN);
    bad.delta = (zw_real)INFINITY;
    expect_init_error(&bad, &s, ZW_ERR_INF);
    bad = c;
    bad.delta_relerr = R(-1.0);
    expect_init_error(&bad, &s, ZW_ERR_ARG);
    EXPECT_STATUS(zw_loop_init(NULL, &c, &s), ZW_ERR_NULL);
}

static void test_poly_errors(void **state)
{
    zw_loop_spec s = spec_of(1u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
    const zw_loop *loop = new_loop(R(1.0), &s);
    static zw_loop zeroed;
    zw_real p[ZW_LOOP_MAX_DEGREE + 1u];
    unsigned deg = 5u;
    (void)state;
    EXPECT_STATUS(zw_loop_poly(loop, (zw_real)NAN, R(0.0), p, &deg), ZW_ERR_NAN);
    assert_int_equal(deg, 0);
    assert_true(p[0] == R(0.0));
    EXPECT_STATUS(zw_loop_poly(loop, R(0.0), (zw_real)INFINITY, p, &deg), ZW_ERR_INF);
    EXPECT_STATUS(zw_loop_poly(loop, ZW_REAL_MAX, ZW_REAL_MAX, p, &deg), ZW_ERR_RANGE);
    assert_true(p[0] == R(0.0) && deg == 0u);
    EXPECT_STATUS(zw_loop_poly(NULL, R(1.0), R(0.0), p, &deg), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_poly(loop, R(1.0), R(0.0), NULL, &deg), ZW_ERR_NULL);
    assert_int_equal(deg, 0);
    EXPECT_STATUS(zw_loop_poly(&zeroed, R(1.0), R(0.0), p, &deg), ZW_ERR_ARG);
}


/* ---- verdicts --------------------------------------------------------------------------- */

#include <complex.h>

/* max |root| of p (degree n, highest first) by Durand-Kerner in long double complex. */
static long double dk_radius(const zw_real *p, unsigned n, long double *angle)
{
    long double complex z[ZW_LOOP_MAX_DEGREE];
    long double scale = 0.0L, best = -1.0L;
    unsigned i, j, it, m = n;
    while (m > 0u && p[m] == R(0.0)) --m;
    *angle = 0.0L;
    if (m == 0u) return 0.0L;
    for (i = 1; i <= m; ++i)
        if (powl(fabsl((long double)p[i] / p[0]), 1.0L / i) > scale) scale = powl(fabsl((long double)p[i] / p[0]), 1.0L / i);
    for (i = 0; i < m; ++i) z[i] = scale * cexpl(I * (6.283185307179586L * i / m + 0.4L));
    for (it = 0; it < 3000; ++it) {
        long double change = 0.0L;
        for (i = 0; i < m; ++i) {
            long double complex num = 0.0L, den = (long double)p[0], step;
            for (j = 0; j <= m; ++j) num = num * z[i] + (long double)p[j];
            for (j = 0; j < m; ++j)
                if (j != i) den *= z[i] - z[j];
            step = num / den;
            z[i] -= step;
            if (cabsl(step) > change) change = cabsl(step);
        }
        if (change <= 8.0L * LDBL_EPSILON * scale) break;
    }
    for (i = 0; i < m; ++i)
        if (cabsl(z[i]) > best) {
            best = cabsl(z[i]);
            *angle = fabsl(cargl(z[i]));
        }
    return best;
}

static void fail_safe_verdict(const zw_loop_verdict *v)
{
    assert_false(v->stable);
    assert_false(v->marginal);
    assert_int_equal(v->deciding, ZW_LOOP_BOUNDARY_NONE);
    assert_true(v->theta == R(0.0));
}

static void test_check_errors(void **state)
{
    zw_loop_spec s = spec_of(2u, ZW_DIFF_TUSTIN, ZW_VFILTER_NONE, R(0.0), 0u);
    const zw_loop *loop = new_loop(R(1.0), &s);
    static zw_loop zeroed, garbage;
    zw_loop_verdict v;
    zw_real rho = R(0.0), theta = R(3.0);
    bool within = true;
    (void)state;
    memset(&garbage, ZWT_SENTINEL, sizeof garbage);
#define CHECK_FAILS(l, a, b, want)                                                                 \
    do {                                                                                         \
        memset(&v, ZWT_SENTINEL, sizeof v);                                                      \
        EXPECT_STATUS(zw_loop_check((l), &g_ws, (a), (b), &v), (want));                                  \
        fail_safe_verdict(&v);                                                                   \
        within = true;                                                                           \
        EXPECT_STATUS(zw_loop_radius_within((l), &g_ws, (a), (b), R(1.0), &within), (want));             \
        assert_false(within);                                                                    \
        within = true;                                                                           \
        EXPECT_STATUS(zw_loop_is_stable((l), &g_ws, (a), (b), &within), (want));                         \
        assert_false(within);                                                                    \
        rho = R(0.0);                                                                            \
        EXPECT_STATUS(zw_loop_spectral_radius((l), &g_ws, (a), (b), &rho, &theta), (want));              \
        assert_true(rho == (zw_real)INFINITY);                                                   \
    } while (0)
    CHECK_FAILS(loop, (zw_real)NAN, R(0.1), ZW_ERR_NAN);
    CHECK_FAILS(loop, R(0.1), (zw_real)NAN, ZW_ERR_NAN);
    CHECK_FAILS(loop, (zw_real)INFINITY, R(0.1), ZW_ERR_INF);
    CHECK_FAILS(loop, R(0.1), -(zw_real)INFINITY, ZW_ERR_INF);
    CHECK_FAILS(NULL, R(0.1), R(0.1), ZW_ERR_NULL);
    CHECK_FAILS(&zeroed, R(0.1), R(0.1), ZW_ERR_ARG);
    CHECK_FAILS(&garbage, R(0.1), R(0.1), ZW_ERR_ARG);
#undef CHECK_FAILS
    EXPECT_STATUS(zw_loop_check(loop, &g_ws, R(0.1), R(0.1), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_is_stable(loop, &g_ws, R(0.1), R(0.1), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_radius_within(loop, &g_ws, R(0.1), R(0.1), R(1.0), NULL), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_radius_within(loop, &g_ws, R(0.1), R(0.1), R(0.0), &within), ZW_ERR_ARG);
    assert_false(within);
    within = true;
    EXPECT_STATUS(zw_loop_radius_within(loop, &g_ws, R(0.1), R(0.1), R(-1.0), &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_loop_radius_within(loop, &g_ws, R(0.1), R(0.1), (zw_real)INFINITY, &within), ZW_ERR_ARG);
    EXPECT_STATUS(zw_loop_radius_within(loop, &g_ws, R(0.1), R(0.1), (zw_real)NAN, &within), ZW_ERR_NAN);
    assert_false(within);
    EXPECT_STATUS(zw_loop_spectral_radius(loop, &g_ws, R(0.1), R(0.1), NULL, &theta), ZW_ERR_NULL);
    EXPECT_STATUS(zw_loop_spectral_radius(loop, &g_ws, R(0.1), R(0.1), &rho, NULL), ZW_ERR_NULL);
    assert_true(rho == (zw_real)INFINITY);
}

/* The ideal loop through the general path gives zw_check's verdicts outside both bands, in
 * every form that reduces to it (backward d = 0, low-pass a = 0, average n = 1), and the
 * deciding boundary matches the closed form's constraint. */
static void test_ideal_matches_closed_form(void **state)
{
    static const zw_real ds[] = {R(0.0), R(1e-6), R(0.013), R(1.0), R(2.049), R(5.1224), R(20.0), R(1e3)};
    static const zw_loop_spec specs[] = {{0u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u},
                                         {0u, ZW_DIFF_BACKWARD, ZW_VFILTER_LOWPASS, R(0.0), 0u},
                                         {0u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, R(0.0), 1u}};
    size_t k, j;
    unsigned seed = 12345u, compared = 0u, marginal = 0u, i;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(ds); ++k) {
        zw_coeffs c = zwt_coeffs(ds[k]);
        zw_extremes x;
        EXPECT_OK(zw_extremes_compute(&c, &x));
        for (j = 0; j < ZWT_ARRAY_LEN(specs); ++j) {
            const zw_loop *loop = new_loop(ds[k], &specs[j]);
            for (i = 0; i < 1500u; ++i) {
                zw_verdict ref;
                zw_loop_verdict v;
                zw_real a, b;
                seed = seed * 1103515245u + 12345u;
                a = (zw_real)((double)(seed >> 8) / 16777216.0 * 1.3 - 0.1) * x.alpha_mmax;
                seed = seed * 1103515245u + 12345u;
                b = (zw_real)((double)(seed >> 8) / 16777216.0) * (x.beta_mmax + ds[k] + R(0.5)) - ds[k] - R(0.25);
                EXPECT_OK(zw_check(&c, a, b, &ref));
                EXPECT_OK(zw_loop_check(loop, &g_ws, a, b, &v));
                {
                    bool fast = !v.stable;
                    EXPECT_OK(zw_loop_is_stable(loop, &g_ws, a, b, &fast));
                    assert_true(fast == v.stable); /* the fast path: the same verdict */
                }
                if (ref.marginal || v.marginal) {
                    marginal++;
                    assert_false(v.stable && !ref.stable && !ref.marginal);
                    continue;
                }
                compared++;
                EXPECT_TRUE_MSG(v.stable == ref.stable, "delta %g alpha %.17g beta %.17g: loop %d, closed form %d",
                                (double)ds[k], (double)a, (double)b, v.stable, ref.stable);
                if (!v.stable && ref.deciding == ZW_BOUND_STIFFNESS)
                    assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_Z_PLUS1);
                if (!v.stable && ref.violated == ZW_BOUND_LINE)
                    assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_Z_MINUS1);
                /* beyond the hyperbola alone, the largest root is a complex pair or (two
                 * real roots past -1, the sign of p(-1) unchanged) real */
                if (!v.stable) assert_true(v.deciding != ZW_LOOP_BOUNDARY_NONE);
                if (v.deciding == ZW_LOOP_BOUNDARY_COMPLEX)
                    assert_true(v.theta > R(0.0) && v.theta < R(3.1415927));
                else
                    assert_true(v.theta == R(0.0));
                if (v.stable) assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_NONE);
            }
        }
    }
    assert_true(compared > 30000u);
    EXPECT_TRUE_MSG(marginal * 200u < compared, "%u marginal of %u", marginal, compared);
}

/* Every kind at random points: "stable" only when the long double roots are inside, and
 * the spectral radius and the radius test agree with those roots. */
static void test_verdicts_against_roots(void **state)
{
    static const zw_loop_spec specs[] = {
        {1u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u},   {8u, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u},
        {2u, ZW_DIFF_TUSTIN, ZW_VFILTER_NONE, R(0.0), 0u},     {1u, ZW_DIFF_BACKWARD, ZW_VFILTER_LOWPASS, R(0.8), 0u},
        {3u, ZW_DIFF_TUSTIN, ZW_VFILTER_LOWPASS, R(0.999), 0u}, {2u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, R(0.0), 5u},
        {8u, ZW_DIFF_TUSTIN, ZW_VFILTER_AVERAGE, R(0.0), 15u}, {8u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, R(0.0), 16u}};
    static const zw_real ds[] = {R(1e-3), R(0.5), R(5.0)};
    size_t k, j;
    unsigned seed = 777u, i, stable = 0u, unstable = 0u, radius_checked = 0u, radius_proved = 0u;
    (void)state;
    for (k = 0; k < ZWT_ARRAY_LEN(specs); ++k)
        for (j = 0; j < ZWT_ARRAY_LEN(ds); ++j) {
            const zw_loop *loop = new_loop(ds[j], &specs[k]);
            for (i = 0; i < 60u; ++i) {
                zw_real p[ZW_LOOP_MAX_DEGREE + 1u], rho, theta, a, b;
                long double ref, ang;
                unsigned deg;
                zw_loop_verdict v;
                bool within;
                seed = seed * 1103515245u + 12345u;
                a = (zw_real)((double)(seed >> 8) / 16777216.0) * R(0.3) * (ds[j] + R(0.05));
                seed = seed * 1103515245u + 12345u;
                b = (zw_real)((double)(seed >> 8) / 16777216.0) * R(1.5) - R(0.5) * ds[j];
                EXPECT_OK(zw_loop_poly(loop, a, b, p, &deg));
                ref = dk_radius(p, deg, &ang);
                EXPECT_OK(zw_loop_check(loop, &g_ws, a, b, &v));
                EXPECT_OK(zw_loop_spectral_radius(loop, &g_ws, a, b, &rho, &theta));
                EXPECT_OK(zw_loop_radius_within(loop, &g_ws, a, b, R(1.0), &within));
                if (fabsl(ref - 1.0L) < 1e-3L) continue; /* the polynomial's own rounding */
                EXPECT_TRUE_MSG(v.stable == (ref < 1.0L), "spec %zu delta %g a %.9g b %.9g: rho %.12Lg, verdict %d",
                                k, (double)ds[j], (double)a, (double)b, ref, v.stable);
                assert_true(within == v.stable);
                EXPECT_OK(zw_loop_is_stable(loop, &g_ws, a, b, &within));
                assert_true(within == (ref < 1.0L)); /* the fast path, against the roots */
                EXPECT_REL(rho, ref, PREC(1e-9, 3e-3));
                {   /* |z| < r for other radii: never claimed when rho >= r, and not vacuous */
                    static const zw_real rs[] = {R(0.8), R(0.95), R(1.25)};
                    size_t q;
                    for (q = 0; q < ZWT_ARRAY_LEN(rs); ++q) {
                        EXPECT_OK(zw_loop_radius_within(loop, &g_ws, a, b, rs[q], &within));
                        if (fabsl(ref - rs[q]) < 1e-3L) continue;
                        if (within) EXPECT_TRUE_MSG(ref < rs[q], "rho %.12Lg, r %g", ref, (double)rs[q]);
                        radius_checked++;
                        radius_proved += (ref < rs[q]) == within ? 1u : 0u;
                    }
                }
                if (v.stable) stable++;
                else unstable++;
            }
        }
    assert_true(stable > 100u && unstable > 100u);
    /* the radius test decides at least 90 % of the points off its band */
    EXPECT_TRUE_MSG(radius_proved * 10u >= radius_checked * 9u, "%u of %u", radius_proved, radius_checked);
}

/* Hand-derivable boundaries: z = 1 is alpha = 0 whatever the loop (p(1) = alpha Na(1));
 * with Tustin z = -1 is beta = 0 (p(-1) = beta Nb(-1)); both decided by the gain's exact
 * sign down to tiny gains, not marginal. */
static void test_exact_real_boundaries(void **state)
{
    zw_loop_spec s = spec_of(2u, ZW_DIFF_BACKWARD, ZW_VFILTER_LOWPASS, R(0.5), 0u);
    const zw_loop *loop = new_loop(R(0.5), &s);
    zw_loop_verdict v;
    (void)state;
    EXPECT_OK(zw_loop_check(loop, &g_ws, R(-1e-30), R(0.1), &v));
    assert_false(v.stable);
    assert_false(v.marginal);
    assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_Z_PLUS1);
    EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.0), R(0.1), &v));
    assert_false(v.stable);
    assert_int_equal(v.deciding, ZW_LOOP_BOUNDARY_Z_PLUS1);
    EXPECT_OK(zw_loop_check(loop, &g_ws, R(1e-6), R(0.1), &v));
    assert_true(v.stable);
    /* Tustin, d = 0, delta = 0.5: the side of beta = 0 that is stable, by its roots */
    s = spec_of(0u, ZW_DIFF_TUSTIN, ZW_VFILTER_NONE, R(0.0), 0u);
    loop = new_loop(R(0.5), &s);
    {
        zw_loop_verdict pos, neg;
        EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.05), R(1e-25), &pos));
        EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.05), R(-1e-25), &neg));
        assert_true(pos.stable != neg.stable);
        assert_false(pos.marginal || neg.marginal);
        assert_int_equal((pos.stable ? neg : pos).deciding, ZW_LOOP_BOUNDARY_Z_MINUS1);
        EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.05), R(0.0), &v));
        assert_false(v.stable); /* a root exactly at -1 */
    }
    /* Tustin with an even-length average: the Tustin mode (-1)^k averages out of the
     * estimate, so z = -1 is a root for every gain: never stable */
    s = spec_of(1u, ZW_DIFF_TUSTIN, ZW_VFILTER_AVERAGE, R(0.0), 4u);
    loop = new_loop(R(0.5), &s);
    EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.01), R(0.2), &v));
    assert_false(v.stable);
}

/* Known approximation (sanity only): small delta and beta, delay d:
 * alpha_max ~ (delta + beta) / (1/2 + d). */
static void test_small_delta_approximation(void **state)
{
    unsigned d;
    (void)state;
    for (d = 0u; d <= ZW_LOOP_MAX_DELAY; ++d) {
        zw_loop_spec s = spec_of(d, ZW_DIFF_BACKWARD, ZW_VFILTER_NONE, R(0.0), 0u);
        const zw_loop *loop = new_loop(R(1e-4), &s);
        zw_real approx = R(2e-4) / (R(0.5) + (zw_real)d);
        zw_loop_verdict v;
        EXPECT_OK(zw_loop_check(loop, &g_ws, R(0.9) * approx, R(1e-4), &v));
        assert_true(v.stable);
        EXPECT_OK(zw_loop_check(loop, &g_ws, R(1.1) * approx, R(1e-4), &v));
        assert_false(v.stable);
        assert_false(v.marginal);
    }
}

/* The workspace (loop.h): NULL is refused with fail-safe outputs, and its contents never
 * matter: a workspace full of garbage (NaN patterns, another loop's leftovers) gives the same
 * verdicts, bit for bit, as a zeroed one, on points of every path (Routh, Schur-Cohn, the
 * root test near the boundary). */
static void test_workspace(void **state)
{
    static zw_loop_workspace zeroed, garbage;
    zw_loop_spec s = spec_of(8u, ZW_DIFF_BACKWARD, ZW_VFILTER_AVERAGE, R(0.0), 16u);
    const zw_loop *loop = new_loop(R(0.5), &s);
    zw_loop_verdict v, w;
    zw_real rho = R(0.0), theta = R(1.0), rho2, theta2;
    bool b = true, b2;
    unsigned i, j;
    (void)state;
    memset(&v, ZWT_SENTINEL, sizeof v);
    EXPECT_STATUS(zw_loop_check(loop, NULL, R(0.01), R(0.1), &v), ZW_ERR_NULL);
    fail_safe_verdict(&v);
    EXPECT_STATUS(zw_loop_is_stable(loop, NULL, R(0.01), R(0.1), &b), ZW_ERR_NULL);
    assert_false(b);
    b = true;
    EXPECT_STATUS(zw_loop_radius_within(loop, NULL, R(0.01), R(0.1), R(1.0), &b), ZW_ERR_NULL);
    assert_false(b);
    EXPECT_STATUS(zw_loop_spectral_radius(loop, NULL, R(0.01), R(0.1), &rho, &theta), ZW_ERR_NULL);
    assert_true(rho == (zw_real)INFINITY);
    assert_true(theta == R(0.0));
    for (i = 0u; i < 40u; ++i) {
        /* alpha from 0 to past the limit, beta across the stable range: every path */
        const zw_real alpha = R(0.004) * (zw_real)i, beta = R(-0.4) + R(0.05) * (zw_real)(i % 20u);
        for (j = 0u; j < 2u; ++j) {
            memset(&zeroed, 0, sizeof zeroed);
            memset(&garbage, j == 0u ? 0xFF : ZWT_SENTINEL, sizeof garbage); /* NaN / junk */
            EXPECT_OK(zw_loop_check(loop, &zeroed, alpha, beta, &v));
            EXPECT_OK(zw_loop_check(loop, &garbage, alpha, beta, &w));
            assert_int_equal(v.stable, w.stable);
            assert_int_equal(v.marginal, w.marginal);
            assert_int_equal(v.deciding, w.deciding);
            assert_true(v.theta == w.theta);
            EXPECT_OK(zw_loop_is_stable(loop, &garbage, alpha, beta, &b));
            assert_int_equal(b, v.stable);
            EXPECT_OK(zw_loop_radius_within(loop, &zeroed, alpha, beta, R(1.0), &b));
            EXPECT_OK(zw_loop_radius_within(loop, &garbage, alpha, beta, R(1.0), &b2));
            assert_int_equal(b, b2);
            EXPECT_OK(zw_loop_spectral_radius(loop, &zeroed, alpha, beta, &rho, &theta));
            EXPECT_OK(zw_loop_spectral_radius(loop, &garbage, alpha, beta, &rho2, &theta2));
            assert_true(rho == rho2 && theta == theta2);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_note_formula_lowpass),
        cmocka_unit_test(test_workspace),
        cmocka_unit_test(test_ideal_is_paper_cubic),
        cmocka_unit_test(test_bilinear_parts),
        cmocka_unit_test(test_degrees),
        cmocka_unit_test(test_lowpass_pole),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_poly_errors),
        cmocka_unit_test(test_check_errors),
        cmocka_unit_test(test_ideal_matches_closed_form),
        cmocka_unit_test(test_verdicts_against_roots),
        cmocka_unit_test(test_exact_real_boundaries),
        cmocka_unit_test(test_small_delta_approximation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
