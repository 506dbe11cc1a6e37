/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zw_hostloop.h - the loop a drive runs, as host programs state it on their command line
 * (zwidth-limits, zwidth-drive, zwidth-tune): one parser of --velocity-filter and
 * --differentiator with the spelling of the Python `zwidth` CLI (zwidth.loop
 * parse_velocity_filter), and the loop in words.  Host only (stdio); no libmodbus, no
 * OpenSSL, so that zwidth-limits (tools/demo.sh) needs only the core.
 */
#ifndef ZW_HOSTLOOP_H
#define ZW_HOSTLOOP_H

#include <stddef.h>

#include "zwidth/device_loop.h"

/* What a program says when the loop is not stated (after "<prog>: error: " or "<prog>: "). */
#define ZW_LOOP_NOT_STATED                                                                  \
    "the loop is not stated: give --delay N (--delay 0 for the paper's ideal loop; most "   \
    "firmware computes during the period and applies at the next tick: --delay 1)"

/* A velocity filter as text: none | lowpass:F[Hz|kHz] (also low-pass:) | pole:A |
 * average:N.  Syntax only (values are the caller's or the core's to judge): *kind is
 * ZW_VFILTER_NONE, _LOWPASS (*cutoff_hz = F, *pole = 0) or, for pole:A, _LOWPASS with
 * *cutoff_hz = 0 and *pole = A, or _AVERAGE (*average = N).  Returns 1, or 0 after printing
 * "<prefix>: --velocity-filter ...: <why>" on stderr. */
int zw_parse_velocity_filter(const char *prefix, const char *text, zw_velocity_filter *kind,
                             double *cutoff_hz, double *pole, unsigned *average);

/* backward | tustin; 0 after printing "<prefix>: --differentiator expects ..." */
int zw_parse_differentiator(const char *prefix, const char *text, zw_differentiator *out);

/* 1 when spec is the paper's ideal loop (delay 0, backward difference, no filter). */
int zw_loop_spec_ideal(const zw_device_loop_spec *spec);

/* The loop in words, every part named, as Python's Loop.statement(): "1 sample delay,
 * backward difference, velocity low-pass 100 Hz (pole 0.533488)", "the paper's ideal loop:
 * no delay, backward difference, no velocity filter".  pole: the pole in force (NaN when
 * not known). */
void zw_loop_statement(const zw_device_loop_spec *spec, double pole, char *buf, size_t cap);

/* The velocity filter part alone: "velocity low-pass 100 Hz (pole 0.533488)", "velocity
 * moving average of 4 samples", "no velocity filter". */
void zw_loop_filter_text(const zw_device_loop_spec *spec, double pole, char *buf, size_t cap);

#endif /* ZW_HOSTLOOP_H */
