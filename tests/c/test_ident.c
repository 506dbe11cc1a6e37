/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_ident (ident.h): the drive's identification experiment.  The PRBS follows Marsaglia's
 * published xorshift32 sequence from seed 1 (the levels are its low bits), the steps their
 * four quarters; every sample played is recorded with the position it was played at; each
 * limit trips the run with its reason and output off; every request beyond a ceiling is
 * refused and changes nothing. */
#include <float.h>
#include <math.h>

#include "zw_test.h"
#include "zwidth/ident.h"

#define CAP 64u

/* xorshift32 from seed 1: Marsaglia, "Xorshift RNGs", J. Stat. Softw. 8(14), 2003. */
static const uint32_t k_xorshift_seed1[10] = {270369u,    67634689u,  2647435461u, 307599695u,  2398689233u,
                                              745495504u, 632435482u, 435756210u,  2005365029u, 2916098932u};

static float g_cmd[CAP], g_pos[CAP];

static zw_ident_limits limits(void)
{
    zw_ident_limits l;
    l.amplitude_max = 2.0f;
    l.x_window = 0.5f;
    l.v_max = 3.0f;
    l.samples_max = 40u;
    return l;
}

static zw_ident_request prbs(uint_least16_t hold, uint_least32_t samples)
{
    zw_ident_request r;
    r.kind = ZW_IDENT_PRBS;
    r.hold = hold;
    r.seed = 1u;
    r.amplitude = 1.5f;
    r.samples = samples;
    return r;
}

static void setup(zw_ident *id)
{
    zw_ident_limits l = limits();
    assert_int_equal(zw_ident_init(id, &l, g_cmd, g_pos, CAP), ZW_OK);
    assert_int_equal(id->state, ZW_IDENT_IDLE);
}

/* Step n times at position x0 + 0.001 n; returns how many commands were nonzero. */
static unsigned play(zw_ident *id, unsigned n, float x0, float *last)
{
    unsigned i, nonzero = 0u;
    for (i = 0u; i < n; ++i) {
        float u = -99.0f;
        assert_int_equal(zw_ident_step(id, x0 + 0.001f * (float)i, 0.1f, &u), ZW_OK);
        nonzero += (u != 0.0f) ? 1u : 0u;
        *last = u;
    }
    return nonzero;
}

static void test_prbs_follows_xorshift32(void **state)
{
    zw_ident id;
    unsigned i;
    float last;
    zw_ident_request r = prbs(3u, 30u);
    (void)state;
    setup(&id);
    assert_int_equal(zw_ident_start(&id, &r, 0.25f), ZW_OK);
    assert_true(zw_ident_running(&id));
    assert_int_equal(play(&id, 30u, 0.25f, &last), 30u);
    assert_int_equal(id.state, ZW_IDENT_DONE);
    assert_int_equal(id.recorded, 30u);
    for (i = 0u; i < 30u; ++i) {
        float u, x;
        float want = ((k_xorshift_seed1[i / 3u] & 1u) != 0u) ? 1.5f : -1.5f;
        assert_int_equal(zw_ident_sample(&id, i, &u, &x), ZW_OK);
        assert_true(u == want);
        assert_true(x == 0.25f + 0.001f * (float)i); /* recorded with the position it was played at */
    }
    /* done: output off, nothing more recorded */
    assert_int_equal(play(&id, 5u, 0.25f, &last), 0u);
    assert_int_equal(id.recorded, 30u);
    assert_false(zw_ident_running(&id));
}

static void test_steps_quarters(void **state)
{
    zw_ident id;
    unsigned i;
    float last, sum = 0.0f;
    zw_ident_request r = prbs(1u, 40u);
    (void)state;
    r.kind = ZW_IDENT_STEPS;
    r.hold = 0u; /* ignored by STEPS */
    setup(&id);
    assert_int_equal(zw_ident_start(&id, &r, 0.0f), ZW_OK);
    assert_int_equal(play(&id, 40u, 0.0f, &last), 40u);
    for (i = 0u; i < 40u; ++i) {
        float u, x;
        assert_int_equal(zw_ident_sample(&id, i, &u, &x), ZW_OK);
        assert_true(u == (((i < 10u) || (i >= 30u)) ? 1.5f : -1.5f));
        sum += u;
    }
    assert_true(sum == 0.0f); /* forward and back */
}

