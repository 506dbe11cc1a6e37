/* The general loop (loop.h): delay, low-pass, moving average, Tustin.  References here are
 * the note's closed formula (shared/notes/general-loop.md) and the paper's cubic, written
 * out in long double from zwt_reference; the independent state-space construction at 50
 * digits is tests/py/test_loop_reference.py. */
#include "zw_test.h"

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
    assert_int_equal(new_loop(R(1.0), &s)->degree, ZW_LOOP_MAX_DEGREE);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_note_formula_lowpass),
        cmocka_unit_test(test_ideal_is_paper_cubic),
        cmocka_unit_test(test_bilinear_parts),
        cmocka_unit_test(test_degrees),
        cmocka_unit_test(test_lowpass_pole),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_poly_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
