/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The sampled plant (plant.h).  References: the ideal plant from zwt_reference (long double,
 * the paper's series), the stiff plant from the augmented matrix exponential
 * expm([[A, b], [0, 0]]) in long double (Taylor series with scaling and squaring), and the
 * coefficients from det(zI - Phi) and C adj(zI - Phi) Gamma.  The 50-digit check over the
 * whole parameter range and the hard cases is tests/py/test_plant_ref.py. */
#include "zw_test.h"

static zw_plant_spec spec_of(zw_real delta, zw_real kappa, zw_real lambda)
{
    zw_plant_spec s;
    memset(&s, 0, sizeof s);
    s.delta = delta;
    s.kappa = kappa;
    s.lambda = lambda;
    return s;
}

static zw_plant plant_of(zw_real delta, zw_real kappa)
{
    zw_plant p;
    zw_plant_spec s = spec_of(delta, kappa, R(0.0));
    memset(&p, ZWT_SENTINEL, sizeof p);
    EXPECT_OK(zw_plant_init(&p, &s));
    assert_int_equal(p.order, 2);
    return p;
}

/* ---- long double reference ----------------------------------------------------------- */

typedef struct lref {
    long double den[3], num[2], den_s[3], num_s[2], den_w[3];
} lref;

/* e^M for an n x n matrix (n <= 4), Taylor on M / 2^k (norm <= 1/4), then k squarings. */
static void expmn(unsigned n, long double M[4][4], long double E[4][4])
{
    long double S[4][4], T[4][4], P[4][4], norm = 0.0L;
    unsigned i, j, l;
    int t, k = 0;
    for (i = 0; i < n; ++i)
        for (j = 0; j < n; ++j) norm = fmaxl(norm, fabsl(M[i][j]));
    while ((long double)n * norm > 0.25L) {
        norm *= 0.5L;
        ++k;
    }
    for (i = 0; i < n; ++i)
        for (j = 0; j < n; ++j) {
            S[i][j] = ldexpl(M[i][j], -k);
            E[i][j] = (i == j) ? 1.0L : 0.0L;
            T[i][j] = E[i][j];
        }
    for (t = 1; t < 30; ++t) { /* T = T S / t; E += T */
        for (i = 0; i < n; ++i)
            for (j = 0; j < n; ++j) {
                long double acc = 0.0L;
                for (l = 0; l < n; ++l) acc += T[i][l] * S[l][j];
                P[i][j] = acc / (long double)t;
            }
        for (i = 0; i < n; ++i)
            for (j = 0; j < n; ++j) {
                T[i][j] = P[i][j];
                E[i][j] += T[i][j];
            }
    }
    for (; k > 0; --k) {
        for (i = 0; i < n; ++i)
            for (j = 0; j < n; ++j) {
                long double acc = 0.0L;
                for (l = 0; l < n; ++l) acc += E[i][l] * E[l][j];
                P[i][j] = acc;
            }
        for (i = 0; i < n; ++i)
            for (j = 0; j < n; ++j) E[i][j] = P[i][j];
    }
}

static void expm3(const long double M3[3][3], long double E3[3][3])
{
    long double M[4][4] = {{0.0L}}, E[4][4];
    unsigned i, j;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) M[i][j] = M3[i][j];
    expmn(3u, M, E);
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) E3[i][j] = E[i][j];
}

static lref reference2(long double d, long double k)
{
    const long double M[3][3] = {{0.0L, 1.0L, 0.0L}, {-k, -d, 1.0L}, {0.0L, 0.0L, 0.0L}};
    long double E[3][3], tr, det, n1, n0;
    lref r;
    expm3(M, E);
    tr = E[0][0] + E[1][1];
    det = expl(-d); /* Liouville: det e^A = e^tr(A) (the product of Phi's entries would cancel) */
    n1 = E[0][2];                                /* Gamma0 */
    n0 = E[0][1] * E[1][2] - E[1][1] * E[0][2];  /* Phi01 Gamma1 - Phi11 Gamma0 */
    r.den[0] = 2.0L;
    r.den[1] = -2.0L * tr;
    r.den[2] = 2.0L * det;
    r.num[0] = 2.0L * n1;
    r.num[1] = 2.0L * n0;
    r.den_s[0] = 2.0L * (1.0L + tr + det);
    r.den_s[1] = -4.0L * expm1l(-d);
    r.den_s[2] = 2.0L * (1.0L - tr + det);
    r.num_s[0] = 2.0L * (n1 - n0);
    r.num_s[1] = 2.0L * (n1 + n0);
    r.den_w[0] = 2.0L;
    r.den_w[1] = 2.0L * (2.0L - tr);
    r.den_w[2] = r.den_s[2];
    return r;
}

