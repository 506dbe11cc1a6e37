/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Box certificates in one precision (box_cert_glue.h): compiled once per precision. */
#define _POSIX_C_SOURCE 199309L
#include "box_cert_glue.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "zwidth/box_cert.h"

#ifdef ZW_REAL_FLOAT
#define ZWB(name) name##_f
#else
#define ZWB(name) name##_d
#endif

typedef struct glue_work {
    zw_box_loop_cell cells[ZW_BOX_CERT_STACK];
    zw_box_loop_scratch scratch;
    zw_loop_workspace ws;
    zw_box_loop_work work;
    zw_plant_box box;
    zw_device_loop_spec spec;
} glue_work;

static double seconds(void)
{
    struct timespec t;
    (void)clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static glue_work *glue_open(const zwb_box_args *a)
{
    glue_work *g = (glue_work *)calloc(1u, sizeof *g);
    zw_plant_box *b;
    if (g == NULL) {
        return NULL;
    }
    b = &g->box;
    b->m_lo = (zw_real)a->box[0];
    b->m_hi = (zw_real)a->box[1];
    b->b_lo = (zw_real)a->box[2];
    b->b_hi = (zw_real)a->box[3];
    b->T = (zw_real)a->box[4];
    b->k_lo = (zw_real)a->box[5];
    b->k_hi = (zw_real)a->box[6];
    b->m_h_lo = (zw_real)a->box[7];
    b->m_h_hi = (zw_real)a->box[8];
    b->b_h_lo = (zw_real)a->box[9];
    b->b_h_hi = (zw_real)a->box[10];
    b->k_h_lo = (zw_real)a->box[11];
    b->k_h_hi = (zw_real)a->box[12];
    b->tau_lo = (zw_real)a->box[13];
    b->tau_hi = (zw_real)a->box[14];
    g->spec.delay = a->delay;
    g->spec.average = a->average;
    g->spec.differentiator = (zw_differentiator)a->differentiator;
    g->spec.filter = (zw_velocity_filter)a->filter;
    if (g->spec.filter == ZW_VFILTER_LOWPASS) {
        if (a->pole_given != 0) {
            g->spec.pole = (zw_real)a->cutoff_or_pole;
        } else {
            g->spec.cutoff_hz = (zw_real)a->cutoff_or_pole;
        }
    }
    (void)zw_box_loop_work_init(&g->work, g->cells, ZW_BOX_CERT_STACK, &g->scratch);
    return g;
}

int ZWB(zwb_box_cert_build)(const zwb_box_args *a, float B_lo, float B_hi, unsigned steps, unsigned leaves,
                            double rel_tol, zw_box_cert *cert, zwb_box_cert_result *out)
{
    glue_work *g = glue_open(a);
    zw_box_cert_report r;
    zw_box_cert_fault fault = ZW_BOX_CERT_BAD_HEADER;
    uint_least32_t verified = 0u;
    double t0;
    unsigned i;
    memset(out, 0, sizeof *out);
    if (g == NULL) {
        return -1;
    }
    t0 = seconds();
    out->status = (int)zw_box_cert_build(&g->box, &g->spec, &g->ws, B_lo, B_hi, steps, leaves, (zw_real)rel_tol,
                                         &g->work, cert, &r);
    out->build_seconds = seconds() - t0;
    out->failed_step = r.failed_step;
    out->tests = r.tests;
    out->leaves = r.leaves;
    for (i = 0u; i < 16u; ++i) {
        out->K_upper[i] = (double)r.K_upper[i];
    }
    t0 = seconds();
    out->verify_status = (int)zw_box_cert_verify(&g->box, &g->spec, cert, &g->work, &fault, &verified);
    out->verify_seconds = seconds() - t0;
    out->fault = (int)fault;
    out->verify_leaves = verified;
    free(g);
    return 0;
}

int ZWB(zwb_box_cert_range)(const zwb_box_args *a, double *B_lo, double *B_hi)
{
    glue_work *g = glue_open(a);
    zw_box_loop_cell *cells = (zw_box_loop_cell *)calloc(ZWB_RANGE_CELLS, sizeof *cells);
    zw_box_loop_work work;
    zw_box_loop_extremes e;
    zw_real lo = ZW_R(0.0), hi = ZW_R(0.0);
    bool nonempty = false;
    int rc = -1;
    if ((g != NULL) && (cells != NULL) &&
        (zw_box_loop_work_init(&work, cells, ZWB_RANGE_CELLS, &g->scratch) == ZW_OK)) {
        zw_status st;
        work.max_evals = 100000u; /* the host's default (python/zwidth/box.py) */
        st = zw_box_loop_k_mmax(&g->box, &g->spec, &g->ws, &work, &e);
        if (st == ZW_OK) {
            st = zw_box_loop_b_range(&g->box, &g->spec, &g->ws, ZW_R(0.5) * e.K_mmax, &work, &lo, &hi,
                                     &nonempty);
        }
        rc = (st != ZW_OK) ? (int)st : nonempty ? 0 : -2;
        *B_lo = (double)lo;
        *B_hi = (double)hi;
    }
    free(cells);
    free(g);
    return rc;
}

int ZWB(zwb_box_cert_verify)(const zwb_box_args *a, const zw_box_cert *cert, int *fault, unsigned long *leaves)
{
    glue_work *g = glue_open(a);
    zw_box_cert_fault f = ZW_BOX_CERT_BAD_HEADER;
    uint_least32_t n = 0u;
    int st;
    if (g == NULL) {
        return -1;
    }
    st = (int)zw_box_cert_verify(&g->box, &g->spec, cert, &g->work, &f, &n);
    *fault = (int)f;
    *leaves = n;
    free(g);
    return st;
}
