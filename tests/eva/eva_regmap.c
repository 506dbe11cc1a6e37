/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of the register
 * map, with every input unconstrained, on any sequence of requests.
 *
 * eva-modules: regmap regmap_codec regmap_policy regmap_commission regmap_persist
 * eva-support: status
 * eva-defines: -DZW_REGMAP_NO_C11_ATOMICS
 * eva-precision: 1
 * eva-options: -eva-auto-loop-unroll 50
 *
 * The map's calls into the ideal core (device.h, selftest.h) and the general loop
 * (device_loop.h) are replaced by the stubs below, which their own drivers (eva_ideal.c,
 * eva_loop.c) justify: each writes every output of the real function, any value of its
 * type on success and the fail-safe value of its header on error, and returns any status.
 * So the analysis covers the map with any behaviour those contracts allow, and nothing
 * inside the core or the loop.
 *
 * A read of a volatile is any value of its type (NaN and infinities included).  The map is
 * initialized by zw_regmap_init with any block (or none), then configured with any
 * ceilings, hooks, word order and stored images, and then handles any number of requests
 * (a loop Eva runs to its fixpoint): PDUs of any length up to the Modbus maximum with any
 * bytes, register reads and writes of any address and quantity, gain and state exchanges,
 * and the configuration calls again.  After every call every output is read.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/box.h"
#include "zwidth/device.h"
#include "zwidth/device_loop.h"
#include "zwidth/regmap.h"
#include "zwidth/regmap_codec.h"
#include "zwidth/regmap_commission.h"
#include "zwidth/regmap_persist.h"
#include "zwidth/regmap_policy.h"
#include "zwidth/selftest.h"
#include "zwidth/status.h"
#include "regmap_internal.h"

volatile zw_real any_real_source;
volatile float any_float_source;
volatile int any_int_source;
volatile unsigned any_unsigned_source;
volatile uint_least8_t any_byte_source;
volatile uint_least16_t any_word_source;
volatile uint_least32_t any_u32_source;
volatile size_t any_size_source;

volatile zw_real sink_real;
volatile float sink_float;
volatile int sink_int;
volatile unsigned sink_unsigned;
volatile size_t sink_size;
volatile const char *sink_name;

static zw_real any_real(void) { return any_real_source; }
static float any_float(void) { return any_float_source; }
static bool any_bool(void) { return any_int_source != 0; }

/* Any size in [0, max]. */
static size_t any_size_upto(size_t max)
{
    size_t n = any_size_source;
    return n <= max ? n : max;
}

#define maybe_null(p) (any_bool() ? (p) : NULL)

/* ---- the general loop: stubs with the contract of device_loop.h ---------------------- */

static zw_status any_error(void)
{
    int s = any_int_source;
    return s == 0 ? ZW_ERR_ARG : (zw_status)s;
}

zw_status zw_device_loop_init(zw_device_loop *out, zw_real m, zw_real b, zw_real T,
                              const zw_device_loop_spec *spec)
{
    unsigned d = any_unsigned_source;
    (void)m;
    (void)b;
    (void)T;
    if (out == NULL || spec == NULL) {
        return ZW_ERR_NULL;
    }
    /* the plant: any values (NaN on error in the real one: included) */
    out->dev.m = any_real();
    out->dev.b = any_real();
    out->dev.T = any_real();
    out->dev.k_scale = any_real();
    out->dev.b_scale = any_real();
    out->dev.co.delta = any_real();
    out->dev.co.e = any_real();
    out->dev.co.c1 = any_real();
    out->dev.co.c2 = any_real();
    out->dev.co.d12 = any_real();
    out->dev.co.s = any_real();
    out->dev.co.g = any_real();
    out->dev.co.sigma = any_real();
    out->dev.co.hs = any_real();
    out->dev.co.delta_relerr = any_real();
    /* the loop: the spec's kinds (an empty loop on error), the pole any value */
    out->loop.spec.delay = d <= ZW_LOOP_MAX_DELAY ? d : 0u;
    out->loop.spec.differentiator = spec->differentiator;
    out->loop.spec.filter = spec->filter;
    out->loop.spec.filter_pole = any_real();
    out->loop.spec.average = spec->average;
    out->mass_relerr = any_real();
    return any_bool() ? ZW_OK : any_error();
}