/* |computed - reference| <= bound (+ the reference's own error, ~1e-17 relative to 1). */
static void expect_within(const zw_real *v, const zw_real *e, const long double *ref, unsigned n,
                          long double slack, const char *what)
{
    unsigned i;
    for (i = 0; i < n; ++i) {
        long double err = fabsl((long double)v[i] - ref[i]);
        EXPECT_TRUE_MSG(err <= (long double)e[i] + slack, "%s[%u] = %.20Lg, reference %.20Lg, err %.3Lg > bound %.3Lg",
                        what, i, (long double)v[i], ref[i], err, (long double)e[i]);
    }
}

static void expect_plant_within(const zw_plant *p, const lref *r, long double slack)
{
    expect_within(p->den, p->den_err, r->den, 3u, slack, "den");
    expect_within(p->num, p->num_err, r->num, 2u, slack, "num");
    expect_within(p->den_s, p->den_s_err, r->den_s, 3u, slack, "den_s");
    expect_within(p->num_s, p->num_s_err, r->num_s, 2u, slack, "num_s");
    expect_within(p->den_w, p->den_w_err, r->den_w, 3u, slack, "den_w");
}

typedef struct lref3 {
    long double den[4], num[3], den_s[4], num_s[3], den_w[4];
} lref3;

/* det(zI - F), highest first, for 3x3 F */
static void charpoly3(long double F[3][3], long double c[4])
{
    c[0] = 1.0L;
    c[1] = -(F[0][0] + F[1][1] + F[2][2]);
    c[2] = F[0][0] * F[1][1] - F[0][1] * F[1][0] + F[0][0] * F[2][2] - F[0][2] * F[2][0] +
           F[1][1] * F[2][2] - F[1][2] * F[2][1];
    c[3] = -(F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
             F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
             F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]));
}

/* p((1 + s) / (1 - s)) (1 - s)^3 and p(1 + w), highest first */
static void images3(const long double p[4], long double ps[4], long double pw[4])
{
    /* (1+s)^k (1-s)^(3-k), lowest power first, k = 3 - i */
    static const long double basis[4][4] = {
        {1.0L, 3.0L, 3.0L, 1.0L},    /* (1+s)^3 */
        {1.0L, 1.0L, -1.0L, -1.0L},  /* (1+s)^2 (1-s) */
        {1.0L, -1.0L, -1.0L, 1.0L},  /* (1+s)(1-s)^2 */
        {1.0L, -3.0L, 3.0L, -1.0L}}; /* (1-s)^3 */
    static const long double binom[4][4] = {{1, 3, 3, 1}, {1, 2, 1, 0}, {1, 1, 0, 0}, {1, 0, 0, 0}};
    unsigned i, j;
    for (j = 0; j < 4; ++j) {
        ps[j] = 0.0L;
        pw[j] = 0.0L;
    }
    for (i = 0; i < 4; ++i)
        for (j = 0; j < 4; ++j) {
            ps[3 - j] += p[i] * basis[i][j];
            pw[3 - j] += p[i] * binom[i][j]; /* z^k = sum_j C(k, j) w^j */
        }
}

static lref3 reference3(long double d, long double k, long double lam)
{
    long double M[4][4] = {{0.0L, 1.0L, 0.0L, 0.0L},
                           {-k, -d, 1.0L, 0.0L},
                           {0.0L, 0.0L, -1.0L / lam, 1.0L / lam},
                           {0.0L, 0.0L, 0.0L, 0.0L}};
    long double E[4][4], F[3][3], G[3][3], cf[4], cg[4];
    unsigned i, j;
    lref3 r;
    expmn(4u, M, E);
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            F[i][j] = E[i][j];
            G[i][j] = E[i][j] - ((j == 0) ? E[i][3] : 0.0L); /* Phi - Gamma C */
        }
    charpoly3(F, cf);
    charpoly3(G, cg);
    for (i = 0; i < 4; ++i) r.den[i] = 2.0L * cf[i];
    for (i = 1; i < 4; ++i) r.num[i - 1] = 2.0L * (cg[i] - cf[i]);
    images3(r.den, r.den_s, r.den_w);
    /* N (degree 2): a2 (1+s)^2 + a1 (1+s)(1-s) + a0 (1-s)^2 */
    r.num_s[0] = r.num[0] - r.num[1] + r.num[2];
    r.num_s[1] = 2.0L * (r.num[0] - r.num[2]);
    r.num_s[2] = r.num[0] + r.num[1] + r.num[2];
    return r;
}

