/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* The register map across contexts, on two threads under ThreadSanitizer (regmap.h,
 * threading model).
 *
 * A "Modbus" thread hammers zw_regmap_handle_pdu: 0x10 writes of certified pairs and of
 * pairs the policy refuses, UNLOCK1/UNLOCK2 then SEAL or ABORT, and 0x03 reads of the four
 * state registers.  A "control" thread, like a control ISR, calls zw_regmap_active_gains
 * and zw_regmap_set_state in a loop.  Checked on every read:
 *   - every pair the control thread reads is one of the certified pairs written here (or
 *     (0, 0)), bit for bit; all of them have distinct K and distinct B, so a K of one with
 *     the B of another is never in the set: a mixed pair is caught;
 *   - every pair it read was accepted by the map at some point (checked after the join);
 *   - a ZW_ERR_BUSY answer comes with (0, 0);
 *   - every state read shows one sample: x, v, f are functions of the step (exact in
 *     float), and the step never goes back.
 * ThreadSanitizer reports any access to the map that is not ordered by the publication.
 * A mixed pair can only be read while the two threads really run at the same time, in a
 * window of a few stores; on a loaded machine they may mostly take turns.  So the control
 * thread counts its "concurrent" reads: those during which the Modbus thread finished a
 * request (a relaxed counter: no ordering that could hide a race from TSan; taking turns
 * on one core makes that happen only at a context switch), and the run goes on past
 * ZWT_SECONDS until ZWT_CONCURRENT such reads were made, at most 4 x ZWT_SECONDS.  (Writing the
 * slot in force instead of the other one is caught this way: tens of thousands of mixed
 * pairs in an 8 s run.)
 *
 * This file and the core are compiled as C11 for this test (tests/c/CMakeLists.txt), so
 * that regmap.c uses <stdatomic.h>, which ThreadSanitizer understands; the firmware build
 * (C99) uses volatile and ZW_MEMORY_BARRIER() instead, which TSan cannot check.
 * Bounded: ZWT_SECONDS of wall time (default 2; see above) or the iteration caps. */
#define _POSIX_C_SOURCE 200809L

#include "zw_test.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

#include "zwidth/regmap.h"

#if !ZW_REGMAP_C11_ATOMICS
#error "build this test as C11 with <stdatomic.h>: the C99 publication is not visible to TSan"
#endif

#define MODBUS_MAX_ITERATIONS 2000000ul
#define CONTROL_MAX_ITERATIONS 200000000ul
#define ZWT_CONCURRENT 5000ul

/* The paper's drive (J = 85.78e-7 kg m^2, b = 2.197e-3 N m s/rad, T = 20 ms), sigma 0.8. */
static zw_cert block(void)
{
    zw_cert c;
    c.m = 85.78e-7f;
    c.b = 2.197e-3f;
    c.T = 0.02f;
    c.sigma = 0.8f;
    c.r = 0.999f;
    c.k_min = 0.0f;
    c.k_max = 10.0f;
    c.b_min = -0.01f;
    c.b_max = 0.01f;
    c.dk_max = 1.0f; /* steps never bind: any pair below is reachable from any other */
    c.db_max = 0.01f;
    c.delay = 0.0f; /* the ideal loop */
    c.vfilter = 0.0f;
    c.vf_param = 0.0f;
    c.differentiator = 0.0f;
    c.m_hi = 0.0f; /* a point block (map version 4) */
    c.b_hi = 0.0f;
    return c;
}

/* Index 0 is output off; the others are certified (checked in setup) and pairwise
 * distinct in K and in B. */
static const float k_certified[][2] = {
    {0.0f, 0.0f},       {0.30f, -1.20e-3f}, {0.35f, -1.36e-3f}, {0.25f, -1.00e-3f},
    {0.20f, -8.0e-4f},  {0.10f, -3.0e-4f},  {0.05f, 1.0e-4f},
};
#define N_CERTIFIED (sizeof k_certified / sizeof k_certified[0])

