/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

// The C++ side of tests/consumer/consumer.c: the public headers from C++ (extern "C"),
// the same checks (expected values: see consumer.c).
#include <cmath>
#include <cstdio>
#include <string_view>

#include "zwidth/zwidth.h"
#include "zwidth/sim.h"  // every public header must compile as C++

namespace {

int failures = 0;

void expect(bool ok, const char *what)
{
    if (!ok) {
        std::printf("FAIL: %s\n", what);
        ++failures;
    }
}

bool near(zw_real got, zw_real want) { return std::fabs(got - want) <= ZW_R(1e-4); }

}  // namespace

int main()
{
    zw_coeffs c;
    zw_verdict v;
    zw_extremes x;
    expect(zw_coeffs_init(&c, ZW_R(2.049)) == ZW_OK, "zw_coeffs_init(2.049)");
    expect(zw_extremes_compute(&c, &x) == ZW_OK, "zw_extremes_compute");
    expect(near(x.alpha_mmax, ZW_R(6.099663)), "alpha_mmax = 6.099663");
    expect(near(x.beta_at_alpha_mmax, ZW_R(0.42075)), "beta at alpha_mmax = 0.42075");
    expect(zw_check(&c, ZW_R(6.09), ZW_R(0.42075), &v) == ZW_OK && v.stable, "(6.09, 0.42075) stable");
    expect(zw_check(&c, ZW_R(6.11), ZW_R(0.42075), &v) == ZW_OK && !v.stable, "(6.11, 0.42075) unstable");
    expect(zw_coeffs_init(&c, ZW_R(5.122)) == ZW_OK, "zw_coeffs_init(5.122)");
    expect(zw_extremes_compute(&c, &x) == ZW_OK && x.at_corner, "corner above delta1");
    expect(near(x.alpha_mmax, ZW_R(23.004769)), "alpha_mmax = 23.004769");
    expect(near(x.beta_at_alpha_mmax, ZW_R(-3.162505)), "beta at alpha_mmax = -3.162505");
    expect(std::string_view(zw_status_name(ZW_ERR_NAN)) == "ZW_ERR_NAN", "zw_status_name");
    if (failures == 0) {
        std::printf("consumer ok (%s, C++)\n", ZW_REAL_NAME);
    }
    return failures == 0 ? 0 : 1;
}