static void test_limits_trip(void **state)
{
    static const struct {
        float x, v;
        unsigned trip;
    } cases[] = {
        {0.51f, 0.0f, ZW_IDENT_TRIP_POSITION}, {-0.6f, 0.0f, ZW_IDENT_TRIP_POSITION},
        {0.0f, 3.01f, ZW_IDENT_TRIP_VELOCITY}, {0.0f, -4.0f, ZW_IDENT_TRIP_VELOCITY},
        {NAN, 0.0f, ZW_IDENT_TRIP_NOT_FINITE}, {0.0f, INFINITY, ZW_IDENT_TRIP_NOT_FINITE},
        {FLT_MAX, 0.0f, ZW_IDENT_TRIP_POSITION}, /* x - x_start overflows: trips, not passes */
    };
    size_t c;
    (void)state;
    for (c = 0; c < ZWT_ARRAY_LEN(cases); ++c) {
        zw_ident id;
        float last, u = -1.0f, x0 = (cases[c].x == FLT_MAX) ? -FLT_MAX : 0.0f;
        zw_ident_request r = prbs(2u, 20u);
        setup(&id);
        assert_int_equal(zw_ident_start(&id, &r, x0), ZW_OK);
        assert_int_equal(play(&id, 5u, x0, &last), 5u);
        assert_int_equal(zw_ident_step(&id, cases[c].x, cases[c].v, &u), ZW_OK);
        assert_true(u == 0.0f);
        assert_int_equal(id.state, ZW_IDENT_TRIPPED);
        assert_int_equal(id.trip, cases[c].trip);
        assert_int_equal(id.recorded, 5u); /* the tripping sample is not recorded */
        assert_int_equal(play(&id, 3u, x0, &last), 0u);
    }
}

static void test_abort(void **state)
{
    zw_ident id;
    float last, u, x;
    zw_ident_request r = prbs(1u, 20u);
    (void)state;
    setup(&id);
    zw_ident_abort(&id); /* nothing to abort */
    assert_int_equal(id.state, ZW_IDENT_IDLE);
    assert_int_equal(zw_ident_start(&id, &r, 0.0f), ZW_OK);
    (void)play(&id, 4u, 0.0f, &last);
    assert_int_equal(zw_ident_sample(&id, 0u, &u, &x), ZW_ERR_ARG); /* still playing */
    assert_true(isnan(u) && isnan(x));
    zw_ident_abort(&id);
    assert_int_equal(id.state, ZW_IDENT_TRIPPED);
    assert_int_equal(id.trip, ZW_IDENT_TRIP_ABORTED);
    assert_int_equal(play(&id, 4u, 0.0f, &last), 0u);
    assert_int_equal(zw_ident_sample(&id, 3u, &u, &x), ZW_OK);
    assert_int_equal(zw_ident_sample(&id, 4u, &u, &x), ZW_ERR_ARG);
    assert_true(isnan(u) && isnan(x));
}

