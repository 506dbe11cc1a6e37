/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* tools/diff_plant.c - differential test of two builds of the core (tools/diff_plant.sh):
 * loads an old and a new shared library of the same precision with dlopen and compares,
 * bit for bit, every field of zw_plant_init's output and its status on random and hard
 * specs, zw_box_loop_check's verdicts on random plant boxes, and (every filter and
 * differentiator) zw_box_loop_check's verdicts and zw_box_loop_k_max's bounds, every field
 * bitwise.  Exit 0: identical. */
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/box.h"
#include "zwidth/plant.h"

#define STR_(x) #x
#define STR(x) STR_(x) /* the float build's names are zw_..._f (precision.h) */

typedef zw_status (*plant_init_fn)(zw_plant *, const zw_plant_spec *);
typedef zw_status (*work_init_fn)(zw_box_loop_work *, zw_box_loop_cell *, uint_least32_t,
                                  zw_box_loop_scratch *);
typedef zw_status (*box_check_fn)(const zw_plant_box *, const zw_device_loop_spec *,
                                  zw_loop_workspace *, zw_real, zw_real, const zw_box_loop_work *,
                                  zw_box_loop_verdict *);

typedef zw_status (*box_k_max_fn)(const zw_plant_box *, const zw_device_loop_spec *,
                                  zw_loop_workspace *, zw_real, const zw_box_loop_work *,
                                  zw_box_loop_bound *);

typedef struct lib {
    plant_init_fn plant_init;
    work_init_fn work_init;
    box_check_fn box_check;
    box_k_max_fn box_k_max;
} lib;

static void *sym(void *h, const char *name)
{
    void *p = dlsym(h, name);
    if (p == NULL) {
        fprintf(stderr, "diff_plant: %s: %s\n", name, dlerror());
        exit(2);
    }
    return p;
}

static lib load(const char *path)
{
    lib l;
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (h == NULL) {
        fprintf(stderr, "diff_plant: %s\n", dlerror());
        exit(2);
    }
    *(void **)&l.plant_init = sym(h, STR(zw_plant_init));
    *(void **)&l.work_init = sym(h, STR(zw_box_loop_work_init));
    *(void **)&l.box_check = sym(h, STR(zw_box_loop_check));
    *(void **)&l.box_k_max = sym(h, STR(zw_box_loop_k_max));
    return l;
}

/* xorshift64*: reproducible */
static uint64_t g_rng = 0x9E3779B97F4A7C15ull;
static uint64_t next_u64(void)
{
    g_rng ^= g_rng >> 12;
    g_rng ^= g_rng << 25;
    g_rng ^= g_rng >> 27;
    return g_rng * 2685821657736338717ull;
}
static double unit(void) { return (double)(next_u64() >> 11) * (1.0 / 9007199254740992.0); }
static double log_uniform(double lo, double hi) { return exp(log(lo) + (log(hi) - log(lo)) * unit()); }

static int same_bits(zw_real a, zw_real b) { return memcmp(&a, &b, sizeof a) == 0; }

static long g_fields;
static int g_values_only; /* DIFF_PLANT_VALUES_ONLY set: the bounds (*_err) are not compared */
static int cmp_arr(const char *what, const zw_real *a, const zw_real *b, unsigned n, long idx)
{
    unsigned i;
    if (g_values_only && (strstr(what, "_err") != NULL)) {
        return 0;
    }
    for (i = 0u; i < n; ++i) {
        ++g_fields;
        if (!same_bits(a[i], b[i])) {
            fprintf(stderr, "case %ld: %s[%u] old %.17g new %.17g\n", idx, what, i, (double)a[i],
                    (double)b[i]);
            return 1;
        }
    }
    return 0;
}