static void expect_plant3_within(const zw_plant *p, const lref3 *r, long double slack)
{
    expect_within(p->den, p->den_err, r->den, 4u, slack, "den");
    expect_within(p->num, p->num_err, r->num, 3u, slack, "num");
    expect_within(p->den_s, p->den_s_err, r->den_s, 4u, slack, "den_s");
    expect_within(p->num_s, p->num_s_err, r->num_s, 3u, slack, "num_s");
    expect_within(p->den_w, p->den_w_err, r->den_w, 4u, slack, "den_w");
}

/* ---- tests ----------------------------------------------------------------------------- */


static zw_plant plant3_of(zw_real delta, zw_real kappa, zw_real lambda)
{
    zw_plant p;
    zw_plant_spec s = spec_of(delta, kappa, lambda);
    memset(&p, ZWT_SENTINEL, sizeof p);
    EXPECT_OK(zw_plant_init(&p, &s));
    assert_int_equal(p.order, 3);
    return p;
}

/* The lag plant against the long double 4x4 matrix exponential. */
static void test_lag_against_reference(void **state)
{
    static const zw_real ds[] = {R(0.0), R(0.3), R(1.0), R(3.0), R(6.0)};
    static const zw_real ks[] = {R(0.0), R(0.2), R(1.0), R(2.25), R(9.0)};
    static const zw_real ls[] = {R(0.05), R(0.3), R(1.0), R(2.0), R(5.0)};
    size_t i, j, l;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i)
        for (j = 0; j < ZWT_ARRAY_LEN(ks); ++j)
            for (l = 0; l < ZWT_ARRAY_LEN(ls); ++l) {
                zw_plant p = plant3_of(ds[i], ks[j], ls[l]);
                lref3 r = reference3((long double)ds[i], (long double)ks[j], (long double)ls[l]);
                expect_plant3_within(&p, &r, 1e-16L);
            }
}

static void expect_close3(const zw_plant *a, const zw_plant *b, long double slack)
{
    unsigned i;
    for (i = 0; i < 4u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)a->den[i] - b->den[i]) <= a->den_err[i] + b->den_err[i] + slack, "den[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->den_s[i] - b->den_s[i]) <= a->den_s_err[i] + b->den_s_err[i] + slack, "den_s[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->den_w[i] - b->den_w[i]) <= a->den_w_err[i] + b->den_w_err[i] + slack, "den_w[%u]", i);
    }
    for (i = 0; i < 3u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)a->num[i] - b->num[i]) <= a->num_err[i] + b->num_err[i] + slack, "num[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->num_s[i] - b->num_s[i]) <= a->num_s_err[i] + b->num_s_err[i] + slack, "num_s[%u]", i);
    }
}

/* The lag's pole on a plant pole (lambda = 1 / |p|): continuous across, and finite. */
static void test_lag_meets_pole(void **state)
{
    /* delta = 2.5, kappa = 1: poles -0.5 and -2 */
    static const zw_real lams[] = {R(2.0), R(0.5)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(lams); ++i) {
        const zw_real l = lams[i];
        zw_plant lo = plant3_of(R(2.5), R(1.0), ZWT_DOWN(l));
        zw_plant mid = plant3_of(R(2.5), R(1.0), l);
        zw_plant hi = plant3_of(R(2.5), R(1.0), ZWT_UP(l));
        lref3 r = reference3(2.5L, 1.0L, (long double)l);
        expect_plant3_within(&mid, &r, 1e-16L);
        expect_close3(&lo, &mid, 4.0L * (long double)(ZWT_UP(l) - l));
        expect_close3(&mid, &hi, 4.0L * (long double)(ZWT_UP(l) - l));
        assert_true(mid.num_err[0] <= TOL(1000) * mid.num[0]); /* no lost accuracy at the meeting */
    }
}

