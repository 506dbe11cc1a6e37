/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Differential test of loop_limits.c (docs/eva.md): the code changes made for the Eva
 * analysis must not change any output.  Built twice, against the old and the new
 * loop_limits.c (the rest of the core the same), it prints every output bit of every
 * public function of loop_limits.h for the same pseudo-random cases; the two outputs must
 * be identical (diff).  Cases: loops built by zw_loop_init and zw_loop_init_plant from
 * random plants and specs (valid, and invalid specs), loops with a field overwritten by
 * garbage (NaN, infinities, huge, random bits), loops of random bytes; gains, angles and
 * the boundary kind random, NaN or infinite; the workspace filled with random bytes
 * before every call (loop.h: any contents).
 *
 *   usage: diff_loop_limits CASES SEED   (see docs/eva.md for the build lines)
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/coeffs.h"
#include "zwidth/loop.h"
#include "zwidth/loop_limits.h"
#include "zwidth/plant.h"

static uint64_t state;

static uint64_t next_u64(void)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
}

static double uniform(void) { return (double)(next_u64() >> 11) * 0x1.0p-53; }

static unsigned below(unsigned n) { return (unsigned)(next_u64() % n); }

/* A real: mostly in [lo, hi], sometimes garbage. */
static zw_real real_in(double lo, double hi)
{
    unsigned k = below(40u);
    zw_real r;
    uint64_t bits;
    switch (k) {
    case 0u: return (zw_real)NAN;
    case 1u: return (zw_real)INFINITY;
    case 2u: return -(zw_real)INFINITY;
    case 3u: return (zw_real)0.0;
    case 4u: return (zw_real)-1e30;
    case 5u:
        bits = next_u64();
        memcpy(&r, &bits, sizeof r);
        return r;
    default: return (zw_real)(lo + (hi - lo) * uniform());
    }
}

static void random_bytes(void *p, size_t n)
{
    unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; ++i) {
        b[i] = (unsigned char)next_u64();
    }
}

static void put(const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; ++i) {
        printf("%02x", b[i]);
    }
    putchar(' ');
}

static void put_real(zw_real x) { put(&x, sizeof x); }

static void make_loop(zw_loop *l)
{
    zw_loop_spec sp;
    unsigned kind = below(10u);
    memset(&sp, 0, sizeof sp);
    sp.delay = below(12u) == 0u ? below(20u) : below(4u);
    sp.differentiator = (zw_differentiator)(below(8u) == 0u ? (int)below(5u) - 1 : (int)below(2u));
    sp.filter = (zw_velocity_filter)(below(8u) == 0u ? (int)below(6u) - 1 : (int)below(3u));
    sp.filter_pole = real_in(0.0, 0.99);
    sp.average = below(10u) == 0u ? below(40u) : 1u + below(6u);
    if (kind == 0u) {
        random_bytes(l, sizeof *l);
        return;
    }
    if (kind <= 4u) {
        zw_coeffs c;
        (void)zw_coeffs_init(&c, real_in(0.0, 3.0));
        (void)zw_loop_init(l, &c, &sp);
    } else {
        zw_plant pl;
        zw_plant_spec ps;
        ps.delta = real_in(0.0, 3.0);
        ps.kappa = below(3u) == 0u ? (zw_real)0.0 : real_in(0.0, 2.0);
        ps.lambda = below(3u) == 0u ? (zw_real)0.0 : real_in(0.0, 3.0);
        ps.delta_relerr = (zw_real)0.0;
        ps.kappa_relerr = (zw_real)0.0;
        ps.lambda_relerr = (zw_real)0.0;
        (void)zw_plant_init(&pl, &ps);
        (void)zw_loop_init_plant(l, &pl, &sp);
    }
    if (below(8u) == 0u) { /* one garbage word somewhere in the loop */
        size_t at = below((unsigned)(sizeof *l / sizeof(zw_real))) * sizeof(zw_real);
        zw_real g = real_in(-10.0, 10.0);
        memcpy((unsigned char *)l + at, &g, sizeof g);
    }
}

int main(int argc, char **argv)
{
    static zw_loop l;
    static zw_loop_workspace ws;
    unsigned n = argc > 1 ? (unsigned)strtoul(argv[1], NULL, 10) : 1000u, i;
    state = argc > 2 ? strtoull(argv[2], NULL, 10) : 88172645463325252ull;
    if (state == 0u) {
        state = 1u;
    }
    for (i = 0; i < n; ++i) {
        zw_loop_beta_set set;
        zw_loop_extremes x;
        zw_real a, lo, hi, c0, ca, cb, g_alpha;
        bool ne;
        int st;
        make_loop(&l);
        printf("%u ", i);
        random_bytes(&ws, sizeof ws);
        a = (zw_real)-7.0;
        st = zw_loop_alpha_max(&l, &ws, real_in(-1.0, 3.0), &a);
        printf("%d ", st);
        put_real(a);
        /* the lines below: mostly inside the region (alpha below the alpha_max found) */
        g_alpha = (a > (zw_real)0.0 && below(4u) != 0u) ? a * (zw_real)uniform() : real_in(-0.5, 3.0);
        random_bytes(&ws, sizeof ws);
        memset(&set, 0x5a, sizeof set);
        st = zw_loop_beta_intervals(&l, &ws, g_alpha, &set);
        printf("%d ", st);
        put(&set, sizeof set);
        random_bytes(&ws, sizeof ws);
        lo = hi = (zw_real)-7.0;
        ne = true;
        st = zw_loop_beta_interval(&l, &ws, g_alpha, &lo, &hi, &ne);
        printf("%d %d ", st, (int)ne);
        put_real(lo);
        put_real(hi);
        if (below(4u) == 0u) { /* the costly one on every 4th case */
            random_bytes(&ws, sizeof ws);
            memset(&x, 0x5a, sizeof x);
            st = zw_loop_extremes_compute(&l, &ws, &x);
            printf("%d ", st);
            put(&x, sizeof x);
        }
        a = lo = (zw_real)-7.0;
        st = zw_loop_boundary_point(&l, real_in(0.0, 3.2), &a, &lo);
        printf("%d ", st);
        put_real(a);
        put_real(lo);
        c0 = ca = cb = (zw_real)-7.0;
        st = zw_loop_boundary_line(&l, (zw_loop_boundary)(int)below(6u), &c0, &ca, &cb);
        printf("%d ", st);
        put_real(c0);
        put_real(ca);
        put_real(cb);
        putchar('\n');
    }
    return 0;
}
