/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/real.h - the one floating type of the core and its maths.
 *
 * Build with -DZW_REAL_FLOAT for float (MCUs with a single-precision FPU, TI C28x
 * where double is 32-bit); default is double.  Every literal goes through ZW_R() so
 * the float build never silently promotes to double.
 */
#ifndef ZWIDTH_REAL_H
#define ZWIDTH_REAL_H

#include <float.h>
#include <math.h>
#include "zwidth/precision.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Builds that silently switch the guards off are refused (docs/fp-environment.md) ----
 * -ffast-math / -Ofast / -ffinite-math-only let the compiler fold x != x to false, so a NaN
 * gain passes every check; TI's --fp_mode=relaxed replaces division by a constant with a
 * multiplication and redirects sqrt to inline approximations.  Contraction into fused
 * multiply-adds has no macro in GCC (-ffp-contract=fast is GCC's default in its GNU modes):
 * CMake passes -ffp-contract=off, and zw_selftest() catches it at run time. */
#if defined(__FAST_MATH__)
#error "zwidth: -ffast-math / -Ofast void the error bounds and the NaN guards; build without them"
#endif
#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "zwidth: -ffinite-math-only folds the NaN guards away; build without it"
#endif
#if defined(__TI_STRICT_FP_MODE__) && !__TI_STRICT_FP_MODE__
#error "zwidth: TI --fp_mode=relaxed voids the error bounds; build with --fp_mode=strict"
#endif
/* Clang honours the standard pragma (GCC ignores it, with a warning, so it is not given
 * there): no contraction in the rest of every file that includes this header. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* Binary floating point with IEEE-754 binary32 floats in every build: the register map
 * packs binary32 words (regmap.c: the 126 / 149 / 0x800000 constants). */
#if FLT_RADIX != 2
#error "zwidth: floating point is not binary (FLT_RADIX != 2)"
#endif
#if FLT_MANT_DIG != 24 || FLT_MAX_EXP != 128 || FLT_MIN_EXP != -125
#error "zwidth: float is not IEEE-754 binary32"
#endif

/* The error bounds assume IEEE-754 binary32 / binary64 arithmetic with round to nearest
 * (unit roundoff below).  Where double is 32-bit (TI C28x COFF ABI, -mdouble=32), build
 * with -DZW_REAL_FLOAT; a double build there would silently void every guard. */
#ifdef ZW_REAL_FLOAT
typedef float zw_real;
#define ZW_R(x) x##f
#define ZW_EXP expf
#define ZW_EXPM1 expm1f
#define ZW_SQRT sqrtf
#define ZW_FABS fabsf
#define ZW_FREXP frexpf
#define ZW_FLOOR floorf
#define ZW_POW powf
#define ZW_SIN sinf
#define ZW_COS cosf
#define ZW_ATAN2 atan2f
#define ZW_LDEXP ldexpf
#define ZW_REAL_MAX FLT_MAX
#define ZW_REAL_MIN FLT_MIN
#define ZW_REAL_MAX_EXP FLT_MAX_EXP
/* Unit roundoff u = 2^-24: |fl(x op y) - x op y| <= u |x op y| for normal results. */
#define ZW_UNIT_ROUNDOFF ZW_R(5.9604644775390625e-8)
#define ZW_REAL_NAME "float"
/* Bytes of zw_real in IEEE-754 terms (not sizeof, which counts 16-bit chars on TI C28x). */
#define ZW_REAL_BYTES 4u
#if defined(HUGE_VALF) && !defined(ZW_PORTABLE_MATH)
#define ZW_HUGE_VAL HUGE_VALF
#endif
#else
#if DBL_MANT_DIG != 53 || DBL_MAX_EXP != 1024 || DBL_MIN_EXP != -1021
#error "zwidth: double is not IEEE-754 binary64 here; build with -DZW_REAL_FLOAT"
#endif
typedef double zw_real;
#define ZW_R(x) x
#define ZW_EXP exp
#define ZW_EXPM1 expm1
#define ZW_SQRT sqrt
#define ZW_FABS fabs
#define ZW_FREXP frexp
#define ZW_FLOOR floor
#define ZW_POW pow
#define ZW_SIN sin
#define ZW_COS cos
#define ZW_ATAN2 atan2
#define ZW_LDEXP ldexp
#define ZW_REAL_MAX DBL_MAX
#define ZW_REAL_MIN DBL_MIN
#define ZW_REAL_MAX_EXP DBL_MAX_EXP
/* Unit roundoff u = 2^-53. */
#define ZW_UNIT_ROUNDOFF ZW_R(1.1102230246251565404e-16)
#define ZW_REAL_NAME "double"
#define ZW_REAL_BYTES 8u
#if defined(HUGE_VAL) && !defined(ZW_PORTABLE_MATH)
#define ZW_HUGE_VAL HUGE_VAL
#endif
#endif

/* ---- C99 library names some embedded toolchains lack (avr-libc, old TI RTS) ----------
 * ZW_HUGE_VAL (zw_real) and ZW_HUGE_VALF (float, for the binary32 registers) are +inf;
 * where <math.h> lacks HUGE_VAL(F), or under ZW_PORTABLE_MATH, they are the largest
 * finite value times 2, which overflows to +inf on IEEE targets (zw_selftest checks).
 * ZW_PORTABLE_MATH also replaces expm1 / expm1f and nextafterf with the portable C99
 * versions in zwidth/portable_math.h (accuracy measured in docs/fp-environment.md). */
#ifndef ZW_HUGE_VAL
#define ZW_HUGE_VAL (ZW_REAL_MAX * ZW_R(2.0))
#endif
#if defined(HUGE_VALF) && !defined(ZW_PORTABLE_MATH)
#define ZW_HUGE_VALF HUGE_VALF
#else
#define ZW_HUGE_VALF (FLT_MAX * 2.0f)
#endif
#ifdef ZW_PORTABLE_MATH
#undef ZW_EXPM1
#define ZW_EXPM1 zw_expm1_portable
#define ZW_NEXTAFTERF zw_nextafterf_portable
#else
#define ZW_NEXTAFTERF nextafterf
#endif

/* NaN and infinity tests that do not depend on C99's classification macros working
 * for every FPU (x != x is true only for NaN; the second test catches +-inf). */
#define ZW_IS_NAN(x) ((x) != (x))
#define ZW_IS_FINITE(x) (!ZW_IS_NAN(x) && ZW_FABS(x) <= ZW_REAL_MAX)

#ifdef __cplusplus
}
#endif

/* Declared whatever ZW_PORTABLE_MATH says: the fallbacks are always built into the core
 * (and the amalgamation copies each header once, where it is first included). */
#include "zwidth/portable_math.h"

#endif /* ZWIDTH_REAL_H */
