/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/c/harness.c - the C side of the benchmark report (bench/report/generate.py).
 *
 * Built twice (bench/report/CMakeLists.txt): zwreport_d against the double core,
 * zwreport_f against the float core (-DZW_REAL_FLOAT comes with zwidth_f).  The points
 * come from a file that generate.py writes, so that C and Python judge the same inputs:
 *
 *   points file: one point per line, "delta alpha beta" as C99 hexadecimal floats (exact
 *   in both directions: Python's float.hex / float.fromhex).  The float program rounds
 *   each value to float on reading (round to nearest, as numpy's float32 cast does), and
 *   generate.py scores it against the reference at those rounded inputs.
 *
 * Modes (results go to stdout, one line per item, hexadecimal floats where a value is
 * exact; errors to stderr, exit status 2):
 *
 *   zwreport_X methods
 *       the method names, one per line.
 *   zwreport_X verdicts POINTS
 *       per point: i, then status and result of every verdict and value method:
 *       check (zw_check: stable, marginal), check_literal (zw_check on literal coefficients:
 *       stable), jury (zw_radius_within r = 1: within), jury_plain (conditions (9),
 *       unguarded: stable), radius (zw_spectral_radius: rho), k_max (zw_device_k_max at
 *       B = beta on m = 1, b = delta, T = 1, so K = alpha and B = beta exactly).
 *   zwreport_X coeffs DELTAS
 *       per delta (one hexadecimal float per line): status and e, c1, c2, d12 of
 *       zw_coeffs_init; status and c1, c2, d12 of zw_coeffs_literal; status and
 *       alpha_mmax, beta_at_alpha_mmax, alpha_p_max, beta_mmax of zw_extremes_compute.
 *   zwreport_X time POINTS REPEATS [METHOD...]
 *       per method: name, nanoseconds per call (best of REPEATS passes over every point).
 *   zwreport_X count METHOD N POINTS
 *       exactly N calls of METHOD, cycling over the first COUNT_POINTS points, for
 *       valgrind --tool=callgrind: instructions per call = (Ir(N) - Ir(0)) / N.  The set-up
 *       (reading and preparing the points) does not depend on N or on METHOD, so one
 *       N = 0 run is the baseline of every method.
 *
 * A method is one function call on a prepared point: the coefficients (careful and
 * literal) and the device are prepared for every point before any timing, so "check"
 * costs zw_check alone; "*_new_plant" methods also compute the coefficients, as a design
 * sweep with a new plant per point must.
 */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "zwidth/zwidth.h"

/* Points the count mode prepares and cycles over: fixed, so that the set-up is the same
 * for every N (the callgrind baseline must be the same program run with N = 0). */
#define COUNT_POINTS 2048

typedef struct point {
    zw_real delta, alpha, beta;
} point;

/* Everything a method may need, computed once per point outside the timed loops. */
typedef struct prepared {
    point x;
    zw_coeffs co;   /* zw_coeffs_init */
    zw_coeffs lit;  /* the same struct filled from the literal formulas */
    zw_device dev;  /* m = 1, b = delta, T = 1: K = alpha, B = beta with no rounding */
    zw_status co_st, lit_st, dev_st;
} prepared;

/* --------------------------------------------------------------------------------------
 * The literal-coefficient peer.  Not a product (coeffs.h keeps zw_coeffs_literal only so
 * that benchmarks can show what the careful formulas buy): the struct zw_check reads,
 * with c1, c2, d12 from the paper's literal eqs (3), (4) and the derived fields from
 * them as the paper would write them (s = c1 + c2, g = c1 / s, hs = (2 / c2) / sigma).
 * sigma is the same exact power-of-two scale zw_coeffs_init uses (it is a scaling, not a
 * coefficient: it changes no rounding), so the only difference from the product is the
 * cancellation of the literal formulas.  zw_check still budgets ZW_COEF_ULPS for the
 * coefficient error, which the literal formulas do not honour: that is the point.
 * -------------------------------------------------------------------------------------- */
static zw_real power_of_two_scale(zw_real delta)
{
    int exponent;
    zw_real mantissa;
    if (!(delta > ZW_R(1.0))) return ZW_R(1.0);
    mantissa = ZW_FREXP(delta, &exponent);
    if (mantissa == ZW_R(0.5)) exponent -= 1; /* delta is itself a power of two */
    if (exponent > ZW_REAL_MAX_EXP - 1) exponent = ZW_REAL_MAX_EXP - 1;
    return ZW_LDEXP(ZW_R(1.0), exponent);
}

static zw_status coeffs_literal_struct(zw_coeffs *out, zw_real delta)
{
    zw_coeffs c;
    zw_status st = zw_coeffs_literal(delta, &c.c1, &c.c2, &c.d12);
    if (st != ZW_OK) return st;
    c.delta = delta;
    c.delta_relerr = ZW_R(0.0);
    c.e = ZW_EXP(-delta);
    c.s = c.c1 + c.c2;
    c.g = c.c1 / c.s;
    c.sigma = power_of_two_scale(delta);
    c.hs = ZW_R(2.0) / c.c2 / c.sigma;
    *out = c;
    return ZW_OK;
}

/* The Jury conditions (9) of shared/notes/math.md on p(z) = 2 z^3 + a1 z^2 + a2 z + a3
 * from zw_char_poly, with no error bound: what a textbook implementation does.
 *   p(1) > 0, p(-1) < 0, |a3| < 2, 4 - a3^2 > |2 a2 - a3 a1|   (c2 beta = -a3). */
static zw_status jury_plain(const zw_coeffs *c, zw_real alpha, zw_real beta, bool *stable)
{
    zw_real p[4];
    zw_status st = zw_char_poly(c, alpha, beta, p);
    if (st != ZW_OK) return st;
    *stable = (p[0] + p[1] + p[2] + p[3] > ZW_R(0.0)) && (-p[0] + p[1] - p[2] + p[3] < ZW_R(0.0)) &&
              (ZW_FABS(p[3]) < p[0]) &&
              (p[0] * p[0] - p[3] * p[3] > ZW_FABS(p[0] * p[2] - p[3] * p[1]));
    return ZW_OK;
}

/* --------------------------------------------------------------------------------------
 * Methods for time and count: each returns a small integer that the caller folds into a
 * volatile sink, so that no call can be optimized away.  Status codes are folded in too.
 * -------------------------------------------------------------------------------------- */
typedef unsigned (*method_fn)(const prepared *p);

static unsigned m_noop(const prepared *p)
{
    return (unsigned)(p->x.alpha > ZW_R(0.0));
}

static unsigned m_coeffs_init(const prepared *p)
{
    zw_coeffs c;
    zw_status st = zw_coeffs_init(&c, p->x.delta);
    return (unsigned)st + (unsigned)(c.c2 > ZW_R(0.5));
}

static unsigned m_coeffs_literal(const prepared *p)
{
    zw_real c1 = ZW_R(0.0), c2 = ZW_R(0.0), d12 = ZW_R(0.0);
    zw_status st = zw_coeffs_literal(p->x.delta, &c1, &c2, &d12);
    return (unsigned)st + (unsigned)(c1 + c2 + d12 > ZW_R(0.5));
}

static unsigned m_device_init(const prepared *p)
{
    zw_device d;
    zw_status st = zw_device_init(&d, ZW_R(1.0), p->x.delta, ZW_R(1.0));
    return (unsigned)st + (unsigned)(d.co.c2 > ZW_R(0.5));
}

static unsigned m_check(const prepared *p)
{
    zw_verdict v;
    zw_status st = zw_check(&p->co, p->x.alpha, p->x.beta, &v);
    return (unsigned)st + (st == ZW_OK ? (unsigned)v.stable : 0u);
}

static unsigned m_check_new_plant(const prepared *p)
{
    zw_coeffs c;
    zw_verdict v;
    zw_status st = zw_coeffs_init(&c, p->x.delta);
    if (st == ZW_OK) st = zw_check(&c, p->x.alpha, p->x.beta, &v);
    return (unsigned)st + (st == ZW_OK ? (unsigned)v.stable : 0u);
}

static unsigned m_check_literal(const prepared *p)
{
    zw_verdict v;
    zw_status st = zw_check(&p->lit, p->x.alpha, p->x.beta, &v);
    return (unsigned)st + (st == ZW_OK ? (unsigned)v.stable : 0u);
}

static unsigned m_check_literal_new_plant(const prepared *p)
{
    zw_coeffs c;
    zw_verdict v;
    zw_status st = coeffs_literal_struct(&c, p->x.delta);
    if (st == ZW_OK) st = zw_check(&c, p->x.alpha, p->x.beta, &v);
    return (unsigned)st + (st == ZW_OK ? (unsigned)v.stable : 0u);
}

static unsigned m_jury(const prepared *p)
{
    bool within = false;
    zw_status st = zw_radius_within(&p->co, p->x.alpha, p->x.beta, ZW_R(1.0), &within);
    return (unsigned)st + (unsigned)within;
}

static unsigned m_jury_plain(const prepared *p)
{
    bool stable = false;
    zw_status st = jury_plain(&p->co, p->x.alpha, p->x.beta, &stable);
    return (unsigned)st + (unsigned)stable;
}

static unsigned m_radius(const prepared *p)
{
    zw_real rho = ZW_R(0.0);
    zw_status st = zw_spectral_radius(&p->co, p->x.alpha, p->x.beta, &rho);
    return (unsigned)st + (unsigned)(rho < ZW_R(1.0));
}

static unsigned m_k_max(const prepared *p)
{
    zw_real k = ZW_R(0.0);
    zw_status st = zw_device_k_max(&p->dev, p->x.beta, &k);
    return (unsigned)st + (unsigned)(k > p->x.alpha);
}

static unsigned m_extremes(const prepared *p)
{
    zw_extremes x;
    zw_status st = zw_extremes_compute(&p->co, &x);
    return (unsigned)st + (unsigned)(x.alpha_mmax > ZW_R(1.0));
}

typedef struct method {
    const char *name;
    method_fn fn;
} method;

static const method k_methods[] = {
    {"noop", m_noop},                     /* the harness loop and indirect call alone */
    {"coeffs_init", m_coeffs_init},
    {"coeffs_literal", m_coeffs_literal},
    {"device_init", m_device_init},
    {"check", m_check},
    {"check_new_plant", m_check_new_plant},
    {"check_literal", m_check_literal},
    {"check_literal_new_plant", m_check_literal_new_plant},
    {"jury", m_jury},
    {"jury_plain", m_jury_plain},
    {"radius", m_radius},
    {"k_max", m_k_max},
    {"extremes", m_extremes},
};
#define N_METHODS (sizeof k_methods / sizeof k_methods[0])

static const method *find_method(const char *name)
{
    size_t i;
    for (i = 0; i < N_METHODS; ++i)
        if (strcmp(k_methods[i].name, name) == 0) return &k_methods[i];
    return NULL;
}

/* -------------------------------------------------------------------------------------- */

static void die(const char *what)
{
    fprintf(stderr, "zwreport (%s): %s\n", ZW_REAL_NAME, what);
    exit(2);
}

/* One C99 hexadecimal (or decimal) float; rounded to zw_real on return. */
static zw_real parse_real(const char *s, char **end)
{
    double v;
    errno = 0;
    v = strtod(s, end);
    if (*end == s) die("malformed number in input file");
    return (zw_real)v;
}

/* Read up to max_points points (0: all); returns the count, *out malloc'ed. */
static size_t read_points(const char *path, size_t max_points, point **out)
{
    FILE *f = fopen(path, "r");
    char line[512];
    size_t n = 0, cap = 1024;
    point *pts;
    if (f == NULL) die("cannot open the points file");
    pts = malloc(cap * sizeof *pts);
    if (pts == NULL) die("out of memory");
    while (fgets(line, sizeof line, f) != NULL) {
        char *s = line, *end;
        if (line[0] == '#' || line[0] == '\n') continue;
        if (max_points != 0 && n == max_points) break;
        if (n == cap) {
            point *grown;
            cap *= 2;
            grown = realloc(pts, cap * sizeof *pts);
            if (grown == NULL) die("out of memory");
            pts = grown;
        }
        pts[n].delta = parse_real(s, &end);
        s = end;
        pts[n].alpha = parse_real(s, &end);
        s = end;
        pts[n].beta = parse_real(s, &end);
        ++n;
    }
    fclose(f);
    *out = pts;
    return n;
}

static prepared *prepare(const point *pts, size_t n)
{
    size_t i;
    prepared *p = malloc((n ? n : 1) * sizeof *p);
    if (p == NULL) die("out of memory");
    for (i = 0; i < n; ++i) {
        p[i].x = pts[i];
        p[i].co_st = zw_coeffs_init(&p[i].co, pts[i].delta);
        p[i].lit_st = coeffs_literal_struct(&p[i].lit, pts[i].delta);
        p[i].dev_st = zw_device_init(&p[i].dev, ZW_R(1.0), pts[i].delta, ZW_R(1.0));
    }
    return p;
}

static void print_real(zw_real x)
{
    printf(" %a", (double)x);
}

static int mode_verdicts(const char *path)
{
    point *pts;
    size_t n = read_points(path, 0, &pts), i;
    prepared *p = prepare(pts, n);
    printf("# i check_st check_stable check_marginal literal_st literal_stable jury_st jury_within "
           "jury_plain_st jury_plain_stable radius_st rho k_max_st k_max\n");
    for (i = 0; i < n; ++i) {
        const prepared *q = &p[i];
        zw_verdict v = {false, false, ZW_BOUND_NONE, 0}, vl = {false, false, ZW_BOUND_NONE, 0};
        bool within = false, plain = false;
        zw_real rho = ZW_R(0.0), kmax = ZW_R(0.0);
        zw_status st_c = q->co_st, st_l = q->lit_st, st_j, st_p, st_r, st_k = q->dev_st;
        if (st_c == ZW_OK) st_c = zw_check(&q->co, q->x.alpha, q->x.beta, &v);
        if (st_l == ZW_OK) st_l = zw_check(&q->lit, q->x.alpha, q->x.beta, &vl);
        st_j = q->co_st == ZW_OK ? zw_radius_within(&q->co, q->x.alpha, q->x.beta, ZW_R(1.0), &within) : q->co_st;
        st_p = q->co_st == ZW_OK ? jury_plain(&q->co, q->x.alpha, q->x.beta, &plain) : q->co_st;
        st_r = q->co_st == ZW_OK ? zw_spectral_radius(&q->co, q->x.alpha, q->x.beta, &rho) : q->co_st;
        if (st_k == ZW_OK) st_k = zw_device_k_max(&q->dev, q->x.beta, &kmax);
        printf("%lu %d %d %d %d %d %d %d %d %d %d", (unsigned long)i, (int)st_c, (int)v.stable,
               (int)v.marginal, (int)st_l, (int)vl.stable, (int)st_j, (int)within, (int)st_p, (int)plain,
               (int)st_r);
        print_real(rho);
        printf(" %d", (int)st_k);
        print_real(kmax);
        printf("\n");
    }
    free(p);
    free(pts);
    return 0;
}

static int mode_coeffs(const char *path)
{
    FILE *f = fopen(path, "r");
    char line[256];
    if (f == NULL) die("cannot open the deltas file");
    printf("# delta series_st e c1 c2 d12 literal_st c1 c2 d12 extremes_st alpha_mmax beta_at alpha_p_max "
           "beta_mmax\n");
    while (fgets(line, sizeof line, f) != NULL) {
        char *end;
        zw_real d, l1 = ZW_R(0.0), l2 = ZW_R(0.0), l12 = ZW_R(0.0);
        zw_coeffs c;
        zw_extremes x;
        zw_status st, st_l, st_x = ZW_ERR_ARG;
        if (line[0] == '#' || line[0] == '\n') continue;
        d = parse_real(line, &end);
        memset(&c, 0, sizeof c);
        memset(&x, 0, sizeof x);
        st = zw_coeffs_init(&c, d);
        st_l = zw_coeffs_literal(d, &l1, &l2, &l12);
        if (st == ZW_OK) st_x = zw_extremes_compute(&c, &x);
        print_real(d);
        printf(" %d", (int)st);
        print_real(c.e);
        print_real(c.c1);
        print_real(c.c2);
        print_real(c.d12);
        printf(" %d", (int)st_l);
        print_real(l1);
        print_real(l2);
        print_real(l12);
        printf(" %d", (int)st_x);
        print_real(x.alpha_mmax);
        print_real(x.beta_at_alpha_mmax);
        print_real(x.alpha_p_max);
        print_real(x.beta_mmax);
        printf("\n");
    }
    fclose(f);
    return 0;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static volatile unsigned g_sink;

/* Best of `repeats` passes over all points, per call.  One untimed warm-up pass first
 * (page faults, branch predictors, caches). */
static double time_method(const method *m, const prepared *p, size_t n, int repeats)
{
    double best = -1.0;
    int r;
    size_t i;
    unsigned acc = 0;
    for (i = 0; i < n; ++i) acc += m->fn(&p[i]);
    for (r = 0; r < repeats; ++r) {
        double t0 = now_ns(), dt;
        for (i = 0; i < n; ++i) acc += m->fn(&p[i]);
        dt = now_ns() - t0;
        if (best < 0.0 || dt < best) best = dt;
    }
    g_sink = acc;
    return best / (double)n;
}

static int mode_time(const char *path, int repeats, int argc, char **argv)
{
    point *pts;
    size_t n = read_points(path, 0, &pts), i;
    prepared *p = prepare(pts, n);
    if (n == 0) die("no points");
    if (argc == 0) {
        for (i = 0; i < N_METHODS; ++i)
            printf("%s %.4f\n", k_methods[i].name, time_method(&k_methods[i], p, n, repeats));
    } else {
        int a;
        for (a = 0; a < argc; ++a) {
            const method *m = find_method(argv[a]);
            if (m == NULL) die("unknown method (try: zwreport methods)");
            printf("%s %.4f\n", m->name, time_method(m, p, n, repeats));
        }
    }
    free(p);
    free(pts);
    return 0;
}

static int mode_count(const char *name, unsigned long calls, const char *path)
{
    const method *m = find_method(name);
    point *pts;
    size_t n, i;
    unsigned long k;
    unsigned acc = 0;
    prepared *p;
    if (m == NULL) die("unknown method (try: zwreport methods)");
    n = read_points(path, COUNT_POINTS, &pts);
    if (n == 0) die("no points");
    p = prepare(pts, n);
    for (k = 0, i = 0; k < calls; ++k) {
        acc += m->fn(&p[i]);
        if (++i == n) i = 0;
    }
    g_sink = acc;
    printf("%s %lu calls over %lu points\n", m->name, calls, (unsigned long)n);
    free(p);
    free(pts);
    return 0;
}

static void usage(void)
{
    fprintf(stderr,
            "usage: zwreport methods | verdicts POINTS | coeffs DELTAS | time POINTS REPEATS [METHOD...] |\n"
            "       count METHOD N POINTS   (precision: %s)\n",
            ZW_REAL_NAME);
    exit(2);
}

static unsigned long parse_count(const char *s)
{
    char *end;
    unsigned long v;
    errno = 0;
    v = strtoul(s, &end, 10);
    if (*s == '\0' || *end != '\0' || errno != 0) usage();
    return v;
}

int main(int argc, char **argv)
{
    if (argc < 2) usage();
    if (strcmp(argv[1], "methods") == 0) {
        size_t i;
        for (i = 0; i < N_METHODS; ++i) printf("%s\n", k_methods[i].name);
        return 0;
    }
    if (strcmp(argv[1], "verdicts") == 0 && argc == 3) return mode_verdicts(argv[2]);
    if (strcmp(argv[1], "coeffs") == 0 && argc == 3) return mode_coeffs(argv[2]);
    if (strcmp(argv[1], "time") == 0 && argc >= 4) {
        unsigned long r = parse_count(argv[3]);
        if (r < 1 || r > 1000) usage();
        return mode_time(argv[2], (int)r, argc - 4, argv + 4);
    }
    if (strcmp(argv[1], "count") == 0 && argc == 5) return mode_count(argv[2], parse_count(argv[3]), argv[4]);
    usage();
    return 2;
}