#define CMP(f, n) bad |= cmp_arr(#f, (const zw_real *)&a->f, (const zw_real *)&b->f, (n), idx)
static int cmp_plant(const zw_plant *a, const zw_plant *b, long idx)
{
    int bad = 0;
    const unsigned M = ZW_PLANT_MAX_ORDER;
    CMP(spec.delta, 1u); CMP(spec.kappa, 1u); CMP(spec.lambda, 1u);
    CMP(spec.delta_relerr, 1u); CMP(spec.kappa_relerr, 1u); CMP(spec.lambda_relerr, 1u);
    if (a->order != b->order) {
        fprintf(stderr, "case %ld: order %u vs %u\n", idx, a->order, b->order);
        bad = 1;
    }
    CMP(den, M + 1u); CMP(den_err, M + 1u); CMP(num, M); CMP(num_err, M);
    CMP(den_s, M + 1u); CMP(den_s_err, M + 1u); CMP(num_s, M); CMP(num_s_err, M);
    CMP(den_w, M + 1u); CMP(den_w_err, M + 1u);
    CMP(c.delta, 1u); CMP(c.e, 1u); CMP(c.c1, 1u); CMP(c.c2, 1u); CMP(c.d12, 1u); CMP(c.s, 1u);
    CMP(c.g, 1u); CMP(c.sigma, 1u); CMP(c.hs, 1u); CMP(c.delta_relerr, 1u);
    return bad;
}

static double garbage(void)
{
    static const double g[] = {NAN, INFINITY, -INFINITY, -1.0, -1e-30, 0.0625, 1e38, 1e300};
    return g[next_u64() % (sizeof g / sizeof g[0])];
}

static double pick_relerr(void)
{
    switch (next_u64() % 4u) {
    case 0: return 0.0;
    case 1: return log_uniform(1e-17, 1e-5);
    case 2: return (sizeof(zw_real) == sizeof(float)) ? 6.0 * 0x1p-24 : 6.0 * 0x1p-53;
    default: return log_uniform(1e-8, 0.06);
    }
}

static void random_spec(zw_plant_spec *s, long i)
{
    const unsigned kind = (unsigned)(next_u64() % 10u);
    s->delta = (next_u64() % 16u == 0u) ? 0.0 : log_uniform(1e-6, 1e3);
    s->kappa = (next_u64() % 8u == 0u) ? 0.0 : log_uniform(1e-9, 1e6);
    s->lambda = (next_u64() % 5u == 0u) ? 0.0 : log_uniform(1e-6, 1e4);
    s->delta_relerr = (zw_real)pick_relerr();
    s->kappa_relerr = (zw_real)pick_relerr();
    s->lambda_relerr = (zw_real)pick_relerr();
    if (kind == 1u) { /* near-critical damping: kappa ~ h^2 (w2 ~ 0) */
        const double h = 0.5 * (double)s->delta;
        s->kappa = (zw_real)(h * h * (1.0 + (unit() - 0.5) * ldexp(1.0, -(int)(next_u64() % 50u))));
    } else if (kind == 2u) { /* the lag meeting a pole: nu = -p_i */
        const double h = 0.5 * (double)s->delta, k = (double)s->kappa, w2 = h * h - k;
        double p = -h;
        if (w2 >= 0.0) {
            p = (next_u64() & 1u) ? -(h + sqrt(w2)) : -k / (h + sqrt(w2));
        }
        if (p < 0.0) {
            s->lambda = (zw_real)(-1.0 / p * (1.0 + (unit() - 0.5) * 1e-6 * (double)(next_u64() % 2u)));
        }
    } else if (kind == 3u) { /* garbage in one field */
        zw_real *f[6] = {&s->delta, &s->kappa, &s->lambda, &s->delta_relerr, &s->kappa_relerr,
                         &s->lambda_relerr};
        *f[next_u64() % 6u] = (zw_real)garbage();
    } else if (kind == 4u) { /* tiny and huge */
        s->delta = (zw_real)log_uniform(1e-30, 1e-6);
        s->kappa = (zw_real)log_uniform(1e-30, 1e-3);
        s->lambda = (zw_real)log_uniform(1e-30, 1e-3);
    } else if (kind == 5u) { /* the series' edges: h ~ 2, |w2| ~ 4, w2 ~ 1 */
        const double h = 2.0 * (1.0 + (unit() - 0.5) * 1e-3);
        s->delta = (zw_real)(2.0 * h);
        s->kappa = (zw_real)(h * h + ((next_u64() & 1u) ? 4.0 : -1.0) * (1.0 + (unit() - 0.5) * 1e-3));
    } else {
        /* plain random */
    }
    (void)i;
}