zw_status zw_device_loop_check(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real K,
                               zw_real B, zw_loop_verdict *out)
{
    (void)dl;
    (void)ws;
    (void)K;
    (void)B;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->stable = false; /* fail-safe, and not stable: any verdict below */
    out->marginal = any_bool();
    out->deciding = ZW_LOOP_BOUNDARY_NONE;
    out->theta = any_real();
    if (any_bool()) {
        return any_error();
    }
    out->stable = any_bool();
    return ZW_OK;
}

zw_status zw_device_loop_radius_within(const zw_device_loop *dl, zw_loop_workspace *ws,
                                       zw_real K, zw_real B, zw_real r, bool *within)
{
    (void)dl;
    (void)ws;
    (void)K;
    (void)B;
    (void)r;
    if (within == NULL) {
        return ZW_ERR_NULL;
    }
    *within = false;
    if (any_bool()) {
        return any_error();
    }
    *within = any_bool();
    return ZW_OK;
}

zw_status zw_device_loop_spectral_radius(const zw_device_loop *dl, zw_loop_workspace *ws,
                                         zw_real K, zw_real B, zw_real *rho, zw_real *theta)
{
    (void)dl;
    (void)ws;
    (void)K;
    (void)B;
    if (rho == NULL || theta == NULL) {
        return ZW_ERR_NULL;
    }
    *rho = any_real();
    *theta = any_real();
    return any_bool() ? ZW_OK : any_error();
}

zw_status zw_device_loop_k_max(const zw_device_loop *dl, zw_loop_workspace *ws, zw_real B,
                               zw_real *K_max)
{
    zw_real k = any_real();
    (void)dl;
    (void)ws;
    (void)B;
    if (K_max == NULL) {
        return ZW_ERR_NULL;
    }
    *K_max = ZW_R(0.0);
    if (any_bool()) {
        return any_error();
    }
    *K_max = k >= ZW_R(0.0) ? k : ZW_R(0.0); /* 0 or more, +inf included */
    return ZW_OK;
}

zw_status zw_device_loop_extremes_compute(const zw_device_loop *dl, zw_loop_workspace *ws,
                                          zw_device_loop_extremes *out)
{
    (void)dl;
    (void)ws;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->K_mmax = ZW_R(0.0);
    out->B_at_K_mmax = ZW_R(0.0);
    out->K_p_max = ZW_R(0.0);
    out->B_mmax = ZW_R(0.0);
    out->B_mmin = ZW_R(0.0);
    if (any_bool()) {
        return any_error();
    }
    out->K_mmax = any_real();
    out->B_at_K_mmax = any_real();
    out->K_p_max = any_real();
    out->B_mmax = any_real();
    out->B_mmin = any_real();
    return ZW_OK;
}

/* ---- the ideal core: stubs with the contracts of device.h and selftest.h ---------------
 * The same treatment as the general loop's above: eva_ideal.c analyses the real functions
 * (no run-time error for any input, every output written on every return); here each
 * writes every output, any value of its type on success and the fail-safe value of its
 * header on error, and returns any status.  Analysing the real ones again under every
 * state of the map took most of this analysis's time (docs/eva.md). */

zw_status zw_device_check(const zw_device *d, zw_real K, zw_real B, zw_verdict *out)
{
    (void)d;
    (void)K;
    (void)B;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->stable = false;
    out->marginal = false;
    out->deciding = ZW_BOUND_NONE;
    out->violated = 0u;
    if (any_bool()) {
        return any_error();
    }
    out->stable = any_bool();
    out->marginal = any_bool();
    out->deciding = (zw_bound)any_int_source;
    out->violated = (uint_least16_t)any_unsigned_source;
    return ZW_OK;
}

zw_status zw_device_radius_within(const zw_device *d, zw_real K, zw_real B, zw_real r,
                                  bool *within)
{
    (void)d;
    (void)K;
    (void)B;
    (void)r;
    if (within == NULL) {
        return ZW_ERR_NULL;
    }
    *within = false;
    if (any_bool()) {
        return any_error();
    }
    *within = any_bool();
    return ZW_OK;
}

zw_status zw_device_spectral_radius(const zw_device *d, zw_real K, zw_real B, zw_real *rho)
{
    (void)d;
    (void)K;
    (void)B;
    if (rho == NULL) {
        return ZW_ERR_NULL;
    }
    *rho = any_real();
    return any_bool() ? ZW_OK : any_error();
}

