/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_selftest: passes on the host's IEEE arithmetic, and fails, naming the property, when
 * the environment is changed under it: directed rounding, flush-to-zero, denormals-are-zero.
 * The builds that contract or assume finite maths are tested by test_selftest_variant.c. */
#include "zw_test.h"

#include <fenv.h>
#if defined(__SSE2__) || defined(__x86_64__)
#include <xmmintrin.h>
#define ZWT_HAVE_MXCSR 1
#else
#define ZWT_HAVE_MXCSR 0
#endif

/* The host is binary32 / binary64 with round to nearest: every property holds. */
static void test_host_passes(void **state)
{
    uint_least16_t failed = 0xFFFFu;
    (void)state;
    EXPECT_OK(zw_selftest());
    EXPECT_OK(zw_selftest_failures(&failed));
    EXPECT_TRUE_MSG(failed == 0u, "failed = 0x%x", (unsigned)failed);
}

static void test_null(void **state)
{
    (void)state;
    EXPECT_STATUS(zw_selftest_failures(NULL), ZW_ERR_NULL);
}

/* Under a directed rounding mode the error bounds (u = 2^-p, half an ulp) are wrong:
 * ZW_ERR_FPENV with the rounding property named; back to nearest, ZW_OK again. */
static void expect_rounding_refused(int mode, const char *name)
{
    uint_least16_t failed = 0u;
    zw_status st;
    if (fesetround(mode) != 0) {
        print_message("rounding mode %s not settable here: skipped\n", name);
        return;
    }
    st = zw_selftest_failures(&failed);
    (void)fesetround(FE_TONEAREST);
    EXPECT_TRUE_MSG(st == ZW_ERR_FPENV, "%s: status %s", name, zw_status_name(st));
    EXPECT_TRUE_MSG((failed & ZW_SELFTEST_ROUNDING) != 0u, "%s: failed = 0x%x", name,
                    (unsigned)failed);
    EXPECT_OK(zw_selftest());
}

static void test_directed_rounding_refused(void **state)
{
    (void)state;
#ifdef FE_TOWARDZERO
    expect_rounding_refused(FE_TOWARDZERO, "FE_TOWARDZERO"); /* C28x FPU with RNDF32 = 0 */
#endif
#ifdef FE_UPWARD
    expect_rounding_refused(FE_UPWARD, "FE_UPWARD");
#endif
#ifdef FE_DOWNWARD
    expect_rounding_refused(FE_DOWNWARD, "FE_DOWNWARD");
#endif
}

#if ZWT_HAVE_MXCSR
/* zw_selftest under MXCSR | mode_bits; expects ZW_ERR_FPENV naming the underflow property,
 * and checks that the mode really was in force (what the FPU did with a subnormal). */
static void expect_flush_refused(unsigned int mode_bits, const char *name)
{
    const unsigned int saved = _mm_getcsr();
    volatile zw_real tiny = ZW_REAL_MIN, sub = ZW_REAL_MIN * ZW_R(0.5);
    uint_least16_t failed = 0u;
    zw_status st;
    zw_real flushed_result, read_as_zero;
    _mm_setcsr(saved | mode_bits);
    flushed_result = tiny * ZW_R(0.5); /* FTZ: 0 */
    read_as_zero = sub * ZW_R(2.0);    /* DAZ: 0 */
    st = zw_selftest_failures(&failed);
    _mm_setcsr(saved);
    EXPECT_TRUE_MSG(flushed_result == ZW_R(0.0) || read_as_zero == ZW_R(0.0), "%s not in force", name);
    EXPECT_TRUE_MSG(st == ZW_ERR_FPENV, "%s: status %s", name, zw_status_name(st));
    EXPECT_TRUE_MSG(failed == ZW_SELFTEST_UNDERFLOW, "%s: failed = 0x%x", name, (unsigned)failed);
    EXPECT_OK(zw_selftest());
}
#endif

/* Flush-to-zero and denormals-are-zero (SSE MXCSR FTZ, DAZ; as on a C28x FPU or a Cortex-M
 * with FPSCR.FZ set): refused, each alone and together (docs/fp-environment.md says why:
 * flushed fields make 0/0, a negative subnormal reads as zero). */
static void test_flush_to_zero_refused(void **state)
{
    (void)state;
#if ZWT_HAVE_MXCSR
    expect_flush_refused(0x8000u, "FTZ");
    expect_flush_refused(0x0040u, "DAZ");
    expect_flush_refused(0x8040u, "FTZ | DAZ");
#else
    print_message("no MXCSR on this host: skipped\n");
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_host_passes),
        cmocka_unit_test(test_null),
        cmocka_unit_test(test_directed_rounding_refused),
        cmocka_unit_test(test_flush_to_zero_refused),
    };
    return cmocka_run_group_tests_name("selftest_" ZW_REAL_NAME, tests, NULL, NULL);
}
