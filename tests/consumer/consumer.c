/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* A program of another project using the installed zwidth (tools/consumer_test.sh builds
 * it with find_package(zwidth) and with pkg-config, for double and float).  Expected
 * values: the 50-digit mpmath reference of tests/py/reference.py (closed forms from the
 * literal coefficients), rounded to 6 decimals; the paper's Table 2 prints the same betas
 * (0.421, -3.162) for these two deltas (Wang et al. 2024, Section V-B). */
#include <stdio.h>

#include "zwidth/zwidth.h"

static int failures;
static volatile zw_real zero = ZW_R(0.0);

static void expect(int ok, const char *what)
{
    if (!ok) {
        printf("FAIL: %s\n", what);
        failures++;
    }
}

static int near(zw_real got, zw_real want, zw_real tol)
{
    return got - want <= tol && want - got <= tol;
}

int main(void)
{
    zw_coeffs c;
    zw_verdict v;
    zw_extremes x;
    /* delta = 2.049: alpha_mmax 6.099663 at beta 0.42075, on the hyperbola's top */
    expect(zw_coeffs_init(&c, ZW_R(2.049)) == ZW_OK, "zw_coeffs_init(2.049)");
    expect(zw_extremes_compute(&c, &x) == ZW_OK, "zw_extremes_compute");
    expect(near(x.alpha_mmax, ZW_R(6.099663), ZW_R(1e-4)), "alpha_mmax = 6.099663");
    expect(near(x.beta_at_alpha_mmax, ZW_R(0.42075), ZW_R(1e-4)), "beta at alpha_mmax = 0.42075");
    expect(!x.at_corner, "top of the hyperbola below delta1");
    expect(zw_check(&c, ZW_R(6.09), ZW_R(0.42075), &v) == ZW_OK && v.stable, "(6.09, 0.42075) stable");
    expect(zw_check(&c, ZW_R(6.11), ZW_R(0.42075), &v) == ZW_OK && !v.stable,
           "(6.11, 0.42075) unstable");
    /* delta = 5.122: alpha_mmax 23.004769 at beta -3.162505, at the corner with the line */
    expect(zw_coeffs_init(&c, ZW_R(5.122)) == ZW_OK, "zw_coeffs_init(5.122)");
    expect(zw_extremes_compute(&c, &x) == ZW_OK, "zw_extremes_compute");
    expect(near(x.alpha_mmax, ZW_R(23.004769), ZW_R(1e-4)), "alpha_mmax = 23.004769");
    expect(x.at_corner, "corner above delta1");
    expect(zw_check(&c, ZW_R(23.1), ZW_R(-3.162505), &v) == ZW_OK && !v.stable,
           "(23.1, -3.162505) unstable");
    /* invalid input gives a named error */
    expect(zw_check(&c, zero / zero, ZW_R(0.0), &v) == ZW_ERR_NAN, "NaN alpha refused");
    if (failures == 0) {
        printf("consumer ok (%s, C)\n", ZW_REAL_NAME);
    }
    return failures == 0 ? 0 : 1;
}