zw_status zw_device_k_max(const zw_device *d, zw_real B, zw_real *K_max)
{
    zw_real k = any_real();
    (void)d;
    (void)B;
    if (K_max == NULL) {
        return ZW_ERR_NULL;
    }
    *K_max = ZW_R(0.0);
    if (any_bool()) {
        return any_error();
    }
    *K_max = k >= ZW_R(0.0) ? k : ZW_R(0.0); /* 0 or more, +inf included */
    return ZW_OK;
}

zw_status zw_device_b_range(const zw_device *d, zw_real K, zw_real *B_lo, zw_real *B_hi,
                            bool *nonempty)
{
    (void)d;
    (void)K;
    if ((B_lo == NULL) || (B_hi == NULL) || (nonempty == NULL)) {
        return ZW_ERR_NULL;
    }
    *B_lo = ZW_R(0.0);
    *B_hi = ZW_R(0.0);
    *nonempty = false;
    if (any_bool()) {
        return any_error();
    }
    *B_lo = any_real();
    *B_hi = any_real();
    *nonempty = any_bool();
    return ZW_OK;
}

zw_status zw_device_extremes_compute(const zw_device *d, zw_device_extremes *out)
{
    (void)d;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->K_mmax = ZW_R(0.0);
    out->B_at_K_mmax = ZW_R(0.0);
    out->at_corner = false;
    out->K_p_max = ZW_R(0.0);
    out->B_mmax = ZW_R(0.0);
    out->B_mmin = ZW_R(0.0);
    out->K_mmin = ZW_R(0.0);
    if (any_bool()) {
        return any_error();
    }
    out->K_mmax = any_real();
    out->B_at_K_mmax = any_real();
    out->at_corner = any_bool();
    out->K_p_max = any_real();
    out->B_mmax = any_real();
    out->B_mmin = any_real();
    return ZW_OK;
}

zw_status zw_selftest(void)
{
    return any_bool() ? ZW_OK : any_error();
}

/* ---- the plant box: stubs with the contracts of box.h --------------------------------
 * The same treatment for the box certification of a ranged block (map version 4):
 * eva_box.c and eva_box_loop.c analyse the real functions (every output written on every
 * return, the fail-safe values of box.h on error); here each writes every output, any
 * value of its type on success and the fail-safe value on error, and returns any status.
 * Without them Eva takes each prototype's default assigns, whose values it cannot show
 * initialized. */

zw_status zw_box_validate(const zw_plant_box *box)
{
    (void)box;
    return any_bool() ? ZW_OK : any_error();
}

zw_status zw_box_loop_work_init(zw_box_loop_work *work, zw_box_loop_cell *cells,
                                uint_least32_t capacity, zw_box_loop_scratch *scratch)
{
    if ((work == NULL) || (cells == NULL) || (scratch == NULL)) {
        return ZW_ERR_NULL;
    }
    if (capacity < ZW_BOX_LOOP_MIN_CELLS) {
        return ZW_ERR_ARG;
    }
    work->cells = cells;
    work->scratch = scratch;
    work->capacity = capacity;
    work->max_evals = ZW_BOX_LOOP_DEFAULT_EVALS;
    work->rel_tol = ZW_BOX_LOOP_DEFAULT_REL_TOL;
    return ZW_OK;
}

zw_status zw_box_loop_check(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real K, zw_real B,
                            const zw_box_loop_work *work, zw_box_loop_verdict *out)
{
    (void)box;
    (void)spec;
    (void)ws;
    (void)K;
    (void)B;
    (void)work;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->stable = false; /* fail-safe: not stable, not decided, plants NaN, count 0 */
    out->decided = false;
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->evals = 0u;
    out->k_worst = ZW_NAN;
    if (any_bool()) {
        return any_error();
    }
    out->stable = any_bool();
    out->decided = out->stable || any_bool();
    out->m_worst = any_real();
    out->b_worst = any_real();
    out->evals = any_u32_source;
    out->k_worst = any_real();
    return ZW_OK;
}

zw_status zw_box_loop_k_max(const zw_plant_box *box, const zw_device_loop_spec *spec,
                            zw_loop_workspace *ws, zw_real B, const zw_box_loop_work *work,
                            zw_box_loop_bound *out)
{
    zw_real k = any_real();
    (void)box;
    (void)spec;
    (void)ws;
    (void)B;
    (void)work;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->K_lower = ZW_R(0.0); /* fail-safe: certifies nothing */
    out->K_upper = ZW_R(0.0);
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->evals = 0u;
    out->converged = false;
    out->k_worst = ZW_NAN;
    if (any_bool()) {
        return any_error();
    }
    out->K_lower = k >= ZW_R(0.0) ? k : ZW_R(0.0); /* 0 or more, +inf included */
    out->K_upper = any_real();
    out->m_worst = any_real();
    out->b_worst = any_real();
    out->evals = any_u32_source;
    out->converged = any_bool();
    out->k_worst = any_real();
    return ZW_OK;
}

