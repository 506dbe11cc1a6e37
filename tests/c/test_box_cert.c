/* SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0 */
/* Box certificates (box_cert.h): what a verified certificate claims holds against
 * independent references (the ideal loop: eq (10) in long double over a grid of plants and
 * B; one sample of delay: the guarded point check, itself tested against mpmath), and every
 * damaged or forged certificate either fails verification or still claims only the truth
 * (fuzzed). */
#include "zw_test.h"
#include "zw_ref_box.h"

#define CELLS 64u
static zw_box_loop_cell g_cells[CELLS];
static zw_box_loop_scratch g_scratch;
static zw_loop_workspace g_ws;
static zw_device_loop g_dl;

typedef struct cert_case {
    zw_plant_box box;
    unsigned delay;
    float B_lo, B_hi;
} cert_case;

/* bench/modbus/bench_regmap_box.c's boxes: the paper drive +-5 % (ideal and delay 1) and an
 * interior minimum in m. */
static cert_case case_of(int i)
{
    cert_case c;
    memset(&c, 0, sizeof c);
    c.box.T = R(0.02);
    c.box.m_lo = (zw_real)(0.95f * 85.78e-7f);
    c.box.m_hi = (zw_real)(1.05f * 85.78e-7f);
    c.box.b_lo = (zw_real)(0.95f * 2.197e-3f);
    c.box.b_hi = (zw_real)(1.05f * 2.197e-3f);
    c.B_lo = -1.0e-3f;
    c.B_hi = 3.0e-3f;
    if (i == 1) {
        c.box.m_lo = R(2.0e-5);
        c.box.m_hi = R(1.5e-4);
        c.box.b_lo = (zw_real)2.197e-3f;
        c.box.b_hi = (zw_real)2.197e-3f;
        c.B_hi = 4.0e-3f;
    } else if (i == 2) {
        c.delay = 1u;
        c.B_hi = 2.0e-3f;
    }
    return c;
}

static zw_box_loop_work work(void)
{
    zw_box_loop_work w;
    EXPECT_OK(zw_box_loop_work_init(&w, g_cells, CELLS, &g_scratch));
    return w;
}

static zw_device_loop_spec spec_of(const cert_case *c)
{
    zw_device_loop_spec spec;
    memset(&spec, 0, sizeof spec);
    spec.delay = c->delay;
    return spec;
}

/* Does the reference say every claim of cert holds?  On a grid of n x n plants and 5 B per
 * step: the level (and half of it: every K' in (0, K] is claimed) is below eq (10)'s K_max,
 * or, with delay, stable by the point check.  The first false claim is reported in *why. */
static bool claims_hold(const cert_case *c, const zw_box_cert *cert, int n, char *why, size_t why_len)
{
    const zw_device_loop_spec spec = spec_of(c);
    unsigned s;
    int i, j, k, h;
    for (s = 0u; s < cert->n_steps; ++s) {
        for (k = 0; k < 5; ++k) {
            const long double B = (long double)cert->B[s] + ((long double)cert->B[s + 1u] - cert->B[s]) * k / 4.0L;
            for (i = 0; i < n; ++i) {
                for (j = 0; j < n; ++j) {
                    const long double m = c->box.m_lo + (long double)(c->box.m_hi - c->box.m_lo) * i / (n - 1);
                    const long double b = c->box.b_lo + (long double)(c->box.b_hi - c->box.b_lo) * j / (n - 1);
                    if (c->delay == 0u) {
                        if ((long double)cert->K[s] > ideal_k_max_ref(m, b, c->box.T, B)) {
                            (void)snprintf(why, why_len, "step %u: K %.9g above K_max %.12Lg at m %Lg b %Lg B %Lg",
                                           s, (double)cert->K[s], ideal_k_max_ref(m, b, c->box.T, B), m, b, B);
                            return false;
                        }
                        continue;
                    }
                    EXPECT_OK(zw_device_loop_init_plant(&g_dl, (zw_real)m, (zw_real)b, c->box.T, R(0.0), R(0.0),
                                                        R(0.0), R(0.0), R(0.0), &spec));
                    for (h = 1; h <= 2; ++h) {
                        zw_loop_verdict v;
                        EXPECT_OK(zw_device_loop_check(&g_dl, &g_ws, (zw_real)cert->K[s] / (zw_real)h, (zw_real)B, &v));
                        if (!v.stable && !v.marginal) {
                            (void)snprintf(why, why_len, "step %u: K %.9g / %d unstable at m %Lg b %Lg B %Lg", s,
                                           (double)cert->K[s], h, m, b, B);
                            return false;
                        }
                    }
                }
            }
        }
    }
    return true;
}

