/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* zw_ref_box.h - long double references for the plant-box tests (test_box_loop.c,
 * test_box_cert.c): the ideal plant's coefficients from their literal formulas (delta >= 0.3,
 * where they lose little in long double) and the ideal loop's K_max(B) (eq (10)),
 * minimized over a grid of plants.  Independent of the library. */
#ifndef ZW_REF_BOX_H
#define ZW_REF_BOX_H

#include "zw_test.h"

typedef struct ref_plant {
    long double e, c1, c2, d12, s;
} ref_plant;

static inline ref_plant ref_at(long double d)
{
    ref_plant r;
    r.e = expl(-d);
    r.c1 = 2.0L * (d - 1.0L + r.e) / (d * d);
    r.c2 = 2.0L * (1.0L - r.e - d * r.e) / (d * d);
    r.d12 = 2.0L * ((d + 2.0L) * r.e + d - 2.0L) / (d * d);
    r.s = r.c1 + r.c2;
    return r;
}

/* K_max(B) of the ideal loop at one plant, long double (eq (10), literal formulas). */
static inline long double ideal_k_max_ref(long double m, long double b, long double T, long double B)
{
    long double d = b * T / m, beta = B * T / m, alpha, f, L;
    ref_plant r = ref_at(d);
    if (!(beta + d > 0.0L)) return 0.0L;
    f = (r.c1 + r.c2) * (beta + d) * (2.0L - r.c2 * beta) / ((r.c1 * beta + 2.0L) * r.c2);
    L = 4.0L * (1.0L + r.e) / r.d12 - 2.0L * beta;
    alpha = f < L ? f : L;
    if (alpha < 0.0L) alpha = 0.0L;
    return alpha * m / (T * T);
}

static inline long double ideal_grid_min(const zw_plant_box *box, long double B, int n)
{
    int i, j;
    long double least = INFINITY;
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            long double m = box->m_lo + (long double)(box->m_hi - box->m_lo) * i / (n - 1);
            long double b = box->b_lo + (long double)(box->b_hi - box->b_lo) * j / (n - 1);
            long double k = ideal_k_max_ref(m, b, box->T, B);
            if (k < least) least = k;
        }
    }
    return least;
}

#endif /* ZW_REF_BOX_H */