/* Refused whatever the pair in force (checked in setup). */
static const float k_refused[][2] = {
    {0.45f, -1.36e-3f}, /* ABOVE_SIGMA: stable, above 0.8 K_max(B) */
    {0.9f, 0.0f},       /* UNSTABLE */
    {20.0f, 0.0f},      /* K_ABOVE_MAX */
    {0.3f, 0.02f},      /* B_ABOVE_MAX */
};
#define N_REFUSED (sizeof k_refused / sizeof k_refused[0])

/* Index of (K, B) in k_certified, bit for bit, or -1. */
static int certified_index(float K, float B)
{
    size_t i;
    for (i = 0; i < N_CERTIFIED; ++i)
        if (zwt_bits_of(K) == zwt_bits_of(k_certified[i][0]) && zwt_bits_of(B) == zwt_bits_of(k_certified[i][1]))
            return (int)i;
    return -1;
}

/* ---- requests ---------------------------------------------------------------------------- */

static void put_float(uint_least8_t *p, float f)
{
    uint32_t u = zwt_bits_of(f);
    p[0] = (uint_least8_t)(u >> 24);
    p[1] = (uint_least8_t)((u >> 16) & 0xFFu);
    p[2] = (uint_least8_t)((u >> 8) & 0xFFu);
    p[3] = (uint_least8_t)(u & 0xFFu);
}

static zw_mb_exception write_pair(zw_regmap *rm, float K, float B)
{
    uint_least8_t req[14] = {0x10, 0x00, ZW_REG_K, 0x00, 0x04, 0x08};
    uint_least8_t resp[253];
    size_t len = 0;
    put_float(req + 6, K);
    put_float(req + 10, B);
    return zw_regmap_handle_pdu(rm, req, sizeof req, resp, sizeof resp, &len);
}

static zw_mb_exception command(zw_regmap *rm, unsigned cmd)
{
    uint_least8_t req[5] = {0x06, 0x00, ZW_REG_COMMAND, (uint_least8_t)(cmd >> 8),
                            (uint_least8_t)(cmd & 0xFFu)};
    uint_least8_t resp[253];
    size_t len = 0;
    return zw_regmap_handle_pdu(rm, req, sizeof req, resp, sizeof resp, &len);
}

/* The state the control thread reports at step n: every value exact in float. */
/* Commissioning hooks of the Modbus thread (only it calls them): any nonce and any MAC do;
 * test_regmap.c tests the authentication itself. */
static bool any_random(void *ctx, uint_least8_t *out, size_t n)
{
    (void)ctx;
    memset(out, 0x5A, n * sizeof *out);
    return true;
}

static bool any_mac(void *ctx, const uint_least8_t *msg, size_t msg_len, const uint_least8_t *mac,
                    size_t mac_len)
{
    (void)ctx, (void)msg, (void)msg_len, (void)mac, (void)mac_len;
    return true;
}

static void allow_commissioning(zw_regmap *rm)
{
    zw_regmap_auth hooks = {any_random, any_mac, NULL};
    const zw_ceilings wide = {1.0f, 1.0f, 85.78e-7f, 2.197e-3f, 0.02f, 1e30f,
                              -FLT_MAX, FLT_MAX, -FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX,
                              0.0f, 0.0f, 0.0f, 0.0f}; /* the ideal loop */
    assert_int_equal(zw_regmap_set_ceilings(rm, &wide, NULL), ZW_OK);
    zw_regmap_set_auth(rm, &hooks);
    zw_regmap_set_consent(rm, true);
}

static float state_x(uint32_t n) { return (float)(n & 0xFFFFFu); }
static float state_v(uint32_t n) { return 3.0f * state_x(n); } /* power-up (0, 0, 0, 0) is step 0 */
static float state_f(uint32_t n) { return 0.25f * state_x(n); }