static void build(const cert_case *c, unsigned steps, unsigned leaves, zw_box_cert *cert, zw_box_cert_report *r)
{
    const zw_device_loop_spec spec = spec_of(c);
    const zw_box_loop_work w = work();
    EXPECT_OK(zw_box_cert_build(&c->box, &spec, &g_ws, c->B_lo, c->B_hi, steps, leaves, R(1.0e-3), &w, cert, r));
}

static zw_box_cert_fault verify(const cert_case *c, const zw_box_cert *cert, uint_least32_t *leaves)
{
    const zw_device_loop_spec spec = spec_of(c);
    const zw_box_loop_work w = work();
    zw_box_cert_fault fault = ZW_BOX_CERT_OK;
    EXPECT_OK(zw_box_cert_verify(&c->box, &spec, cert, &w, &fault, leaves));
    return fault;
}

/* Built certificates verify within the bounds, claim only the truth, and keep a stated
 * share of the point bracket (the figures go to bench/REPORT.md). */
static void test_build_verify_sound(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < 3; ++i) {
        const cert_case c = case_of(i);
        zw_box_cert cert;
        zw_box_cert_report r;
        uint_least32_t leaves = 0u;
        char why[200] = "";
        unsigned s;
        double least = 1.0;
        build(&c, 16u, 512u, &cert, &r);
        assert_int_equal(r.failed_step, ZW_BOX_CERT_MAX_STEPS);
        assert_int_equal(cert.n_steps, 16);
        assert_true(r.leaves >= 16u && r.leaves <= ZW_BOX_CERT_MAX_LEAVES);
        assert_true(cert.n_nodes == 2u * r.leaves - 16u);
        assert_int_equal(verify(&c, &cert, &leaves), ZW_BOX_CERT_OK);
        assert_int_equal(leaves, r.leaves);
        assert_true(cert.B[0] == c.B_lo && cert.B[16] == c.B_hi);
        EXPECT_TRUE_MSG(claims_hold(&c, &cert, c.delay ? 9 : 41, why, sizeof why), "box %d: %s", i, why);
        for (s = 0u; s < 16u; ++s) {
            const double ratio = (double)cert.K[s] / (double)r.K_upper[s];
            assert_true(cert.K[s] > 0.0f && ratio <= 1.0);
            least = ratio < least ? ratio : least;
        }
        print_message("box %d: %u leaves, %u tests, least level / point bracket %.3f\n", i, (unsigned)r.leaves,
                      (unsigned)r.tests, least);
        /* the host proves each leaf on a wider cell: the ideal boxes keep half, delay 1 more */
        assert_true(least >= (c.delay ? 0.25 : 0.35));
    }
}

