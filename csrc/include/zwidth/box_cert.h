/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/box_cert.h - box certificates: the search on the host, the check on the drive
 * (docs/design/box-certificate.md; implemented in box_loop.c beside the search it records).
 *
 * A certificate proves a staircase of stiffness limits over the B range of a plant box:
 * step i claims that every K' in (0, K[i]] is stable at every B in [B[i], B[i+1]] for
 * every plant of the box, with the drive's loop (zw_device_loop_spec).  Its proof is, per
 * step, the preorder of a k-d tree over the cell box x (0, K[i]] x [B[i], B[i+1]] (x the
 * box's Kp range with stiffness): a node is 4 bits, 0 a leaf that must pass the same
 * guarded interval test as zw_box_loop_check's sub-boxes (Kharitonov over the outward
 * rounded interval polynomial), 1..5 a split at the midpoint of m, b, K, B or Kp (its two
 * children follow, left first).  zw_box_cert_verify walks it with no search, at most
 * ZW_BOX_CERT_MAX_LEAVES leaf tests, so its cost is bounded whatever the box; a forged or
 * damaged certificate either proves what it claims or is invalid, never more.
 *
 * zw_box_cert_build (host only: a search, unbounded on an MCU's scale) finds the levels by
 * bisection, each a depth-first certification within a leaf budget whose preorder is
 * recorded; every leaf is proven on its cell widened by ZW_BOX_CERT_WIDEN (relative) at
 * both ends, so a drive with a different libm (last-ulp differences of exp) still proves
 * the cell itself.  Build in the drive's precision (zwidth_f for a float drive): float
 * interval arithmetic is coarser than double, and a leaf proven in double may not pass in
 * float.
 */
#ifndef ZWIDTH_BOX_CERT_H
#define ZWIDTH_BOX_CERT_H

#include "zwidth/box.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ZW_BOX_CERT_MAX_STEPS 16u
#define ZW_BOX_CERT_MAX_LEAVES 512u
#define ZW_BOX_CERT_MAX_NODES 1024u            /* 2 x leaves, less one per step */
#define ZW_BOX_CERT_NODE_WORDS 256u            /* 4 nodes per 16-bit word */
/* On the wire and in the stored image (regmap_codec.h): n_steps, n_nodes, the 17
 * breakpoints and 16 levels as binary32 (two words each, high word first), the node words. */
#define ZW_BOX_CERT_WORDS 324u
#define ZW_BOX_CERT_WORD_B 2u                  /* first word of B[0] */
#define ZW_BOX_CERT_WORD_K 36u                 /* first word of K[0] */
#define ZW_BOX_CERT_WORD_NODES 68u             /* nodes[0] */
#define ZW_BOX_CERT_WIDEN ZW_R(6.103515625e-05) /* 2^-14 */

/* Node codes: a leaf, or the side a split halves. */
#define ZW_BOX_CERT_LEAF 0u
#define ZW_BOX_CERT_SPLIT_M 1u
#define ZW_BOX_CERT_SPLIT_BP 2u
#define ZW_BOX_CERT_SPLIT_K 3u
#define ZW_BOX_CERT_SPLIT_B 4u
#define ZW_BOX_CERT_SPLIT_KP 5u

/* The certificate, as on the wire (binary32 breakpoints and levels whatever zw_real is).
 * Node j is bits 4 (j mod 4) .. 4 (j mod 4) + 3 of nodes[j / 4]; nibbles and words past
 * n_nodes are 0.  Plain data: 648 bytes. */
typedef struct zw_box_cert {
    uint_least16_t n_steps, n_nodes;
    float B[ZW_BOX_CERT_MAX_STEPS + 1u];  /* breakpoints, strictly increasing */
    float K[ZW_BOX_CERT_MAX_STEPS];       /* levels, finite and > 0 */
    uint_least16_t nodes[ZW_BOX_CERT_NODE_WORDS];
} zw_box_cert;

/* Why a certificate is not valid (zw_box_cert_verify). */
typedef enum zw_box_cert_fault {
    ZW_BOX_CERT_OK = 0,
    ZW_BOX_CERT_BAD_HEADER = 1,   /* n_steps not 1..16, n_nodes not 1..1024 */
    ZW_BOX_CERT_BAD_STEP = 2,     /* a breakpoint not finite or not increasing, a level not
                                     finite or <= 0, a gain the box cannot normalize */
    ZW_BOX_CERT_BAD_NODE = 3,     /* a code above 5, or the nodes end inside a tree */
    ZW_BOX_CERT_BAD_SPLIT = 4,    /* a midpoint not strictly inside its cell, or a split that
                                     would hold more than ZW_BOX_CERT_STACK cells waiting */
    ZW_BOX_CERT_TOO_MANY = 5,     /* more than 512 leaves */
    ZW_BOX_CERT_UNUSED = 6,       /* nodes (or non-zero padding) left after the last tree */
    ZW_BOX_CERT_LEAF_FAILS = 7    /* a leaf's cell is not proven stable */
} zw_box_cert_fault;

/* The walk's stack never holds more cells than this (with the box_loop work's cells as the
 * stack: capacity at least this much). */
#define ZW_BOX_CERT_STACK 33u

/* Check cert for the box and loop: *fault ZW_BOX_CERT_OK when every claim is proven, else
 * the first fault found (then nothing of it may be used).  *leaves: leaf tests run.  Errors
 * (ZW_ERR_*): those of zw_box_loop_check's setup (box, spec), ZW_ERR_NULL, ZW_ERR_ARG (work's
 * capacity below ZW_BOX_CERT_STACK); *fault is then not OK either.  At most ZW_BOX_CERT_MAX_LEAVES interval tests and as many splits. */
zw_status zw_box_cert_verify(const zw_plant_box *box, const zw_device_loop_spec *spec,
                             const zw_box_cert *cert, const zw_box_loop_work *work,
                             zw_box_cert_fault *fault, uint_least32_t *leaves);

/* The certified level at B (a verified certificate): the step containing B, the larger
 * level on a breakpoint.  *inside false (and *K 0) when B is outside [B[0], B[n]]. */
void zw_box_cert_level(const zw_box_cert *cert, float B, float *K, bool *inside);

/* The widest run of steps around B whose levels are all >= K: [*B_lo, *B_hi]; *nonempty
 * false (ends NaN) when the step at B is below K or B is outside. */
void zw_box_cert_b_range(const zw_box_cert *cert, float K, float B, float *B_lo, float *B_hi,
                         bool *nonempty);

/* The highest level and the middle of its (first) step. */
void zw_box_cert_k_mmax(const zw_box_cert *cert, float *K, float *B);

/* What zw_box_cert_build found. */
typedef struct zw_box_cert_report {
    uint_least32_t tests;      /* interval tests of the whole search */
    uint_least32_t leaves;     /* leaves of the certificate */
    uint_least16_t failed_step;/* ZW_BOX_CERT_MAX_STEPS when every step got a level, else the
                                  first step that did not (then the certificate is empty) */
    zw_real K_upper[ZW_BOX_CERT_MAX_STEPS]; /* per step, the least point K_max found at its
                                  ends: the level cannot pass it */
} zw_box_cert_report;

/* Build a certificate of n_steps equal steps over [B_lo, B_hi] (B_lo < B_hi, both as
 * binary32; n_steps 1..16) with at most max_leaves (1..512) leaves, shared equally; each
 * level the highest a bisection to rel_tol finds provable in its share.  Host only.  ws:
 * the point checks' workspace; work: its cells (capacity >= ZW_BOX_CERT_STACK) and
 * scratch (its budget fields unused).
 * Errors: those of zw_box_loop_k_max, ZW_ERR_ARG (counts, range).  When a step cannot be
 * proven at any K (report->failed_step), *cert has n_steps 0 and the status is ZW_OK. */
zw_status zw_box_cert_build(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, float B_lo, float B_hi, unsigned n_steps,
                            unsigned max_leaves, zw_real rel_tol, const zw_box_loop_work *work,
                            zw_box_cert *cert, zw_box_cert_report *report);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_BOX_CERT_H */
