/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */
/* Per-point cost of zw_sweep_check_many built four ways (sweep_isa.sh links them side by
 * side): a baseline revision, portable, AVX2, AVX-512.  Thread CPU time (other load on
 * the machine does not count), the variants interleaved, best of REPEATS; points in
 * cache, delta log-uniform in [lo, hi] (arguments), alpha in (0, 2), beta in (-delta, delta).
 * Also counts the verdicts that differ from the first variant's (expected: 0). */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N 20000
#define REPEATS 300
#define VARIANTS 4

typedef int (*check_many)(size_t, const double *, ptrdiff_t, const double *, ptrdiff_t, const double *,
                          ptrdiff_t, bool *, size_t *);
int v_base(size_t, const double *, ptrdiff_t, const double *, ptrdiff_t, const double *, ptrdiff_t, bool *, size_t *);
int v_portable(size_t, const double *, ptrdiff_t, const double *, ptrdiff_t, const double *, ptrdiff_t, bool *,
               size_t *);
int v_avx2(size_t, const double *, ptrdiff_t, const double *, ptrdiff_t, const double *, ptrdiff_t, bool *, size_t *);
int v_avx512(size_t, const double *, ptrdiff_t, const double *, ptrdiff_t, const double *, ptrdiff_t, bool *,
             size_t *);

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    static double d[N], a[N], b[N];
    static bool s[VARIANTS][N];
    const check_many f[VARIANTS] = {v_base, v_portable, v_avx2, v_avx512};
    const char *name[VARIANTS] = {"baseline", "portable", "AVX2", "AVX-512"};
    double best[VARIANTS] = {1e9, 1e9, 1e9, 1e9};
    const double lo = argc > 2 ? atof(argv[1]) : 1e-3, hi = argc > 2 ? atof(argv[2]) : 20.0;
    size_t i, differ[VARIANTS] = {0};
    int r, k;
    srand(1);
    for (i = 0; i < N; ++i) {
        const double u = rand() / (double)RAND_MAX;
        d[i] = exp(log(lo) + u * (log(hi) - log(lo)));
        a[i] = 2.0 * rand() / (double)RAND_MAX;
        b[i] = d[i] * (2.0 * rand() / (double)RAND_MAX - 1.0);
    }
    for (r = 0; r < REPEATS; ++r) {
        for (k = 0; k < VARIANTS; ++k) {
            const double t0 = cpu_now();
            if (f[k](N, d, 1, a, 1, b, 1, s[k], NULL) != 0) return 1;
            const double t = cpu_now() - t0;
            best[k] = t < best[k] ? t : best[k];
        }
    }
    for (k = 0; k < VARIANTS; ++k) {
        for (i = 0; i < N; ++i) differ[k] += s[k][i] != s[0][i];
    }
    printf("delta in [%g, %g], %d points, best of %d, ns a point (CPU):", lo, hi, N, REPEATS);
    for (k = 0; k < VARIANTS; ++k) printf("  %s %.1f (%zu differ)", name[k], best[k] * 1e9 / N, differ[k]);
    printf("\n");
    return 0;
}