/* lambda -> 0: N3 -> z N2, D3 -> z D2. */
/* eval on the lag plant: against the reference at complex points, and D3 next to z = 1
 * with lambda >> 1 (the poles 1 and e^-1/lambda both near 1) in relative accuracy. */
static void test_lag_eval(void **state)
{
    static const zw_real pts[][2] = {{R(0.3), R(0.9)}, {R(-1.0), R(0.0)}, {R(0.999), R(0.02)}};
    zw_plant p = plant3_of(R(0.7), R(2.0), R(0.4));
    zw_plant q = plant3_of(R(0.01), R(0.0), R(1000.0));
    lref3 r = reference3(0.7L, 2.0L, 0.4L);
    size_t i;
    zw_real nr, ni, ne, dr, di, de;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(pts); ++i) {
        long double complex_r = pts[i][0], complex_i = pts[i][1];
        long double Nr = 0.0L, Ni = 0.0L, Dr = 0.0L, Di = 0.0L, t;
        unsigned j;
        for (j = 0; j < 3u; ++j) { /* Horner */
            t = Nr * complex_r - Ni * complex_i + r.num[j];
            Ni = Nr * complex_i + Ni * complex_r;
            Nr = t;
        }
        for (j = 0; j < 4u; ++j) {
            t = Dr * complex_r - Di * complex_i + r.den[j];
            Di = Dr * complex_i + Di * complex_r;
            Dr = t;
        }
        EXPECT_OK(zw_plant_eval(&p, pts[i][0], pts[i][1], &nr, &ni, &ne, &dr, &di, &de));
        EXPECT_TRUE_MSG(hypotl(nr - Nr, ni - Ni) <= (long double)ne + 1e-16L, "N at %zu", i);
        EXPECT_TRUE_MSG(hypotl(dr - Dr, di - Di) <= (long double)de + 1e-16L, "D at %zu", i);
    }
    {
        /* D3 = 2 (z - 1)(z - e)(z - a) at z = 1 + 2^-20, a = e^-0.001 */
        const zw_real w = R(9.5367431640625e-7);
        const long double lw = (long double)w;
        const long double D = 2.0L * lw * (lw - expm1l(-0.01L)) * (lw - expm1l(-0.001L));
        EXPECT_OK(zw_plant_eval(&q, R(1.0) + w, R(0.0), &nr, &ni, &ne, &dr, &di, &de));
        EXPECT_TRUE_MSG(fabsl(dr - D) <= de && de <= TOLL(256) * D, "D3 near 1: %Lg vs %Lg, bound %Lg",
                        (long double)dr, D, (long double)de);
    }
}

static void test_lag_to_zero(void **state)
{
    zw_plant p2 = plant_of(R(0.8), R(1.5));
    zw_plant p3 = plant3_of(R(0.8), R(1.5), PREC(R(1e-9), R(1e-5)));
    unsigned i;
    (void)state;
    for (i = 0; i < 3u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)p3.den[i] - p2.den[i]) <= p3.den_err[i] + p2.den_err[i] + 1e-300L, "den[%u]", i);
    }
    assert_true(fabs((double)p3.den[3]) <= (double)p3.den_err[3] + 1e-300);
    for (i = 0; i < 2u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)p3.num[i] - p2.num[i]) <= p3.num_err[i] + p2.num_err[i] + PREC(1e-8L, 1e-4L), "num[%u]", i);
    }
}

static const zw_real k_deltas[] = {R(0.0), R(1e-6), R(0.01), R(0.5), R(1.0), R(2.0), R(3.7), R(10.0), R(100.0)};

static void same_array(const zw_real *a, const zw_real *b, size_t n)
{
    assert_memory_equal(a, b, n * sizeof *a);
}

