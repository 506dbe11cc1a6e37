/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Cost of a gain write under a ranged block (map version 4), on the host.
 *
 * For a few plant boxes it times SEAL (zw_regmap_init: validation, the box's K_mmax, the
 * ONLY_OFF probe) and single gain writes through zw_regmap_write (the certification and,
 * when B changes, the live K_MAX / K_CERT refresh), and counts the sub-box tests of the
 * certification itself by repeating it with zw_box_loop_check under the map's own budget
 * (ZW_REGMAP_BOX_EVALS, ZW_REGMAP_BOX_CELLS, ZW_REGMAP_BOX_REL_TOL).
 *
 *   cmake --build build -j2
 *   cc -std=c99 -O2 -Icsrc/include bench/modbus/bench_regmap_box.c build/libzwidth_d.a -lm \
 *      -o build/bench_regmap_box && build/bench_regmap_box
 * (float: -DZW_REAL_FLOAT and build/libzwidth_f.a)
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "zwidth/regmap.h"

static zw_regmap g_rm;
static zw_box_loop_cell g_cells[ZW_REGMAP_BOX_CELLS];
static zw_box_loop_scratch g_scratch;
static zw_loop_workspace g_ws;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct box_case {
    const char *name;
    float m, m_hi, b, b_hi, T, sigma;
    float delay;
    float B; /* the B the writes use */
} box_case;

/* The sub-box tests the write's certification costs (its own proof, at K / sigma). */
static unsigned long cert_evals(const box_case *bc, float K, int *outcome)
{
    zw_plant_box box;
    zw_device_loop_spec spec;
    zw_box_loop_work work;
    zw_box_loop_verdict v;
    memset(&box, 0, sizeof box);
    memset(&spec, 0, sizeof spec);
    box.m_lo = bc->m;
    box.m_hi = bc->m_hi;
    box.b_lo = bc->b;
    box.b_hi = bc->b_hi;
    box.T = bc->T;
    spec.delay = (unsigned)bc->delay;
    (void)zw_box_loop_work_init(&work, g_cells, ZW_REGMAP_BOX_CELLS, &g_scratch);
    work.max_evals = ZW_REGMAP_BOX_EVALS;
    work.rel_tol = ZW_REGMAP_BOX_REL_TOL;
    (void)zw_box_loop_check(&box, &spec, &g_ws, (zw_real)(K / bc->sigma), (zw_real)bc->B, &work, &v);
    *outcome = v.stable ? 1 : (v.decided ? -1 : 0);
    return (unsigned long)v.evals;
}

static void write_pair(float K, float B, zw_reason *why)
{
    uint_least16_t w[4];
    zw_float_to_words(K, &w[0]);
    zw_float_to_words(B, &w[2]);
    (void)zw_regmap_write(&g_rm, ZW_REG_K, 4u, w, why);
}

static float live(uint_least16_t addr)
{
    uint_least16_t w[2];
    (void)zw_regmap_read(&g_rm, addr, 2u, w, NULL);
    return zw_words_to_float(w);
}

