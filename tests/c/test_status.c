/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_status_name: every status has its own stable name, anything else is "ZW_UNKNOWN". */
#include "zw_test.h"

#define ZWT_STATUS(x) {x, #x}
static const struct {
    zw_status status;
    const char *spelled; /* the enumerator's own identifier, by the preprocessor */
} k_statuses[] = {
    ZWT_STATUS(ZW_OK),          ZWT_STATUS(ZW_ERR_NULL),    ZWT_STATUS(ZW_ERR_NAN),
    ZWT_STATUS(ZW_ERR_INF),     ZWT_STATUS(ZW_ERR_MASS),    ZWT_STATUS(ZW_ERR_PERIOD),
    ZWT_STATUS(ZW_ERR_DAMPING), ZWT_STATUS(ZW_ERR_DELTA),   ZWT_STATUS(ZW_ERR_RANGE),
    ZWT_STATUS(ZW_ERR_ARG),     ZWT_STATUS(ZW_ERR_DOMAIN),  ZWT_STATUS(ZW_ERR_FPENV),
    ZWT_STATUS(ZW_ERR_DELAY),   ZWT_STATUS(ZW_ERR_FILTER),   ZWT_STATUS(ZW_ERR_BUSY),
    ZWT_STATUS(ZW_ERR_BOX),
};

/* Each status is named after its enumerator (the header's example: "ZW_ERR_MASS"). */
static void test_names_match_enumerators(void **state)
{
    size_t i;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k_statuses); ++i) {
        const char *name = zw_status_name(k_statuses[i].status);
        assert_non_null(name);
        assert_string_equal(name, k_statuses[i].spelled);
    }
}

/* No two statuses share a name, and none is called "ZW_UNKNOWN". */
static void test_names_distinct(void **state)
{
    size_t i, j;
    (void)state;
    for (i = 0; i < ZWT_ARRAY_LEN(k_statuses); ++i) {
        const char *a = zw_status_name(k_statuses[i].status);
        assert_string_not_equal(a, "ZW_UNKNOWN");
        for (j = i + 1; j < ZWT_ARRAY_LEN(k_statuses); ++j)
            assert_string_not_equal(a, zw_status_name(k_statuses[j].status));
    }
}

/* Every declared value 0..ZW_STATUS_LAST is covered by the table above (no gaps). */
static void test_values_contiguous(void **state)
{
    int v;
    (void)state;
    assert_int_equal(ZWT_ARRAY_LEN(k_statuses), (int)ZW_STATUS_LAST + 1);
    for (v = 0; v <= (int)ZW_STATUS_LAST; ++v)
        assert_int_equal((int)k_statuses[v].status, v);
}

/* Values outside the enumeration. */
static void test_unknown(void **state)
{
    (void)state;
    assert_string_equal(zw_status_name((zw_status)((int)ZW_STATUS_LAST + 1)), "ZW_UNKNOWN");
    assert_string_equal(zw_status_name((zw_status)1000), "ZW_UNKNOWN");
    assert_string_equal(zw_status_name((zw_status)-1), "ZW_UNKNOWN");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_match_enumerators),
        cmocka_unit_test(test_names_distinct),
        cmocka_unit_test(test_values_contiguous),
        cmocka_unit_test(test_unknown),
    };
    printf("zwidth C tests: status (%s)\n", ZW_REAL_NAME);
    return cmocka_run_group_tests_name("status_" ZW_REAL_NAME, tests, NULL, NULL);
}