zw_status zw_box_loop_k_mmax(const zw_plant_box *box, const zw_device_loop_spec *spec,
                             zw_loop_workspace *ws, const zw_box_loop_work *work,
                             zw_box_loop_extremes *out)
{
    (void)box;
    (void)spec;
    (void)ws;
    (void)work;
    if (out == NULL) {
        return ZW_ERR_NULL;
    }
    out->K_mmax = ZW_R(0.0); /* fail-safe: certifies nothing */
    out->B_at = ZW_NAN;
    out->K_upper_at = ZW_R(0.0);
    out->m_worst = ZW_NAN;
    out->b_worst = ZW_NAN;
    out->evals = 0u;
    out->converged = false;
    out->k_worst = ZW_NAN;
    if (any_bool()) {
        return any_error();
    }
    out->K_mmax = any_real();
    out->B_at = any_real();
    out->K_upper_at = any_real();
    out->m_worst = any_real();
    out->b_worst = any_real();
    out->evals = any_u32_source;
    out->converged = any_bool();
    out->k_worst = any_real();
    return ZW_OK;
}

/* ---- the firmware's hooks -------------------------------------------------------------- */

static bool random_hook(void *ctx, uint_least8_t *out, size_t n)
{
    size_t i;
    (void)ctx;
    /*@ loop unroll 2u * ZW_AUTH_NONCE_WORDS; */
    for (i = 0u; i < n; ++i) {
        out[i] = any_byte_source;
    }
    return any_bool();
}

static bool verify_hook(void *ctx, const uint_least8_t *msg, size_t msg_len,
                        const uint_least8_t *mac, size_t mac_len)
{
    size_t i;
    unsigned acc = 0u;
    (void)ctx;
    for (i = 0u; i < msg_len; ++i) {
        acc += msg[i]; /* every byte of the message is read: it must be initialized */
    }
    for (i = 0u; i < mac_len; ++i) {
        acc += mac[i];
    }
    sink_unsigned = acc;
    return any_bool();
}

static bool save_hook(void *ctx, const uint_least8_t *image, size_t len)
{
    size_t i;
    unsigned acc = 0u;
    (void)ctx;
    for (i = 0u; i < len; ++i) {
        acc += image[i];
    }
    sink_unsigned = acc;
    return any_bool();
}

/* ---- inputs ---------------------------------------------------------------------------- */

static void any_cert(zw_cert *c)
{
    c->m = any_float();
    c->b = any_float();
    c->T = any_float();
    c->sigma = any_float();
    c->r = any_float();
    c->k_min = any_float();
    c->k_max = any_float();
    c->b_min = any_float();
    c->b_max = any_float();
    c->dk_max = any_float();
    c->db_max = any_float();
    c->delay = any_float();
    c->vfilter = any_float();
    c->vf_param = any_float();
    c->differentiator = any_float();
    c->m_hi = any_float(); /* the plant box (map version 4) */
    c->b_hi = any_float();
}

static void any_ceilings(zw_ceilings *k)
{
    k->sigma_max = any_float();
    k->r_max = any_float();
    k->m = any_float();
    k->b = any_float();
    k->T = any_float();
    k->plant_tol = any_float();
    k->k_min = any_float();
    k->k_max = any_float();
    k->b_min = any_float();
    k->b_max = any_float();
    k->dk_max = any_float();
    k->db_max = any_float();
    k->delay = any_float(); /* the firmware's loop */
    k->vfilter = any_float();
    k->vf_param = any_float();
    k->differentiator = any_float();
}

#define ZW_EVA_PDU_MAX 253u /* the Modbus PDU limit */
#define ZW_EVA_WORDS 130u   /* more than a read (125) or a write (123) may hold */
#define ZW_EVA_IMAGE (ZW_IMAGE_BYTES + 2u)

/* ---- the calls ------------------------------------------------------------------------- */

