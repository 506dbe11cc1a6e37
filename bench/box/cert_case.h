/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/box/cert_case.h - one box of the Cortex-M4F box-certificate benchmark: the box, its
 * loop, the B range and the certificate the host built for it (bench/box/cert_gen.c writes
 * the table, bench/box/m4f_cert.c checks it on the drive and runs the register map with it
 * in force; tools/m4f_box_cert.sh runs both). */
#ifndef ZW_BENCH_CERT_CASE_H
#define ZW_BENCH_CERT_CASE_H

#include <stdbool.h>
#include <stdint.h>

#include "zwidth/zwidth.h"
#include "zwidth/box_cert.h"

#define CERT_CASE_LOOKUPS 5u

/* The register map's ranged block over a box (bench/box/m4f_cert.c, zw_regmap_init_box):
 * sigma, K range, K step; B range the certificate's [B[0], B[n]], B step its width. */
#define CERT_CASE_SIGMA 0.8f
#define CERT_CASE_K_MAX 10.0f
#define CERT_CASE_DK_MAX 1.0f

typedef struct cert_case {
    const char *name;
    zw_plant_box box;
    zw_device_loop_spec spec;
    float B_lo, B_hi;                /* the certificate's B range */
    zw_box_cert cert;                /* as zw_box_cert_build made it on the host */
    uint_least32_t host_tests;       /* interval tests of the host's search */
    uint_least32_t host_leaves;      /* leaves zw_box_cert_verify ran on the host */
    int host_fault;                  /* zw_box_cert_fault of the host's verify (0: OK) */
    float K_upper[ZW_BOX_CERT_MAX_STEPS]; /* report.K_upper (zw_real rounded to float) */
    unsigned corrupt_step;           /* the step whose level the corrupted copy doubles */
    float lookup_B[CERT_CASE_LOOKUPS];      /* zw_box_cert_level probes */
    float lookup_K[CERT_CASE_LOOKUPS];      /* the host's answers */
    bool lookup_inside[CERT_CASE_LOOKUPS];
} cert_case;

extern const cert_case cert_cases[];
extern const unsigned cert_n_cases;

#endif /* ZW_BENCH_CERT_CASE_H */