static int diff_plants(const lib *o, const lib *n, long count)
{
    long i, bad = 0;
    int st_diff = 0;
    long ok = 0, order3 = 0;
    for (i = 0; i < count; ++i) {
        zw_plant_spec s;
        zw_plant po, pn;
        zw_status so, sn;
        random_spec(&s, i);
        memset(&po, 0xA5, sizeof po);
        memset(&pn, 0x5A, sizeof pn);
        so = o->plant_init(&po, &s);
        sn = n->plant_init(&pn, &s);
        if (so != sn) {
            fprintf(stderr, "case %ld: status %d vs %d\n", i, (int)so, (int)sn);
            st_diff = 1;
        }
        if (cmp_plant(&po, &pn, i) != 0) {
            ++bad;
        }
        ok += (so == ZW_OK);
        order3 += (so == ZW_OK) && (po.order == 3u);
        /* spec aliasing out->spec: the same result */
        pn.spec = s;
        sn = n->plant_init(&pn, &pn.spec);
        if ((sn != so) || (cmp_plant(&po, &pn, i) != 0)) {
            fprintf(stderr, "case %ld: aliased spec differs\n", i);
            ++bad;
        }
    }
    printf("zw_plant_init: %ld specs (%ld ok, %ld order 3), %ld fields compared, %ld differ%s\n",
           count, ok, order3, g_fields, bad, st_diff ? ", statuses differ" : "");
    return (bad != 0) || st_diff;
}

static zw_box_loop_cell g_cells[2][1024];
static zw_box_loop_scratch g_scr[2];
static zw_loop_workspace g_ws[2];

static int same_verdict(const zw_box_loop_verdict *a, const zw_box_loop_verdict *b)
{
    return (a->stable == b->stable) && (a->decided == b->decided) && same_bits(a->m_worst, b->m_worst) &&
           same_bits(a->b_worst, b->b_worst) && (a->evals == b->evals) &&
           same_bits(a->k_worst, b->k_worst);
}