static void run(const box_case *bc)
{
    zw_cert c;
    zw_reason why = ZW_REASON_NONE;
    double t0, t_seal, kmax;
    static const double frac[] = {0.5, 0.9, 0.98, 0.99, 0.999, 1.0005, 1.05, -1.0}; /* -1: K_CERT */
    unsigned i;
    memset(&c, 0, sizeof c);
    c.m = bc->m;
    c.m_hi = bc->m_hi;
    c.b = bc->b;
    c.b_hi = bc->b_hi;
    c.T = bc->T;
    c.sigma = bc->sigma;
    c.r = 1.0f;
    c.k_min = 0.0f;
    c.k_max = 100.0f;
    c.b_min = -0.01f;
    c.b_max = 0.01f;
    c.dk_max = 100.0f;
    c.db_max = 0.01f;
    c.delay = bc->delay;
    t0 = now_s();
    (void)zw_regmap_init(&g_rm, &c, &why);
    t_seal = now_s() - t0;
    printf("\n%s: m [%g, %g], b [%g, %g], T %g, sigma %g, delay %g\n", bc->name, (double)c.m,
           (double)c.m_hi, (double)c.b, (double)c.b_hi, (double)c.T, (double)c.sigma, (double)c.delay);
    printf("  SEAL (init): %s, %.1f ms; K_MMAX %.6g at B %.6g\n", zw_reason_name(why), 1e3 * t_seal,
           (double)live(ZW_REG_LIVE_K_MMAX), (double)live(ZW_REG_LIVE_B_AT_KMMAX));
    if (why != ZW_REASON_NONE) return;
    /* move to B with a small K (a write that changes B also refreshes K_MAX: timed) */
    t0 = now_s();
    write_pair(0.1f * live(ZW_REG_LIVE_K_CERT), bc->B, &why);
    printf("  write (0.1 K_CERT, B = %g), B changes: %s, %.2f ms (certification + live K_MAX at "
           "the new B)\n", (double)bc->B, zw_reason_name(why), 1e3 * (now_s() - t0));
    kmax = (double)live(ZW_REG_LIVE_K_MAX);
    printf("  K_MAX(B) %.7g (box lower bound), K_CERT %.7g\n", kmax, (double)live(ZW_REG_LIVE_K_CERT));
    printf("  | K / (sigma K_MAX) | verdict | sub-box tests (certification) | time per write, B kept |\n");
    for (i = 0; i < sizeof frac / sizeof frac[0]; ++i) {
        const float K = frac[i] < 0.0 ? live(ZW_REG_LIVE_K_CERT) : (float)(frac[i] * (double)bc->sigma * kmax);
        int outcome = 0;
        const unsigned long evals = cert_evals(bc, K, &outcome);
        double t = 0.0;
        unsigned rep;
        for (rep = 0; rep < 5u; ++rep) { /* the same write 5 times, B unchanged: K_MAX cached */
            t0 = now_s();
            write_pair(K, bc->B, &why);
            t += now_s() - t0;
        }
        if (frac[i] < 0.0) printf("  K_CERT:\n");
        printf("  | %-5g | %-22s | %5lu (%s) | %.2f ms |\n", frac[i], zw_reason_name(why), evals,
               outcome > 0 ? "proven" : (outcome < 0 ? "refuted" : "budget spent"), 1e3 * t / 5.0);
    }
}

int main(void)
{
    static const box_case cases[] = {
        {"paper drive, m and b +-5 %", 0.95f * 85.78e-7f, 1.05f * 85.78e-7f, 0.95f * 2.197e-3f,
         1.05f * 2.197e-3f, 0.02f, 0.8f, 0.0f, -1.0e-3f},
        {"interior minimum in m (K_max not monotone)", 2.0e-5f, 1.5e-4f, 2.197e-3f, 2.197e-3f, 0.02f,
         1.0f, 0.0f, 1.0e-3f},
        {"paper drive +-5 %, delay 1", 0.95f * 85.78e-7f, 1.05f * 85.78e-7f, 0.95f * 2.197e-3f,
         1.05f * 2.197e-3f, 0.02f, 0.8f, 1.0f, -5.0e-4f},
    };
    unsigned i;
    printf("zwidth regmap, ranged blocks: budget %u sub-box tests per certification, %u cells, "
           "rel_tol %g, %s zw_real\n", ZW_REGMAP_BOX_EVALS, ZW_REGMAP_BOX_CELLS,
           (double)ZW_REGMAP_BOX_REL_TOL, sizeof(zw_real) == sizeof(float) ? "float" : "double");
    printf("sizeof(zw_regmap) = %lu bytes\n", (unsigned long)sizeof(zw_regmap));
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) run(&cases[i]);
    return 0;
}
