/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* The "any value" helpers of the Eva drivers (tests/eva/eva_*.c, docs/eva.md): a read of a
 * volatile is any value of its type for Eva (NaN and both infinities included for a
 * zw_real), and every output a driver checks is read into a volatile sink. */
#ifndef ZW_EVA_ANY_H
#define ZW_EVA_ANY_H

#include <stdbool.h>
#include <stddef.h>

#include "zwidth/coeffs.h"

volatile zw_real any_real_source;
volatile int any_int_source;
volatile unsigned any_unsigned_source;

/* Sinks: every output is read into one of these. */
volatile zw_real sink_real;
volatile int sink_int;
volatile unsigned sink_unsigned;

static inline zw_real any_real(void) { return any_real_source; }
static inline bool any_bool(void) { return any_int_source != 0; }

/* The pointer or NULL, either way. */
#define maybe_null(p) (any_bool() ? (p) : NULL)

/* Coefficients with every field any value (a failed init's NaN, a hand-filled struct,
 * garbage). */
static inline void any_coeffs(zw_coeffs *c)
{
    c->delta = any_real();
    c->e = any_real();
    c->c1 = any_real();
    c->c2 = any_real();
    c->d12 = any_real();
    c->s = any_real();
    c->g = any_real();
    c->sigma = any_real();
    c->hs = any_real();
    c->delta_relerr = any_real();
}

#endif
