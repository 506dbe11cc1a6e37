/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* box_cert_glue.h - box certificates in either precision for the bindings.
 *
 * A drive checks its certificate in its own precision, so the host must build it there
 * (box_cert.h): box_cert_glue.c is compiled twice, against zwidth_d (suffix _d) and against
 * zwidth_f (ZW_REAL_FLOAT, suffix _f), behind one precision-free interface of doubles.
 * zw_box_cert itself has no zw_real in it. */
#ifndef ZW_BOX_CERT_GLUE_H
#define ZW_BOX_CERT_GLUE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct zw_box_cert;

/* The box (zw_plant_box's fields in order: m, b ranges, T, k_p, the hand's m, b, k, tau) and
 * the loop (zw_device_loop_spec's codes; cutoff_or_pole a cut-off in Hz or, pole_given, the
 * pole). */
typedef struct zwb_box_args {
    double box[15];
    unsigned delay, average;
    int differentiator, filter, pole_given;
    double cutoff_or_pole;
} zwb_box_args;

typedef struct zwb_box_cert_result {
    int status;                /* zw_status of the build */
    unsigned failed_step;      /* ZW_BOX_CERT_MAX_STEPS when every step got a level */
    unsigned long tests, leaves;
    double K_upper[16];
    int verify_status, fault;  /* zw_box_cert_verify of what was built */
    unsigned long verify_leaves;
    double build_seconds, verify_seconds;
} zwb_box_cert_result;

/* Build and then verify; 0, or -1 when memory for the work could not be had. */
int zwb_box_cert_build_d(const zwb_box_args *a, float B_lo, float B_hi, unsigned steps, unsigned leaves,
                         double rel_tol, struct zw_box_cert *cert, zwb_box_cert_result *out);
int zwb_box_cert_build_f(const zwb_box_args *a, float B_lo, float B_hi, unsigned steps, unsigned leaves,
                         double rel_tol, struct zw_box_cert *cert, zwb_box_cert_result *out);
/* certificate()'s default B range: the B certified over the box at half its K_mmax
 * (zw_box_loop_k_mmax, zw_box_loop_b_range; the host's search defaults, a work list of
 * ZWB_RANGE_CELLS).  0 with *B_lo, *B_hi set; a zw_status (> 0) when a search fails,
 * -1 when memory could not be had, -2 when no B is certified there. */
#define ZWB_RANGE_CELLS 65536u
int zwb_box_cert_range_d(const zwb_box_args *a, double *B_lo, double *B_hi);
int zwb_box_cert_range_f(const zwb_box_args *a, double *B_lo, double *B_hi);
/* Verify only: *fault (zw_box_cert_fault), the status returned. */
int zwb_box_cert_verify_d(const zwb_box_args *a, const struct zw_box_cert *cert, int *fault, unsigned long *leaves);
int zwb_box_cert_verify_f(const zwb_box_args *a, const struct zw_box_cert *cert, int *fault, unsigned long *leaves);

#ifdef __cplusplus
}
#endif

#endif /* ZW_BOX_CERT_GLUE_H */
