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

/* The error bounds assume IEEE-754 binary32 / binary64 arithmetic with round to nearest
 * (unit roundoff below).  Where double is 32-bit (TI C28x COFF ABI, -mdouble=32), build
 * with -DZW_REAL_FLOAT; a double build there would silently void every guard. */
#ifdef ZW_REAL_FLOAT
#if FLT_MANT_DIG != 24
#error "zwidth: float is not IEEE-754 binary32"
#endif
typedef float zw_real;
#define ZW_R(x) x##f
#define ZW_EXP expf
#define ZW_EXPM1 expm1f
#define ZW_SQRT sqrtf
#define ZW_FABS fabsf
#define ZW_FREXP frexpf
#define ZW_FLOOR floorf
#define ZW_POW powf
#define ZW_LDEXP ldexpf
#define ZW_REAL_MAX FLT_MAX
#define ZW_REAL_MIN FLT_MIN
#define ZW_REAL_MAX_EXP FLT_MAX_EXP
/* Unit roundoff u = 2^-24: |fl(x op y) - x op y| <= u |x op y| for normal results. */
#define ZW_UNIT_ROUNDOFF ZW_R(5.9604644775390625e-8)
#define ZW_REAL_NAME "float"
#else
#if DBL_MANT_DIG != 53
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
#define ZW_LDEXP ldexp
#define ZW_REAL_MAX DBL_MAX
#define ZW_REAL_MIN DBL_MIN
#define ZW_REAL_MAX_EXP DBL_MAX_EXP
/* Unit roundoff u = 2^-53. */
#define ZW_UNIT_ROUNDOFF ZW_R(1.1102230246251565404e-16)
#define ZW_REAL_NAME "double"
#endif

/* NaN and infinity tests that do not depend on C99's classification macros working
 * for every FPU (x != x is true only for NaN; the second test catches +-inf). */
#define ZW_IS_NAN(x) ((x) != (x))
#define ZW_IS_FINITE(x) (!ZW_IS_NAN(x) && ZW_FABS(x) <= ZW_REAL_MAX)

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_REAL_H */