/* kappa = lambda = 0 is zw_plant_from_coeffs(zw_coeffs_init(delta)), bit for bit. */
static void test_ideal_bit_for_bit(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k_deltas); ++i) {
        zw_plant a, b;
        zw_coeffs c = zwt_coeffs(k_deltas[i]);
        zw_plant_spec s = spec_of(k_deltas[i], R(0.0), R(0.0));
        EXPECT_OK(zw_plant_init(&a, &s));
        EXPECT_OK(zw_plant_from_coeffs(&b, &c));
        assert_int_equal(a.order, 2);
        assert_int_equal(b.order, 2);
        same_array(a.den, b.den, 4u);
        same_array(a.den_err, b.den_err, 4u);
        same_array(a.num, b.num, 3u);
        same_array(a.num_err, b.num_err, 3u);
        same_array(a.den_s, b.den_s, 4u);
        same_array(a.den_s_err, b.den_s_err, 4u);
        same_array(a.num_s, b.num_s, 3u);
        same_array(a.num_s_err, b.num_s_err, 3u);
        same_array(a.den_w, b.den_w, 4u);
        same_array(a.den_w_err, b.den_w_err, 4u);
        assert_memory_equal(&a.c, &b.c, sizeof a.c);
    }
}

/* The ideal plant against the paper's coefficient functions in long double. */
static void test_ideal_against_reference(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k_deltas); ++i) {
        zw_plant p = plant_of(k_deltas[i], R(0.0));
        zwt_ref r = zwt_reference((long double)k_deltas[i]);
        lref l;
        l.den[0] = 2.0L;
        l.den[1] = -2.0L * (1.0L + r.e);
        l.den[2] = 2.0L * r.e;
        l.num[0] = r.c1;
        l.num[1] = r.c2;
        l.den_s[0] = 4.0L * (1.0L + r.e);
        l.den_s[1] = 4.0L * -expm1l(-(long double)k_deltas[i]);
        l.den_s[2] = 0.0L;
        l.num_s[0] = r.d12;
        l.num_s[1] = r.s;
        l.den_w[0] = 2.0L;
        l.den_w[1] = l.den_s[1] * 0.5L;
        l.den_w[2] = 0.0L;
        expect_plant_within(&p, &l, 1e-18L);
    }
}

/* The stiff plant against the long double matrix exponential (away from the tiny-P corner,
 * where long double itself would cancel; the Python test covers it at 50+ digits). */
static void test_stiff_against_reference(void **state)
{
    static const zw_real ks[] = {R(0.05), R(0.25), R(1.0), R(2.0), R(4.0), R(6.25), R(9.0)};
    static const zw_real ds[] = {R(0.0), R(0.1), R(0.7), R(1.0), R(2.0), R(4.0), R(5.0), R(6.0)};
    size_t i, j;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        for (j = 0; j < ZWT_ARRAY_LEN(ks); ++j) {
            zw_plant p = plant_of(ds[i], ks[j]);
            lref r = reference2((long double)ds[i], (long double)ks[j]);
            expect_plant_within(&p, &r, 1e-16L); /* the long double reference's own error */
        }
    }
}

/* Continuity across critical damping (delta^2 = 4 kappa) and the regime switches: the
 * plants at neighbouring kappa differ by no more than their bounds plus the coefficients'
 * change over one ulp of kappa. */
static void expect_close(const zw_plant *a, const zw_plant *b, long double slack)
{
    unsigned i;
    for (i = 0; i < 3u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)a->den[i] - b->den[i]) <= a->den_err[i] + b->den_err[i] + slack, "den[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->den_s[i] - b->den_s[i]) <= a->den_s_err[i] + b->den_s_err[i] + slack, "den_s[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->den_w[i] - b->den_w[i]) <= a->den_w_err[i] + b->den_w_err[i] + slack, "den_w[%u]", i);
    }
    for (i = 0; i < 2u; ++i) {
        EXPECT_TRUE_MSG(fabsl((long double)a->num[i] - b->num[i]) <= a->num_err[i] + b->num_err[i] + slack, "num[%u]", i);
        EXPECT_TRUE_MSG(fabsl((long double)a->num_s[i] - b->num_s[i]) <= a->num_s_err[i] + b->num_s_err[i] + slack, "num_s[%u]", i);
    }
}