static int diff_boxes(const lib *o, const lib *n, long count)
{
    zw_box_loop_work wo, wn;
    long i, bad = 0, ok = 0, stable = 0, evals = 0;
    if ((o->work_init(&wo, g_cells[0], 1024u, &g_scr[0]) != ZW_OK) ||
        (n->work_init(&wn, g_cells[1], 1024u, &g_scr[1]) != ZW_OK)) {
        fprintf(stderr, "diff_plant: work init failed\n");
        return 1;
    }
    wo.max_evals = wn.max_evals = 400u;
    for (i = 0; i < count; ++i) {
        zw_plant_box box;
        zw_device_loop_spec spec;
        zw_box_loop_verdict vo, vn;
        zw_status so, sn;
        const double m = log_uniform(1e-5, 1.0), b = log_uniform(1e-4, 10.0), T = log_uniform(1e-4, 0.02);
        const double k = (next_u64() % 3u == 0u) ? 0.0 : log_uniform(1.0, 1e5);
        zw_real K, B;
        memset(&box, 0, sizeof box);
        memset(&spec, 0, sizeof spec);
        box.m_lo = (zw_real)m;
        box.m_hi = (zw_real)(m * (1.0 + 0.2 * unit()));
        box.b_lo = (zw_real)b;
        box.b_hi = (zw_real)(b * (1.0 + 0.2 * unit()));
        box.T = (zw_real)T;
        box.k_lo = (zw_real)k;
        box.k_hi = (zw_real)(k * (1.0 + 0.2 * unit()));
        if (next_u64() % 4u == 0u) {
            box.m_h_lo = (zw_real)(0.1 * m);
            box.m_h_hi = (zw_real)(0.15 * m);
            box.b_h_lo = (zw_real)(0.1 * b);
            box.b_h_hi = (zw_real)(0.2 * b);
            box.k_h_lo = (zw_real)(0.1 * k);
            box.k_h_hi = (zw_real)(0.2 * k);
        }
        spec.delay = (unsigned)(next_u64() % 3u);
        /* K around the ideal plant's b / T + m / T^2 scale (Colgate), B small */
        K = (zw_real)(log_uniform(1e-3, 10.0) * 2.0 * b / T);
        B = (zw_real)((next_u64() & 1u) ? 0.0 : 0.1 * b * unit());
        memset(&vo, 0xA5, sizeof vo);
        memset(&vn, 0x5A, sizeof vn);
        so = o->box_check(&box, &spec, &g_ws[0], K, B, &wo, &vo);
        sn = n->box_check(&box, &spec, &g_ws[1], K, B, &wn, &vn);
        if ((so != sn) || !same_verdict(&vo, &vn)) {
            fprintf(stderr, "box %ld: status %d/%d stable %d/%d decided %d/%d evals %lu/%lu\n", i,
                    (int)so, (int)sn, vo.stable, vn.stable, vo.decided, vn.decided,
                    (unsigned long)vo.evals, (unsigned long)vn.evals);
            ++bad;
        }
        ok += (so == ZW_OK);
        stable += (so == ZW_OK) && vo.stable;
        evals += (so == ZW_OK) ? (long)vo.evals : 0;
    }
    printf("zw_box_loop_check: %ld boxes (%ld ok, %ld stable, %ld sub-box tests), %ld differ\n", count, ok,
           stable, evals, bad);
    return bad != 0;
}

static int same_bound(const zw_box_loop_bound *a, const zw_box_loop_bound *b)
{
    return same_bits(a->K_lower, b->K_lower) && same_bits(a->K_upper, b->K_upper) &&
           same_bits(a->m_worst, b->m_worst) && same_bits(a->b_worst, b->b_worst) &&
           same_bits(a->k_worst, b->k_worst) && (a->evals == b->evals) && (a->converged == b->converged);
}

/* Boxes with and without stiffness and hand, every filter kind and differentiator, any
 * delay 0..2: the verdict and the K_max bound, every field bitwise (errors included). */