/* Each kind of damage gives its fault. */
static void test_faults(void **state)
{
    cert_case c = case_of(2);
    zw_box_cert good, bad;
    zw_box_cert_report r;
    uint_least32_t leaves;
    unsigned j;
    (void)state;
    c.B_hi = 1.0e-3f;
    build(&c, 4u, 64u, &good, &r);
    assert_int_equal(r.failed_step, ZW_BOX_CERT_MAX_STEPS);
    assert_int_equal(verify(&c, &good, &leaves), ZW_BOX_CERT_OK);
    bad = good;
    bad.n_steps = 0u;
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_HEADER);
    bad.n_steps = 17u;
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_HEADER);
    bad = good;
    bad.n_nodes = 1025u;
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_HEADER);
    bad = good;
    bad.B[2] = bad.B[1];
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_STEP);
    bad = good;
    bad.K[3] = -bad.K[3];
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_STEP);
    bad.K[3] = (float)NAN;
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_STEP);
    bad = good; /* a level above the truth: some leaf cannot pass */
    bad.K[1] = 2.0f * (float)r.K_upper[1];
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_LEAF_FAILS);
    bad = good; /* the trees end early */
    bad.n_nodes = (uint_least16_t)(good.n_nodes - 1u);
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_NODE);
    bad = good; /* a node past the last tree */
    bad.n_nodes = (uint_least16_t)(good.n_nodes + 1u);
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_UNUSED);
    bad = good; /* non-zero padding */
    bad.nodes[ZW_BOX_CERT_NODE_WORDS - 1u] = 0x1000u;
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_UNUSED);
    bad = good; /* an unknown code as the first node */
    bad.nodes[0] = (uint_least16_t)((bad.nodes[0] & 0xFFF0u) | 0x7u);
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_NODE);
    bad = good; /* the ideal boxes have no Kp range: a Kp split has no inside */
    bad.nodes[0] = (uint_least16_t)((bad.nodes[0] & 0xFFF0u) | ZW_BOX_CERT_SPLIT_KP);
    assert_true(verify(&c, &bad, &leaves) != ZW_BOX_CERT_OK);
    /* 34 nested splits (each left child split again): more cells wait than the stack holds */
    memset(&bad, 0, sizeof bad);
    bad.n_steps = 1u;
    bad.B[0] = 0.0f;
    bad.B[1] = 1.0e-3f;
    bad.K[0] = 1.0e-3f;
    bad.n_nodes = 2u * 34u + 1u;
    for (j = 0u; j < 34u; ++j) {
        bad.nodes[j / 4u] = (uint_least16_t)(bad.nodes[j / 4u] | (ZW_BOX_CERT_SPLIT_K << (4u * (j % 4u))));
    }
    assert_int_equal(verify(&c, &bad, &leaves), ZW_BOX_CERT_BAD_SPLIT);
    /* more than 512 leaves: a balanced tree of K splits, 1024 leaves claimed */
    memset(&bad, 0, sizeof bad);
    bad.n_steps = 1u;
    bad.B[0] = 0.0f;
    bad.B[1] = 1.0e-3f;
    bad.K[0] = 1.0e-6f;
    bad.n_nodes = 1024u;
    assert_true(verify(&c, &bad, &leaves) != ZW_BOX_CERT_OK);
    /* errors: nothing is OK */
    {
        const zw_device_loop_spec spec = spec_of(&c);
        zw_box_loop_work w = work();
        zw_box_cert_fault fault = ZW_BOX_CERT_OK;
        EXPECT_STATUS(zw_box_cert_verify(&c.box, &spec, NULL, &w, &fault, &leaves), ZW_ERR_NULL);
        assert_true(fault != ZW_BOX_CERT_OK);
        fault = ZW_BOX_CERT_OK;
        w.capacity = ZW_BOX_CERT_STACK - 1u;
        EXPECT_STATUS(zw_box_cert_verify(&c.box, &spec, &good, &w, &fault, &leaves), ZW_ERR_ARG);
        assert_true(fault != ZW_BOX_CERT_OK);
        w = work();
        bad = good;
        EXPECT_STATUS(zw_box_cert_build(&c.box, &spec, &g_ws, 1.0f, 0.0f, 4u, 64u, R(1.0e-3), &w, &bad, &r),
                      ZW_ERR_ARG);
        assert_int_equal(bad.n_steps, 0);
        EXPECT_STATUS(zw_box_cert_build(&c.box, &spec, &g_ws, 0.0f, 1.0e-3f, 17u, 64u, R(1.0e-3), &w, &bad, &r),
                      ZW_ERR_ARG);
        EXPECT_STATUS(zw_box_cert_build(&c.box, &spec, &g_ws, 0.0f, 1.0e-3f, 4u, 513u, R(1.0e-3), &w, &bad, &r),
                      ZW_ERR_ARG);
    }
}

/* A B range with unstable B in it: no certificate, and the step is named. */
static void test_build_unprovable(void **state)
{
    cert_case c = case_of(2);
    zw_box_cert cert;
    zw_box_cert_report r;
    uint_least32_t leaves;
    (void)state;
    c.B_hi = 0.5f; /* far beyond the stable B of the delay-1 loop */
    build(&c, 4u, 64u, &cert, &r);
    assert_true(r.failed_step < 4u);
    assert_int_equal(cert.n_steps, 0);
    assert_int_equal(r.leaves, 0);
    assert_true(verify(&c, &cert, &leaves) != ZW_BOX_CERT_OK);
}

/* Random damage (bits of the nodes, levels, breakpoints, counts): whatever still verifies
 * claims only the truth. */