static float float_at(const uint_least8_t *p)
{
    uint32_t u = ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* ---- the two threads ------------------------------------------------------------------------ */

typedef struct shared {
    zw_regmap rm;
    atomic_bool stop;
    atomic_ulong progress;   /* relaxed: requests the Modbus thread has finished */
    atomic_ulong concurrent; /* relaxed: control reads during which progress moved */
} shared;

typedef struct modbus_result {
    unsigned long requests, accepted_writes, refused_writes, unexpected, state_reads, state_busy,
        torn_states, step_back, commissionings;
    unsigned accepted_mask; /* bit i: k_certified[i] was accepted at least once */
    char first_problem[160];
} modbus_result;

typedef struct control_result {
    unsigned long reads, busy, busy_not_off, mixed;
    unsigned observed_mask; /* bit i: k_certified[i] was read */
    float mixed_K, mixed_B;
} control_result;

static void note(modbus_result *r, const char *what, unsigned long value)
{
    if (r->first_problem[0] == '\0')
        snprintf(r->first_problem, sizeof r->first_problem, "%s (%lu)", what, value);
}

/* One 0x03 read of STATE_X .. STATE_STEP: one sample, never older than the last. */
static void read_state(zw_regmap *rm, modbus_result *r, uint32_t *last_step)
{
    static const uint_least8_t req[5] = {0x03, 0x00, ZW_REG_STATE_X, 0x00, 0x08};
    uint_least8_t resp[253];
    size_t len = 0;
    zw_mb_exception e = zw_regmap_handle_pdu(rm, req, sizeof req, resp, sizeof resp, &len);
    uint32_t step;
    if (e == ZW_MB_SERVER_FAILURE) { /* no consistent sample in ZW_REGMAP_READ_TRIES tries */
        r->state_busy++;
        return;
    }
    if (e != ZW_MB_OK || len != 18u) {
        r->unexpected++;
        note(r, "state read not answered", (unsigned long)e);
        return;
    }
    r->state_reads++;
    step = ((uint32_t)resp[14] << 24) | ((uint32_t)resp[15] << 16) | ((uint32_t)resp[16] << 8) |
           resp[17];
    if (zwt_bits_of(float_at(resp + 2)) != zwt_bits_of(state_x(step)) ||
        zwt_bits_of(float_at(resp + 6)) != zwt_bits_of(state_v(step)) ||
        zwt_bits_of(float_at(resp + 10)) != zwt_bits_of(state_f(step))) {
        r->torn_states++;
        note(r, "state registers mix two samples at step", (unsigned long)step);
    }
    if (step < *last_step) {
        r->step_back++;
        note(r, "state step went back to", (unsigned long)step);
    }
    *last_step = step;
}

static void *modbus_thread(void *arg)
{
    shared *sh = arg;
    modbus_result *r = calloc(1, sizeof *r);
    uint32_t rng = 12345u, last_step = 0u;
    bool commissioning = false;
    unsigned long i;
    if (r == NULL) return NULL;
    r->accepted_mask = 1u; /* (0, 0) is in force from power-up */
    for (i = 0; i < MODBUS_MAX_ITERATIONS && !atomic_load(&sh->stop); ++i) {
        unsigned pick;
        rng = rng * 1664525u + 1013904223u; /* Numerical Recipes LCG */
        pick = (rng >> 16) % 16u;
        if (pick < 9u) {
            size_t j = (size_t)((rng >> 8) % N_CERTIFIED);
            zw_mb_exception e = write_pair(&sh->rm, k_certified[j][0], k_certified[j][1]);
            r->requests++;
            if (e == ZW_MB_OK) {
                r->accepted_writes++;
                r->accepted_mask |= 1u << j;
            } else if (!commissioning) { /* certified pairs are refused only while commissioning */
                r->unexpected++;
                note(r, "certified pair refused, index", (unsigned long)j);
            }
        } else if (pick < 12u) {
            size_t j = (size_t)((rng >> 8) % N_REFUSED);
            r->requests++;
            if (write_pair(&sh->rm, k_refused[j][0], k_refused[j][1]) == ZW_MB_OK) {
                r->unexpected++;
                note(r, "refused pair accepted, index", (unsigned long)j);
            }
            r->refused_writes++;
        } else if (pick == 12u) {
            /* unlock, or leave commissioning by SEAL (the staged block is the one in force,
             * with its CRC) or ABORT */
            zw_mb_exception e1 = ZW_MB_OK, e2;
            if (!commissioning) {
                e1 = command(&sh->rm, ZW_CMD_UNLOCK1);
                e2 = command(&sh->rm, ZW_CMD_UNLOCK2);
                r->requests += 2u;
                r->commissionings++;
            } else {
                e2 = command(&sh->rm, ((rng >> 8) & 1u) != 0u ? ZW_CMD_SEAL : ZW_CMD_ABORT);
                r->requests++;
            }
            if (e1 != ZW_MB_OK || e2 != ZW_MB_OK) {
                r->unexpected++;
                note(r, "command refused, exception", (unsigned long)(e1 != ZW_MB_OK ? e1 : e2));
            }
            commissioning = !commissioning;
        }
        atomic_fetch_add_explicit(&sh->progress, 1ul, memory_order_relaxed);
        read_state(&sh->rm, r, &last_step);
        atomic_fetch_add_explicit(&sh->progress, 1ul, memory_order_relaxed);
        r->requests++;
    }
    return r;
}

static void *control_thread(void *arg)
{
    shared *sh = arg;
    control_result *r = calloc(1, sizeof *r);
    unsigned long i;
    if (r == NULL) return NULL;
    for (i = 0; i < CONTROL_MAX_ITERATIONS && !atomic_load_explicit(&sh->stop, memory_order_relaxed);
         ++i) {
        uint32_t step = (uint32_t)i;
        float K = 1.0f, B = 1.0f;
        unsigned long before = atomic_load_explicit(&sh->progress, memory_order_relaxed);
        zw_status st = zw_regmap_active_gains(&sh->rm, &K, &B);
        int idx;
        r->reads++;
        if (atomic_load_explicit(&sh->progress, memory_order_relaxed) != before)
            atomic_fetch_add_explicit(&sh->concurrent, 1ul, memory_order_relaxed);
        if (st == ZW_ERR_BUSY) {
            r->busy++;
            if (zwt_bits_of(K) != 0u || zwt_bits_of(B) != 0u) r->busy_not_off++;
        } else if (st != ZW_OK || (idx = certified_index(K, B)) < 0) {
            if (r->mixed++ == 0u) {
                r->mixed_K = K;
                r->mixed_B = B;
            }
        } else {
            r->observed_mask |= 1u << idx;
        }
        zw_regmap_set_state(&sh->rm, state_x(step), state_v(step), state_f(step), step);
    }
    return r;
}

/* ---- the test ------------------------------------------------------------------------------- */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Every pair of the two sets does what the test assumes, from every certified pair. */
static void check_sets(zw_regmap *rm)
{
    size_t i, j;
    for (i = 0; i < N_CERTIFIED; ++i) {
        for (j = 0; j < N_CERTIFIED; ++j) {
            EXPECT_TRUE_MSG(write_pair(rm, k_certified[i][0], k_certified[i][1]) == ZW_MB_OK,
                            "certified pair %zu", i);
            EXPECT_TRUE_MSG(write_pair(rm, k_certified[j][0], k_certified[j][1]) == ZW_MB_OK,
                            "certified pair %zu after %zu", j, i);
            /* a mix of two different pairs is not in the set */
            if (i != j) assert_true(certified_index(k_certified[i][0], k_certified[j][1]) < 0);
        }
        for (j = 0; j < N_REFUSED; ++j) {
            EXPECT_TRUE_MSG(write_pair(rm, k_refused[j][0], k_refused[j][1]) != ZW_MB_OK,
                            "refused pair %zu after %zu", j, i);
        }
    }
}

static void test_publication_under_concurrency(void **state)
{
    shared *sh = calloc(1, sizeof *sh);
    zw_cert c = block();
    zw_reason why = ZW_REASON_NONE;
    pthread_t modbus, control;
    void *mr = NULL, *cr = NULL;
    modbus_result *m;
    control_result *k;
    double seconds = 2.0, t0;
    const char *env = getenv("ZWT_SECONDS");
    unsigned popcount = 0u, bit;
    (void)state;
    assert_non_null(sh);
    if (env != NULL && atof(env) > 0.0) seconds = atof(env);
    EXPECT_OK(zw_regmap_init(&sh->rm, &c, &why));
    check_sets(&sh->rm);
    EXPECT_OK(zw_regmap_init(&sh->rm, &c, &why)); /* gains off again */
    allow_commissioning(&sh->rm);
    atomic_init(&sh->stop, false);
    atomic_init(&sh->progress, 0ul);
    atomic_init(&sh->concurrent, 0ul);

    assert_int_equal(pthread_create(&modbus, NULL, modbus_thread, sh), 0);
    assert_int_equal(pthread_create(&control, NULL, control_thread, sh), 0);
    t0 = now_s();
    while (now_s() - t0 < seconds ||
           (atomic_load_explicit(&sh->concurrent, memory_order_relaxed) < ZWT_CONCURRENT &&
            now_s() - t0 < 4.0 * seconds)) {
        struct timespec nap = {0, 20000000L};
        nanosleep(&nap, NULL);
    }
    atomic_store(&sh->stop, true);
    assert_int_equal(pthread_join(modbus, &mr), 0);
    assert_int_equal(pthread_join(control, &cr), 0);
    assert_non_null(mr);
    assert_non_null(cr);
    m = mr;
    k = cr;
    for (bit = 1u; bit < (1u << N_CERTIFIED); bit <<= 1u) popcount += (k->observed_mask & bit) != 0u;

    printf("  %.1f s: modbus %lu requests (%lu accepted, %lu refused writes, %lu commissionings, "
           "%lu state reads, %lu busy); control %lu gain reads (%lu busy, %lu concurrent), "
           "%u of %zu pairs seen\n",
           now_s() - t0, m->requests, m->accepted_writes, m->refused_writes, m->commissionings,
           m->state_reads, m->state_busy, k->reads, k->busy,
           atomic_load(&sh->concurrent), popcount, N_CERTIFIED);
    EXPECT_TRUE_MSG(m->unexpected == 0u, "modbus side: %s", m->first_problem);
    EXPECT_TRUE_MSG(m->torn_states == 0u && m->step_back == 0u, "state: %s", m->first_problem);
    EXPECT_TRUE_MSG(k->mixed == 0u, "%lu gain reads outside the certified set, first (%.9g, %.9g)",
                    k->mixed, (double)k->mixed_K, (double)k->mixed_B);
    EXPECT_TRUE_MSG(k->busy_not_off == 0u, "%lu ZW_ERR_BUSY answers were not (0, 0)",
                    k->busy_not_off);
    EXPECT_TRUE_MSG((k->observed_mask & ~m->accepted_mask) == 0u,
                    "pairs read but never accepted: mask 0x%X", k->observed_mask & ~m->accepted_mask);
    /* the run exercised what it claims: many publications seen from the other thread */
    EXPECT_TRUE_MSG(m->accepted_writes >= 100u && k->reads >= 10000u && m->state_reads >= 100u,
                    "too little concurrency to mean anything");
    EXPECT_TRUE_MSG(popcount >= 3u, "the control thread saw only %u certified pairs", popcount);
    free(m);
    free(k);
    free(sh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_publication_under_concurrency),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