static void test_continuity_hard_cases(void **state)
{
    static const zw_real ds[] = {R(1e-4), R(0.3), R(2.0), R(3.99), R(4.0), R(4.01), R(6.0), R(50.0)};
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(ds); ++i) {
        const zw_real d = ds[i];
        const zw_real kc = d * d / R(4.0);                /* critical damping */
        const zw_real ke[] = {kc, kc + R(4.0), kc - R(4.0), d * d / R(8.0)}; /* |w2| = 4, w2 = h^2 / 2 */
        size_t j;
        for (j = 0; j < ZWT_ARRAY_LEN(ke); ++j) {
            zw_plant lo, mid, hi;
            const zw_real k = ke[j];
            if (!(ZWT_DOWN(k) > R(0.0))) continue;
            lo = plant_of(d, ZWT_DOWN(k));
            mid = plant_of(d, k);
            hi = plant_of(d, ZWT_UP(k));
            /* one ulp of kappa moves a coefficient by at most ~ulp(kappa) / kappa */
            expect_close(&lo, &mid, 4.0L * (long double)(ZWT_UP(k) - k));
            expect_close(&mid, &hi, 4.0L * (long double)(ZWT_UP(k) - k));
        }
    }
}

/* kappa -> 0 meets the ideal plant. */
static void test_kappa_to_zero(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k_deltas); ++i) {
        zw_plant a = plant_of(k_deltas[i], R(0.0));
        zw_plant b = plant_of(k_deltas[i], PREC(R(1e-30), R(1e-25)));
        expect_close(&a, &b, PREC(1e-29L, 1e-24L));
    }
}

/* A stated input uncertainty only widens the bounds. */
static void test_relerr_widens(void **state)
{
    zw_plant a, b;
    zw_plant_spec s = spec_of(R(0.8), R(3.0), R(0.0));
    unsigned i;
    (void)state;
    EXPECT_OK(zw_plant_init(&a, &s));
    s.delta_relerr = TOL(8);
    s.kappa_relerr = TOL(8);
    EXPECT_OK(zw_plant_init(&b, &s));
    for (i = 0; i < 3u; ++i) {
        assert_true(b.den_s_err[i] >= a.den_s_err[i]);
        assert_true(b.den_err[i] >= a.den_err[i]);
    }
    assert_true(b.num_err[0] > a.num_err[0]);
}

/* eval: N and D at complex points against long double Horner on the reference; D keeps its
 * relative accuracy next to z = 1. */
static void test_eval(void **state)
{
    static const zw_real pts[][2] = {{R(1.0), R(0.0)}, {R(0.3), R(0.9)}, {R(-1.0), R(0.0)}, {R(0.999), R(0.02)}, {R(2.0), R(-1.0)}};
    zw_plant p = plant_of(R(0.7), R(2.0));
    zw_plant q = plant_of(R(0.01), R(0.0));
    lref r = reference2(0.7L, 2.0L);
    size_t i;
    zw_real nr, ni, ne, dr, di, de;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(pts); ++i) {
        long double zr = pts[i][0], zi = pts[i][1];
        long double Nr = r.num[0] * zr + r.num[1], Ni = r.num[0] * zi;
        long double z2r = zr * zr - zi * zi, z2i = 2.0L * zr * zi;
        long double Dr = r.den[0] * z2r + r.den[1] * zr + r.den[2], Di = r.den[0] * z2i + r.den[1] * zi;
        EXPECT_OK(zw_plant_eval(&p, pts[i][0], pts[i][1], &nr, &ni, &ne, &dr, &di, &de));
        EXPECT_TRUE_MSG(hypotl(nr - Nr, ni - Ni) <= (long double)ne + 1e-17L, "N at %zu", i);
        EXPECT_TRUE_MSG(hypotl(dr - Dr, di - Di) <= (long double)de + 1e-17L, "D at %zu", i);
    }
    /* D = 2 (z - 1)(z - e) at z = 1 + 2^-20: relative accuracy */
    {
        const zw_real w = R(9.5367431640625e-7);
        const long double e = expl(-0.01L);
        const long double D = 2.0L * (long double)w * ((long double)w + 1.0L - e);
        EXPECT_OK(zw_plant_eval(&q, R(1.0) + w, R(0.0), &nr, &ni, &ne, &dr, &di, &de));
        EXPECT_TRUE_MSG(fabsl(dr - D) <= de && de <= TOLL(64) * D, "D near 1: %Lg vs %Lg, bound %Lg", (long double)dr, D, (long double)de);
    }
}

static bool all_nan(const zw_real *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; ++i)
        if (!isnan(v[i])) return false;
    return true;
}