static void test_fuzz_forged(void **state)
{
    unsigned seed = 2026u;
    int i, t, accepted = 0, refused = 0;
    (void)state;
    for (i = 0; i < 3; ++i) {
        const cert_case c = case_of(i);
        zw_box_cert good;
        zw_box_cert_report r;
        build(&c, 16u, (i == 2) ? 128u : 512u, &good, &r);
        for (t = 0; t < ((i == 2) ? 150 : 700); ++t) {
            zw_box_cert bad = good;
            uint_least32_t leaves;
            char why[200] = "";
            unsigned kind, s;
            seed = seed * 1103515245u + 12345u;
            kind = (seed >> 16) % 5u;
            seed = seed * 1103515245u + 12345u;
            s = (seed >> 16) % 16u;
            seed = seed * 1103515245u + 12345u;
            switch (kind) {
            case 0u: /* one nibble */
                bad.nodes[(seed >> 8) % (good.n_nodes / 4u + 1u)] ^= (uint_least16_t)(1u << ((seed >> 20) % 16u));
                break;
            case 1u: /* a level up by up to 2x */
                bad.K[s] = bad.K[s] * (1.0f + (float)((seed >> 12) % 1000u) / 1000.0f);
                break;
            case 2u: /* a breakpoint moved by up to half a step */
                bad.B[s] += ((float)((seed >> 12) % 1000u) / 1000.0f - 0.5f) * (good.B[1] - good.B[0]);
                break;
            case 3u: /* the counts */
                bad.n_nodes = (uint_least16_t)(bad.n_nodes + ((seed >> 12) % 5u) - 2u);
                bad.n_steps = (uint_least16_t)(bad.n_steps - ((seed >> 20) % 2u));
                break;
            default: /* swap two levels */
                bad.K[s] = good.K[(s + 1u + (seed >> 12) % 15u) % 16u];
                bad.K[(s + 1u + (seed >> 12) % 15u) % 16u] = good.K[s];
                break;
            }
            if (verify(&c, &bad, &leaves) != ZW_BOX_CERT_OK) {
                refused += 1;
                continue;
            }
            accepted += 1;
            EXPECT_TRUE_MSG(claims_hold(&c, &bad, c.delay ? 5 : 21, why, sizeof why), "box %d kind %u: %s", i, kind,
                            why);
        }
    }
    print_message("fuzz: %d damaged certificates refused, %d still valid (and true)\n", refused, accepted);
    assert_true(refused > 0);
}

/* Lookups: the step at B, the larger level on a breakpoint, nothing outside. */
static void test_lookups(void **state)
{
    zw_box_cert c;
    float K = -1.0f, lo, hi, B;
    bool in = true;
    (void)state;
    memset(&c, 0, sizeof c);
    c.n_steps = 3u;
    c.B[0] = -1.0f;
    c.B[1] = 0.0f;
    c.B[2] = 1.0f;
    c.B[3] = 2.0f;
    c.K[0] = 5.0f;
    c.K[1] = 7.0f;
    c.K[2] = 6.0f;
    zw_box_cert_level(&c, -0.5f, &K, &in);
    assert_true(in && K == 5.0f);
    zw_box_cert_level(&c, 0.0f, &K, &in);
    assert_true(in && K == 7.0f);
    zw_box_cert_level(&c, 1.0f, &K, &in);
    assert_true(in && K == 7.0f);
    zw_box_cert_level(&c, 2.0f, &K, &in);
    assert_true(in && K == 6.0f);
    zw_box_cert_level(&c, -1.0f, &K, &in);
    assert_true(in && K == 5.0f);
    zw_box_cert_level(&c, 2.5f, &K, &in);
    assert_true(!in && K == 0.0f);
    zw_box_cert_level(&c, (float)NAN, &K, &in);
    assert_false(in);
    zw_box_cert_b_range(&c, 5.5f, 0.5f, &lo, &hi, &in);
    assert_true(in && lo == 0.0f && hi == 2.0f);
    zw_box_cert_b_range(&c, 5.0f, 1.5f, &lo, &hi, &in);
    assert_true(in && lo == -1.0f && hi == 2.0f);
    zw_box_cert_b_range(&c, 6.5f, -0.5f, &lo, &hi, &in);
    assert_true(!in && isnan(lo) && isnan(hi));
    zw_box_cert_k_mmax(&c, &K, &B);
    assert_true(K == 7.0f && B == 0.5f);
    c.n_steps = 0u;
    zw_box_cert_k_mmax(&c, &K, &B);
    assert_true(K == 0.0f && isnan(B));
    zw_box_cert_level(&c, 0.5f, &K, &in);
    assert_false(in);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_build_verify_sound),
        cmocka_unit_test(test_faults),
        cmocka_unit_test(test_build_unprovable),
        cmocka_unit_test(test_fuzz_forged),
        cmocka_unit_test(test_lookups),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