static void drive_configuration(zw_regmap *rm)
{
    zw_ceilings k;
    zw_regmap_auth auth;
    zw_regmap_storage storage;
    zw_reason reason;
    zw_status st;

    zw_regmap_set_consent(maybe_null(rm), any_bool());

    auth.random = any_bool() ? random_hook : NULL;
    auth.verify = any_bool() ? verify_hook : NULL;
    auth.ctx = NULL;
    zw_regmap_set_auth(maybe_null(rm), maybe_null(&auth));

    any_ceilings(&k);
    st = zw_regmap_set_ceilings(rm, &k, &reason);
    sink_int = (int)st;
    sink_int = (int)reason;
    (void)zw_regmap_set_ceilings(maybe_null(rm), maybe_null(&k), maybe_null(&reason));

    zw_regmap_set_word_order(maybe_null(rm), any_unsigned_source);

    storage.save = any_bool() ? save_hook : NULL;
    storage.ctx = NULL;
    zw_regmap_set_storage(maybe_null(rm), maybe_null(&storage));
}

static void drive_restore(zw_regmap *rm)
{
    uint_least8_t newest[ZW_EVA_IMAGE], previous[ZW_EVA_IMAGE];
    static uint_least8_t image[ZW_IMAGE_BYTES]; /* zero first: Eva widens the 367-word loop
                                                   that fills it */
    zw_reason reason;
    zw_status st;
    size_t i;
    /*@ loop unroll ZW_EVA_IMAGE; */
    for (i = 0u; i < ZW_EVA_IMAGE; ++i) {
        newest[i] = any_byte_source;
        previous[i] = any_byte_source;
    }
    st = zw_regmap_restore(rm, maybe_null(newest), any_size_upto(ZW_EVA_IMAGE),
                           maybe_null(previous), any_size_upto(ZW_EVA_IMAGE), &reason);
    sink_int = (int)st;
    sink_int = (int)reason;
    (void)zw_regmap_restore(maybe_null(rm), maybe_null(newest), any_size_upto(ZW_EVA_IMAGE),
                            maybe_null(previous), any_size_upto(ZW_EVA_IMAGE),
                            maybe_null(&reason));
    if (zw_regmap_image(rm, image)) {
        for (i = 0u; i < ZW_IMAGE_BYTES; ++i) {
            sink_unsigned = image[i];
        }
    }
    (void)zw_regmap_image(maybe_null(rm), maybe_null(image));
}

static void drive_gains_and_state(zw_regmap *rm)
{
    float K, B;
    zw_status st = zw_regmap_active_gains(rm, &K, &B);
    sink_int = (int)st;
    sink_float = K;
    sink_float = B;
    (void)zw_regmap_active_gains(maybe_null(rm), maybe_null(&K), maybe_null(&B));
    zw_regmap_set_state(maybe_null(rm), any_float(), any_float(), any_float(), any_u32_source);
}

static void drive_pdu(zw_regmap *rm)
{
    uint_least8_t req[ZW_EVA_PDU_MAX], resp[ZW_EVA_PDU_MAX];
    size_t req_len = any_size_upto(ZW_EVA_PDU_MAX), resp_cap = any_size_upto(ZW_EVA_PDU_MAX);
    size_t resp_len, i;
    zw_mb_exception exc;
    /*@ loop unroll ZW_EVA_PDU_MAX; */
    for (i = 0u; i < ZW_EVA_PDU_MAX; ++i) {
        req[i] = any_byte_source;
    }
    exc = zw_regmap_handle_pdu(rm, req, req_len, resp, resp_cap, &resp_len);
    sink_int = (int)exc;
    sink_size = resp_len;
    if (resp_len >= 2u) {
        sink_unsigned = resp[0];
        sink_unsigned = resp[1];
    }
    (void)zw_regmap_handle_pdu(maybe_null(rm), maybe_null(req), req_len, maybe_null(resp),
                               resp_cap, maybe_null(&resp_len));
}

static void drive_registers(zw_regmap *rm)
{
    uint_least16_t words[ZW_EVA_WORDS];
    const uint_least16_t addr = any_word_source, count = any_word_source;
    zw_reason reason;
    zw_mb_exception exc;
    size_t i;
    exc = zw_regmap_read(rm, addr, count, words, &reason);
    sink_int = (int)exc;
    if (exc != ZW_MB_SERVER_FAILURE) {
        sink_int = (int)reason;
    }
    if (count >= 1u && count <= 125u) { /* a read's quantity: every word written */
        sink_unsigned = words[0];
        sink_unsigned = words[count - 1u];
    }
    (void)zw_regmap_read(maybe_null(rm), addr, count, maybe_null(words), maybe_null(&reason));
    /*@ loop unroll ZW_EVA_WORDS; */
    for (i = 0u; i < ZW_EVA_WORDS; ++i) {
        words[i] = any_word_source;
    }
    exc = zw_regmap_write(rm, addr, (uint_least16_t)any_size_upto(ZW_EVA_WORDS), words, &reason);
    sink_int = (int)exc;
    if (exc != ZW_MB_SERVER_FAILURE) {
        sink_int = (int)reason;
    }
    (void)zw_regmap_write(maybe_null(rm), addr, (uint_least16_t)any_size_upto(ZW_EVA_WORDS),
                          maybe_null(words), maybe_null(&reason));
}