/* Every request beyond a ceiling is refused and leaves the last run as it was. */
static void test_requests_refused(void **state)
{
    zw_ident id;
    float last, u, x;
    zw_ident_request ok = prbs(2u, 8u), r;
    unsigned k;
    (void)state;
    setup(&id);
    assert_int_equal(zw_ident_start(&id, &ok, 0.0f), ZW_OK);
    assert_int_equal(zw_ident_start(&id, &ok, 0.0f), ZW_ERR_BUSY);
    (void)play(&id, 8u, 0.0f, &last);
    assert_int_equal(id.state, ZW_IDENT_DONE);
    for (k = 0u; k < 9u; ++k) {
        zw_status want = ZW_ERR_ARG;
        float x_now = 0.0f;
        r = ok;
        switch (k) {
        case 0u: r.kind = 3u; break;
        case 1u: r.hold = 0u; break;
        case 2u: r.amplitude = 2.0001f; break;
        case 3u: r.amplitude = 0.0f; break;
        case 4u: r.amplitude = NAN; want = ZW_ERR_NAN; break;
        case 5u: r.samples = 41u; break; /* above samples_max */
        case 6u: r.samples = 0u; break;
        case 7u: x_now = NAN; want = ZW_ERR_NAN; break;
        default: x_now = -INFINITY; want = ZW_ERR_INF; break;
        }
        assert_int_equal(zw_ident_start(&id, &r, x_now), want);
        assert_int_equal(id.state, ZW_IDENT_DONE);
        assert_int_equal(id.recorded, 8u);
        assert_int_equal(zw_ident_sample(&id, 7u, &u, &x), ZW_OK);
        assert_true(x == 0.007f);
    }
    assert_int_equal(zw_ident_start(NULL, &ok, 0.0f), ZW_ERR_NULL);
    assert_int_equal(zw_ident_start(&id, NULL, 0.0f), ZW_ERR_NULL);
}

static void test_init_refused(void **state)
{
    zw_ident id;
    zw_ident_limits l;
    zw_ident_request r = prbs(1u, 4u);
    unsigned k;
    float u = 1.0f;
    (void)state;
    for (k = 0u; k < 7u; ++k) {
        zw_status want = ZW_ERR_ARG;
        uint_least32_t cap = CAP;
        l = limits();
        switch (k) {
        case 0u: l.amplitude_max = NAN; want = ZW_ERR_NAN; break;
        case 1u: l.x_window = INFINITY; want = ZW_ERR_INF; break;
        case 2u: l.v_max = 0.0f; break;
        case 3u: l.v_max = -1.0f; break;
        case 4u: l.samples_max = 0u; break;
        case 5u: cap = 0u; break;
        default: l.amplitude_max = -FLT_MAX; break;
        }
        assert_int_equal(zw_ident_init(&id, &l, g_cmd, g_pos, cap), want);
        /* a failed init leaves nothing to start */
        assert_int_equal(zw_ident_start(&id, &r, 0.0f), ZW_ERR_ARG);
        assert_false(zw_ident_running(&id));
    }
    l = limits();
    assert_int_equal(zw_ident_init(NULL, &l, g_cmd, g_pos, CAP), ZW_ERR_NULL);
    assert_int_equal(zw_ident_init(&id, NULL, g_cmd, g_pos, CAP), ZW_ERR_NULL);
    assert_int_equal(zw_ident_init(&id, &l, NULL, g_pos, CAP), ZW_ERR_NULL);
    /* the capacity bounds a run as samples_max does */
    assert_int_equal(zw_ident_init(&id, &l, g_cmd, g_pos, 5u), ZW_OK);
    r.samples = 6u;
    assert_int_equal(zw_ident_start(&id, &r, 0.0f), ZW_ERR_ARG);
    r.samples = 5u;
    assert_int_equal(zw_ident_start(&id, &r, 0.0f), ZW_OK);
    assert_int_equal(zw_ident_step(NULL, 0.0f, 0.0f, &u), ZW_ERR_NULL);
    assert_true(u == 0.0f); /* fail-safe: output off */
    assert_int_equal(zw_ident_step(&id, 0.0f, 0.0f, NULL), ZW_ERR_NULL);
    assert_false(zw_ident_running(NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_prbs_follows_xorshift32),
        cmocka_unit_test(test_steps_quarters),
        cmocka_unit_test(test_limits_trip),
        cmocka_unit_test(test_abort),
        cmocka_unit_test(test_requests_refused),
        cmocka_unit_test(test_init_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