static bool failsafe_plant(const zw_plant *p)
{
    return p->order == 0u && all_nan(p->den, 4u) && all_nan(p->num, 3u) && all_nan(p->den_s, 4u) &&
           all_nan(p->num_s, 3u) && all_nan(p->den_err, 4u) && all_nan(p->den_w, 4u) &&
           isnan(p->spec.delta) && zwt_all_nan_coeffs(&p->c);
}

static void expect_init_fails(zw_plant_spec s, zw_status want)
{
    zw_plant p;
    memset(&p, ZWT_SENTINEL, sizeof p);
    EXPECT_STATUS(zw_plant_init(&p, &s), want);
    assert_true(failsafe_plant(&p));
}

static void test_errors_failsafe(void **state)
{
    const zw_real nan = (zw_real)NAN, inf = (zw_real)INFINITY;
    zw_plant p;
    zw_plant_spec s = spec_of(R(1.0), R(1.0), R(0.0));
    zw_coeffs c;
    zw_real v[6];
    unsigned i;
    (void)state;
    EXPECT_STATUS(zw_plant_init(NULL, &s), ZW_ERR_NULL);
    memset(&p, ZWT_SENTINEL, sizeof p);
    EXPECT_STATUS(zw_plant_init(&p, NULL), ZW_ERR_NULL);
    assert_true(failsafe_plant(&p));
    expect_init_fails(spec_of(nan, R(1.0), R(0.0)), ZW_ERR_NAN);
    expect_init_fails(spec_of(R(1.0), nan, R(0.0)), ZW_ERR_NAN);
    expect_init_fails(spec_of(R(1.0), R(1.0), nan), ZW_ERR_NAN);
    expect_init_fails(spec_of(inf, R(1.0), R(0.0)), ZW_ERR_INF);
    expect_init_fails(spec_of(R(1.0), inf, R(0.0)), ZW_ERR_INF);
    expect_init_fails(spec_of(R(-1.0), R(1.0), R(0.0)), ZW_ERR_DELTA);
    expect_init_fails(spec_of(R(1.0), R(-1.0), R(0.0)), ZW_ERR_ARG);
    expect_init_fails(spec_of(R(1.0), R(1.0), R(-1.0)), ZW_ERR_ARG);
    s.kappa_relerr = R(0.0625);
    expect_init_fails(s, ZW_ERR_ARG);
    s.kappa_relerr = R(-1e-9);
    expect_init_fails(s, ZW_ERR_ARG);
    s.kappa_relerr = R(0.0);
    s.delta_relerr = nan;
    expect_init_fails(s, ZW_ERR_NAN);
    /* h^2 or (1 / lambda)^2 overflows */
    expect_init_fails(spec_of(PREC(R(1e200), R(1e30)), R(1.0), R(0.0)), ZW_ERR_RANGE);
    expect_init_fails(spec_of(R(1.0), R(1.0), PREC(R(1e-200), R(1e-25))), ZW_ERR_RANGE);
    /* from_coeffs */
    EXPECT_STATUS(zw_plant_from_coeffs(&p, NULL), ZW_ERR_NULL);
    assert_true(failsafe_plant(&p));
    EXPECT_STATUS(zw_plant_from_coeffs(NULL, &c), ZW_ERR_NULL);
    c = zwt_coeffs(R(1.0));
    c.delta_relerr = R(-1.0);
    memset(&p, ZWT_SENTINEL, sizeof p);
    EXPECT_STATUS(zw_plant_from_coeffs(&p, &c), ZW_ERR_ARG);
    assert_true(failsafe_plant(&p));
    c.delta_relerr = R(0.0);
    c.delta = nan;
    EXPECT_STATUS(zw_plant_from_coeffs(&p, &c), ZW_ERR_NAN);
    assert_true(failsafe_plant(&p));
    /* eval on a failed plant, with NaN z, with NULL outputs */
    for (i = 0; i < 6u; ++i) v[i] = R(0.0);
    EXPECT_STATUS(zw_plant_eval(&p, R(1.0), R(0.0), &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]), ZW_ERR_ARG);
    assert_true(all_nan(v, 6u));
    p = plant_of(R(1.0), R(1.0));
    for (i = 0; i < 6u; ++i) v[i] = R(0.0);
    EXPECT_STATUS(zw_plant_eval(&p, nan, R(0.0), &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]), ZW_ERR_NAN);
    assert_true(all_nan(v, 6u));
    for (i = 0; i < 6u; ++i) v[i] = R(0.0);
    EXPECT_STATUS(zw_plant_eval(&p, R(1.0), R(0.0), &v[0], &v[1], NULL, &v[3], &v[4], &v[5]), ZW_ERR_NULL);
    assert_true(isnan(v[0]) && isnan(v[1]) && isnan(v[3]) && isnan(v[4]) && isnan(v[5]));
}