static void drive_codec(void)
{
    uint_least16_t w[2], block[ZW_CERT_WORDS + 1u], nonce[ZW_AUTH_NONCE_WORDS];
    static uint_least16_t box_words[ZW_BOX_CERT_WORDS];
    static uint_least8_t msg[ZW_AUTH_MSG_BYTES];
    static zw_box_cert bc;
    zw_cert c, d;
    size_t i;
    zw_float_to_words(any_float(), w);
    sink_unsigned = w[0];
    sink_unsigned = w[1];
    zw_float_to_words(any_float(), maybe_null(w));
    w[0] = any_word_source;
    w[1] = any_word_source;
    sink_float = zw_words_to_float(w);
    sink_float = zw_words_to_float(maybe_null(w));
    any_cert(&c);
    sink_float = zw_cert_field(&c, any_unsigned_source);
    zw_cert_set_field(&c, any_unsigned_source, any_float());
    zw_cert_encode(&c, block);
    for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
        sink_unsigned = block[i];
    }
    zw_cert_decode(block, &d);
    sink_float = d.m;
    sink_float = d.differentiator;
    /*@ loop unroll ZW_AUTH_NONCE_WORDS; */
    for (i = 0u; i < ZW_AUTH_NONCE_WORDS; ++i) {
        nonce[i] = any_word_source;
    }
    /*@ loop unroll ZW_CERT_WORDS + 1u; */
    for (i = 0u; i <= ZW_CERT_WORDS; ++i) {
        block[i] = any_word_source;
    }
    sink_unsigned = zw_crc16_words(block, any_size_upto(ZW_CERT_WORDS + 1u));
    sink_unsigned = zw_crc16_words(maybe_null(block), any_size_upto(ZW_CERT_WORDS + 1u));
    for (i = 0u; i < ZW_BOX_CERT_WORDS; ++i) {
        box_words[i] = any_word_source;
    }
    zw_regmap_auth_message(nonce, block, box_words, msg);
    for (i = 0u; i < ZW_AUTH_MSG_BYTES; ++i) {
        sink_unsigned = msg[i];
    }
    zw_regmap_auth_message(maybe_null(nonce), maybe_null(block), maybe_null(box_words), maybe_null(msg));
    /* the box certificate's words (any words: decoded, encoded, one at a time) */
    zw_box_cert_decode(box_words, &bc);
    zw_box_cert_encode(&bc, box_words);
    sink_unsigned = zw_box_cert_word(&bc, any_unsigned_source);
    sink_name = zw_reason_name((zw_reason)any_int_source);
    /* the map's internal reader of a float payload (regmap_internal.h; no caller in the map
     * today, so reached here): two words, or four PDU bytes */
    sink_float = zw_rm_payload_float(nonce, NULL, any_size_upto(ZW_AUTH_NONCE_WORDS - 2u));
    sink_float = zw_rm_payload_float(NULL, msg, any_size_upto(ZW_AUTH_MSG_BYTES / 2u - 2u));
}

int main(void)
{
    static zw_regmap rm; /* static: the map is kept in owned storage on a target too */
    zw_cert cert;
    zw_reason reason;
    zw_status st;

    any_cert(&cert);
    st = zw_regmap_init(&rm, maybe_null(&cert), maybe_null(&reason));
    sink_int = (int)st;
    (void)zw_regmap_init(maybe_null(&rm), maybe_null(&cert), maybe_null(&reason));
    drive_configuration(&rm);
    drive_restore(&rm);
    /* any number of requests and calls, in any order */
    while (any_bool()) {
        drive_pdu(&rm);
        if (any_bool()) {
            drive_registers(&rm);
        }
        if (any_bool()) {
            drive_gains_and_state(&rm);
        }
        if (any_bool()) {
            drive_configuration(&rm);
        }
    }
    drive_codec();
    return 0;
}
