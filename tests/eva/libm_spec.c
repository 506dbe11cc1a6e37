/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* ACSL contracts for the libm functions the core calls that Frama-C's libc leaves without
 * one (tools/eva.sh).  Deliberately weak, so that they are true of every libm: the result
 * depends on x only and may be any value of the type, NaN and infinities included. */
#include <math.h>

/*@ assigns \result \from x; */
extern double expm1(double x);

/*@ assigns \result \from x; */
extern float expm1f(float x);
