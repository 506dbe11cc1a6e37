/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_selftest compiled the way an integrator might compile it, and linked to this main:
 * it must report ZW_ERR_FPENV with the property ZWT_EXPECT_BIT named.  CMake builds it
 * (tests/c/CMakeLists.txt) with
 *   - -std=gnu99 -O2 -ffp-contract=fast -mfma (a vendor IDE's GNU mode on an FPU with
 *     fused multiply-add): ZW_SELFTEST_CONTRACTION;
 *   - -ffinite-math-only -U__FINITE_MATH_ONLY__ (a compiler that folds NaN tests without
 *     saying so, so real.h's #error cannot fire): ZW_SELFTEST_NAN.
 * Exit 77 (CTest SKIP_RETURN_CODE) where the CPU lacks the instructions the variant uses.
 * This file itself is compiled with the project's flags. */
#include <stdio.h>

#include "zwidth/selftest.h"

int main(void)
{
    uint_least16_t failed = 0u;
    zw_status st;
#ifdef ZWT_NEEDS_FMA
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("fma")) {
        printf("no FMA on this CPU: skipped\n");
        return 77;
    }
#endif
    st = zw_selftest_failures(&failed);
    printf("%s: zw_selftest -> %s, failed = 0x%x (expected bit 0x%x)\n", ZWT_VARIANT,
           zw_status_name(st), (unsigned)failed, (unsigned)(ZWT_EXPECT_BIT));
    return st == ZW_ERR_FPENV && (failed & (ZWT_EXPECT_BIT)) != 0u ? 0 : 1;
}
