/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_hostloop.c - the loop options of the host programs (see zw_hostloop.h). */
#include "zw_hostloop.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* strncasecmp is POSIX, not C99 */
static int prefix_nocase(const char *text, const char *prefix)
{
    for (; *prefix != '\0'; ++text, ++prefix)
        if (tolower((unsigned char)*text) != *prefix) return 0;
    return 1;
}

/* a number, then optional spaces and a unit from units (lower case, longest first), the
 * whole text: 1 and *scale (1 without a unit) */
static int number_unit(const char *text, double *out, double *scale)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (end == text || errno == ERANGE || !isfinite(*out)) return 0;
    while (*end == ' ') ++end;
    *scale = 1.0;
    if (prefix_nocase(end, "khz")) { *scale = 1e3; end += 3; }
    else if (prefix_nocase(end, "hz")) end += 2;
    while (*end == ' ') ++end;
    return *end == '\0';
}

int zw_parse_velocity_filter(const char *prefix, const char *text, zw_velocity_filter *kind,
                             double *cutoff_hz, double *pole, unsigned *average)
{
    const char *colon = strchr(text, ':');
    const char *value = colon != NULL ? colon + 1 : "";
    size_t klen = colon != NULL ? (size_t)(colon - text) : strlen(text);
    char *end;
    double x, scale;
    *cutoff_hz = 0.0;
    *pole = 0.0;
    *average = 0u;
    if (colon == NULL && klen == 4 && prefix_nocase(text, "none")) {
        *kind = ZW_VFILTER_NONE;
        return 1;
    }
    if ((klen == 7 && prefix_nocase(text, "lowpass")) || (klen == 8 && prefix_nocase(text, "low-pass"))) {
        if (!number_unit(value, &x, &scale)) {
            fprintf(stderr, "%s: --velocity-filter: a low-pass needs a cut-off in Hz, e.g. "
                            "lowpass:30Hz, got '%s'\n", prefix, text);
            return 0;
        }
        *kind = ZW_VFILTER_LOWPASS;
        *cutoff_hz = x * scale;
        return 1;
    }
    if (klen == 4 && prefix_nocase(text, "pole")) {
        errno = 0;
        x = strtod(value, &end);
        if (end == value || *end != '\0' || errno == ERANGE) {
            fprintf(stderr, "%s: --velocity-filter: a pole needs a number in [0, 1), e.g. "
                            "pole:0.83, got '%s'\n", prefix, text);
            return 0;
        }
        *kind = ZW_VFILTER_LOWPASS;
        *pole = x;
        return 1;
    }
    if (klen == 7 && prefix_nocase(text, "average")) {
        long n;
        errno = 0;
        n = strtol(value, &end, 10);
        if (end == value || *end != '\0' || errno == ERANGE || n < 0 || n > 1000000L) {
            fprintf(stderr, "%s: --velocity-filter: a moving average needs a whole number of "
                            "samples, e.g. average:4, got '%s'\n", prefix, text);
            return 0;
        }
        *kind = ZW_VFILTER_AVERAGE;
        *average = (unsigned)n;
        return 1;
    }
    fprintf(stderr, "%s: --velocity-filter: unknown velocity filter '%s': use none, "
                    "lowpass:F_CHz (e.g. lowpass:30Hz), pole:A (e.g. pole:0.83) or average:N "
                    "(e.g. average:4)\n", prefix, text);
    return 0;
}

int zw_parse_differentiator(const char *prefix, const char *text, zw_differentiator *out)
{
    if (strcmp(text, "backward") == 0) *out = ZW_DIFF_BACKWARD;
    else if (strcmp(text, "tustin") == 0) *out = ZW_DIFF_TUSTIN;
    else {
        fprintf(stderr, "%s: --differentiator expects backward or tustin, got '%s'\n", prefix, text);
        return 0;
    }
    return 1;
}

int zw_loop_spec_ideal(const zw_device_loop_spec *spec)
{
    return spec->delay == 0u && spec->differentiator == ZW_DIFF_BACKWARD &&
           spec->filter == ZW_VFILTER_NONE;
}

void zw_loop_filter_text(const zw_device_loop_spec *spec, double pole, char *buf, size_t cap)
{
    if (spec->filter == ZW_VFILTER_LOWPASS && spec->cutoff_hz > 0.0) {
        if (isnan(pole)) snprintf(buf, cap, "velocity low-pass %g Hz", (double)spec->cutoff_hz);
        else snprintf(buf, cap, "velocity low-pass %g Hz (pole %g)", (double)spec->cutoff_hz, pole);
    } else if (spec->filter == ZW_VFILTER_LOWPASS) {
        snprintf(buf, cap, "velocity low-pass pole %g", (double)spec->pole);
    } else if (spec->filter == ZW_VFILTER_AVERAGE) {
        snprintf(buf, cap, "velocity moving average of %u samples", spec->average);
    } else {
        snprintf(buf, cap, "no velocity filter");
    }
}

void zw_loop_statement(const zw_device_loop_spec *spec, double pole, char *buf, size_t cap)
{
    char delay[32], vf[96];
    const char *diff = spec->differentiator == ZW_DIFF_TUSTIN ? "tustin differentiator"
                                                               : "backward difference";
    if (spec->delay == 0u) snprintf(delay, sizeof delay, "no delay");
    else snprintf(delay, sizeof delay, "%u sample%s delay", spec->delay, spec->delay == 1u ? "" : "s");
    zw_loop_filter_text(spec, pole, vf, sizeof vf);
    snprintf(buf, cap, "%s%s, %s, %s", zw_loop_spec_ideal(spec) ? "the paper's ideal loop: " : "",
             delay, diff, vf);
}
