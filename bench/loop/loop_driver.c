/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* Timing and callgrind driver for zw_loop_check (bench/loop/bench_loop.py builds and runs
 * it).  Usage: loop_driver delta delay diff(0/1) filter(0/1/2) pole average n_points
 * alpha_hi beta_lo beta_hi [fast]  (fast: zw_loop_is_stable instead of zw_loop_check).  Prints "ns_per_call stable_fraction marginal_fraction ns_per_stable_call". */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "zwidth/zwidth.h"

static zw_loop g_loop; /* large: static, like a drive would keep it */
static zw_loop_workspace g_ws; /* the checks' scratch (loop.h) */

int main(int argc, char **argv)
{
    zw_coeffs c;
    zw_loop_spec spec;
    zw_loop_verdict v;
    unsigned n, i, stable = 0u, marginal = 0u, seed = 1u;
    double ahi, blo, bhi, t0, t1;
    struct timespec ts;
    static zw_real alphas[200000], betas[200000];
    static unsigned char verdict[200000];
    int fast;
    if (argc != 11 && argc != 12) return 2;
    fast = argc == 12;
    if (zw_coeffs_init(&c, (zw_real)atof(argv[1])) != ZW_OK) return 3;
    spec.delay = (unsigned)atoi(argv[2]);
    spec.differentiator = (zw_differentiator)atoi(argv[3]);
    spec.filter = (zw_velocity_filter)atoi(argv[4]);
    spec.filter_pole = (zw_real)atof(argv[5]);
    spec.average = (unsigned)atoi(argv[6]);
    n = (unsigned)atoi(argv[7]);
    if (n > 200000u) n = 200000u;
    ahi = atof(argv[8]);
    blo = atof(argv[9]);
    bhi = atof(argv[10]);
    if (zw_loop_init(&g_loop, &c, &spec) != ZW_OK) return 4;
    for (i = 0; i < n; ++i) {
        seed = seed * 1103515245u + 12345u;
        alphas[i] = (zw_real)((double)(seed >> 8) / 16777216.0 * ahi);
        seed = seed * 1103515245u + 12345u;
        betas[i] = (zw_real)(blo + (double)(seed >> 8) / 16777216.0 * (bhi - blo));
    }
    clock_gettime(CLOCK_MONOTONIC, &ts);
    t0 = (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
    for (i = 0; i < n; ++i) {
        if (fast) {
            bool s = false;
            if (zw_loop_is_stable(&g_loop, &g_ws, alphas[i], betas[i], &s) != ZW_OK) return 5;
            v.stable = s;
            v.marginal = false;
        } else if (zw_loop_check(&g_loop, &g_ws, alphas[i], betas[i], &v) != ZW_OK) {
            return 5;
        }
        stable += v.stable ? 1u : 0u;
        marginal += v.marginal ? 1u : 0u;
        verdict[i] = v.stable ? 1 : 0;
    }
    clock_gettime(CLOCK_MONOTONIC, &ts);
    t1 = (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
    /* the stable points alone (a drive's usual query: "is this gain safe?") */
    {
        unsigned ns = 0u;
        double t2, t3;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        t2 = (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
        for (i = 0; i < n; ++i)
            if (verdict[i]) {
                if (fast) {
                    bool s;
                    (void)zw_loop_is_stable(&g_loop, &g_ws, alphas[i], betas[i], &s);
                } else {
                    (void)zw_loop_check(&g_loop, &g_ws, alphas[i], betas[i], &v);
                }
                ns++;
            }
        clock_gettime(CLOCK_MONOTONIC, &ts);
        t3 = (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
        printf("%.1f %.4f %.6f %.1f\n", (t1 - t0) / n, (double)stable / n, (double)marginal / n,
               ns ? (t3 - t2) / ns : 0.0);
    }
    return 0;
}