static int diff_filters(const lib *o, const lib *n, long count)
{
    zw_box_loop_work wo, wn;
    long i, bad = 0, ok = 0, stable = 0, stiff = 0;
    double k_lower = 0.0;
    if ((o->work_init(&wo, g_cells[0], 1024u, &g_scr[0]) != ZW_OK) ||
        (n->work_init(&wn, g_cells[1], 1024u, &g_scr[1]) != ZW_OK)) {
        fprintf(stderr, "diff_plant: work init failed\n");
        return 1;
    }
    wo.max_evals = wn.max_evals = 200u;
    for (i = 0; i < count; ++i) {
        zw_plant_box box;
        zw_device_loop_spec spec;
        zw_box_loop_verdict vo, vn;
        zw_box_loop_bound bo, bn;
        zw_status so, sn, ko, kn;
        const double m = log_uniform(1e-5, 1.0), b = log_uniform(1e-4, 10.0), T = log_uniform(1e-4, 0.02);
        const double k = (next_u64() % 2u == 0u) ? 0.0 : log_uniform(1.0, 1e5);
        zw_real K, B;
        memset(&box, 0, sizeof box);
        memset(&spec, 0, sizeof spec);
        box.m_lo = (zw_real)m;
        box.m_hi = (zw_real)(m * (1.0 + 0.2 * unit()));
        box.b_lo = (zw_real)b;
        box.b_hi = (zw_real)(b * (1.0 + 0.2 * unit()));
        box.T = (zw_real)T;
        box.k_lo = (zw_real)k;
        box.k_hi = (zw_real)(k * (1.0 + 0.2 * unit()));
        if (next_u64() % 3u == 0u) {
            box.m_h_lo = (zw_real)(0.1 * m);
            box.m_h_hi = (zw_real)(0.15 * m);
            box.b_h_lo = (zw_real)(0.1 * b);
            box.b_h_hi = (zw_real)(0.2 * b);
            box.k_h_lo = (zw_real)(0.1 * k);
            box.k_h_hi = (zw_real)(0.2 * k);
        }
        spec.delay = (unsigned)(next_u64() % 3u);
        spec.differentiator = (next_u64() & 1u) ? ZW_DIFF_TUSTIN : ZW_DIFF_BACKWARD;
        switch (next_u64() % 4u) {
        case 0u:
            spec.filter = ZW_VFILTER_NONE;
            break;
        case 1u:
            spec.filter = ZW_VFILTER_LOWPASS;
            spec.pole = (zw_real)(0.9 * unit());
            break;
        case 2u:
            spec.filter = ZW_VFILTER_LOWPASS;
            spec.cutoff_hz = (zw_real)(log_uniform(0.01, 0.4) / T);
            break;
        default:
            spec.filter = ZW_VFILTER_AVERAGE;
            spec.average = 1u + (unsigned)(next_u64() % 16u);
            break;
        }
        K = (zw_real)(log_uniform(1e-3, 10.0) * 2.0 * b / T);
        B = (zw_real)((next_u64() & 1u) ? 0.0 : 0.1 * b * unit());
        memset(&vo, 0xA5, sizeof vo);
        memset(&vn, 0x5A, sizeof vn);
        memset(&bo, 0xA5, sizeof bo);
        memset(&bn, 0x5A, sizeof bn);
        so = o->box_check(&box, &spec, &g_ws[0], K, B, &wo, &vo);
        sn = n->box_check(&box, &spec, &g_ws[1], K, B, &wn, &vn);
        ko = o->box_k_max(&box, &spec, &g_ws[0], B, &wo, &bo);
        kn = n->box_k_max(&box, &spec, &g_ws[1], B, &wn, &bn);
        if ((so != sn) || !same_verdict(&vo, &vn) || (ko != kn) || !same_bound(&bo, &bn)) {
            fprintf(stderr, "box %ld (filter %d average %u): check %d/%d stable %d/%d; k_max %d/%d K_lower %.17g/%.17g\n",
                    i, (int)spec.filter, spec.average, (int)so, (int)sn, vo.stable, vn.stable, (int)ko, (int)kn,
                    (double)bo.K_lower, (double)bn.K_lower);
            ++bad;
        }
        ok += (so == ZW_OK) && (ko == ZW_OK);
        stable += (so == ZW_OK) && vo.stable;
        stiff += (k > 0.0);
        k_lower += (ko == ZW_OK) ? (double)bo.K_lower : 0.0;
    }
    printf("zw_box_loop_check + _k_max, every filter: %ld boxes (%ld with stiffness, %ld both ok, %ld stable, "
           "sum of K_lower %.6g), %ld differ\n", count, stiff, ok, stable, k_lower, bad);
    return bad != 0;
}

int main(int argc, char **argv)
{
    lib o, n;
    long specs = 50000, boxes = 300;
    int bad;
    if (argc < 3) {
        fprintf(stderr, "usage: diff_plant OLD.so NEW.so [specs [boxes]]\n");
        return 2;
    }
    if (argc > 3) specs = atol(argv[3]);
    if (argc > 4) boxes = atol(argv[4]);
    g_values_only = (getenv("DIFF_PLANT_VALUES_ONLY") != NULL);
    o = load(argv[1]);
    n = load(argv[2]);
    bad = diff_plants(&o, &n, specs);
    bad |= diff_boxes(&o, &n, boxes);
    bad |= diff_filters(&o, &n, boxes);
    printf("%s\n", bad ? "DIFFER" : "identical");
    return bad ? 1 : 0;
}