static void test_spec_from_device(void **state)
{
    const zw_real nan = (zw_real)NAN;
    zw_plant_spec s;
    zw_real M;
    (void)state;
    EXPECT_OK(zw_plant_spec_from_device(R(0.2), R(1.5), R(0.001), R(300.0), R(0.0002), R(0.3),
                                        R(2.0), R(500.0), &s, &M));
    EXPECT_REL(M, 0.5L, TOL(1));
    EXPECT_REL(s.delta, 3.5L * 0.001L / 0.5L, TOL(5));
    EXPECT_REL(s.kappa, 800.0L * 1e-6L / 0.5L, TOL(6));
    EXPECT_REL(s.lambda, 0.2L, TOL(2));
    assert_true(s.delta_relerr >= TOL(4) && s.kappa_relerr >= TOL(5) && s.lambda_relerr >= TOL(1));
    /* uncoupled, no spring, no lag: the paper's plant */
    EXPECT_OK(zw_plant_spec_from_device(R(0.2), R(1.5), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0),
                                        R(0.0), &s, &M));
    assert_true(s.kappa == R(0.0) && s.lambda == R(0.0) && M == R(0.2));
#define FAILS(call, want)                                                                        \
    do {                                                                                         \
        s.delta = R(1.0);                                                                        \
        M = R(1.0);                                                                              \
        EXPECT_STATUS(call, want);                                                               \
        assert_true(isnan(s.delta) && isnan(s.kappa) && isnan(s.lambda) && isnan(s.delta_relerr) && isnan(M)); \
    } while (0)
    FAILS(zw_plant_spec_from_device(R(0.0), R(1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_MASS);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_PERIOD);
    FAILS(zw_plant_spec_from_device(R(1.0), R(-1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_DAMPING);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(-1.0), R(0.0), &s, &M), ZW_ERR_DAMPING);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(-1.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_ARG);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(0.0), R(-1.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_ARG);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(0.0), R(0.0), R(-1.0), R(0.0), R(0.0), &s, &M), ZW_ERR_ARG);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0), R(-1.0), &s, &M), ZW_ERR_ARG);
    FAILS(zw_plant_spec_from_device(nan, R(1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_NAN);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), (zw_real)INFINITY, R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_INF);
    FAILS(zw_plant_spec_from_device(PREC(R(1e-300), R(1e-37)), PREC(R(1e300), R(1e30)), PREC(R(1e10), R(1e5)), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_RANGE);
    FAILS(zw_plant_spec_from_device(R(1.0), R(1.0), PREC(R(1e-170), R(1e-25)), R(1.0), R(0.0), R(0.0), R(0.0), R(0.0), &s, &M), ZW_ERR_RANGE);
#undef FAILS
    M = R(1.0);
    EXPECT_STATUS(zw_plant_spec_from_device(R(1.0), R(1.0), R(0.001), R(0.0), R(0.0), R(0.0), R(0.0), R(0.0), NULL, &M), ZW_ERR_NULL);
    assert_true(isnan(M));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ideal_bit_for_bit),
        cmocka_unit_test(test_ideal_against_reference),
        cmocka_unit_test(test_stiff_against_reference),
        cmocka_unit_test(test_continuity_hard_cases),
        cmocka_unit_test(test_kappa_to_zero),
        cmocka_unit_test(test_relerr_widens),
        cmocka_unit_test(test_lag_against_reference),
        cmocka_unit_test(test_lag_meets_pole),
        cmocka_unit_test(test_lag_to_zero),
        cmocka_unit_test(test_lag_eval),
        cmocka_unit_test(test_eval),
        cmocka_unit_test(test_errors_failsafe),
        cmocka_unit_test(test_spec_from_device),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
