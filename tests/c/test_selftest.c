/* zw_selftest: passes on the host's IEEE arithmetic, and fails, naming the property, when
 * the environment is changed under it (rounding mode).  Flush-to-zero is accepted: every
 * bound adds ZW_ETA = ZW_REAL_MIN per operation (docs/fp-environment.md).  The builds that
 * contract or assume finite maths are tested by test_selftest_variant.c. */
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

/* Flush-to-zero and denormals-are-zero (SSE MXCSR FTZ | DAZ, as on a C28x FPU or a
 * Cortex-M with FPSCR.FZ set): accepted, by design (ZW_ETA covers a flushed result). */
static void test_flush_to_zero_accepted(void **state)
{
    (void)state;
#if ZWT_HAVE_MXCSR
    {
        const unsigned int saved = _mm_getcsr();
        uint_least16_t failed = 0xFFFFu;
        zw_status st;
        volatile zw_real tiny = ZW_REAL_MIN;
        zw_real flushed;
        _mm_setcsr(saved | 0x8040u); /* FTZ (bit 15) | DAZ (bit 6) */
        flushed = tiny * ZW_R(0.5);
        st = zw_selftest_failures(&failed);
        _mm_setcsr(saved);
        /* the mode really was in force: half the smallest normal came out as 0 */
        EXPECT_TRUE_MSG(flushed == ZW_R(0.0), "FTZ not in force");
        EXPECT_TRUE_MSG(st == ZW_OK && failed == 0u, "status %s, failed = 0x%x",
                        zw_status_name(st), (unsigned)failed);
    }
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
        cmocka_unit_test(test_flush_to_zero_accepted),
    };
    return cmocka_run_group_tests_name("selftest_" ZW_REAL_NAME, tests, NULL, NULL);
}
