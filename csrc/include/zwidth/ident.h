/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* zwidth/ident.h - the identification experiment on the drive (docs/identify.md).
 *
 * The host identifies the plant (zwidth identify) from a log of a known command played with
 * the gains off.  This module is the drive's half: the control loop plays a bounded
 * excitation and records, every sample, the command it computed and the position it
 * measured, and turns the output off at once when the device leaves its position window,
 * moves faster than the velocity limit, or a measurement is not finite.  The ceilings (the
 * amplitude, the window, the velocity, the duration) are the firmware's own, fixed at
 * zw_ident_init; a request beyond any of them is refused and changes nothing.
 *
 * Use.  At start-up: zw_ident_init(&id, &ceilings, command_buf, position_buf, capacity),
 * with two float arrays of `capacity` entries the firmware owns (no heap).  To run one:
 * zw_ident_start(&id, &request, x_now) (the firmware makes sure the impedance output is off:
 * the register map's commissioning mode does).  Then, in the control loop, every sample:
 *
 *     float F;
 *     if (zw_ident_running(&id)) { (void)zw_ident_step(&id, x, v, &F); apply(F); }
 *
 * The command logged at sample n is the one zw_ident_step returned at n, whenever the
 * drive applies it (the host fits that delay).  After the run (state DONE or TRIPPED) the
 * samples 0 .. recorded-1 are read with zw_ident_sample.
 *
 * Contexts.  zw_ident_step runs in the control loop; constant time (an LFSR step and a few
 * comparisons), no core call.  zw_ident_start, zw_ident_abort and the readers run in one
 * other context (the Modbus task); the state word is written last by zw_ident_step, so a
 * reader that sees DONE or TRIPPED sees every sample before it.  zw_ident_abort may race a
 * step on several cores; on one core (a task preempted by the ISR) the step sees it at its
 * next call.
 *
 * Fail-safe: every status but ZW_OK leaves *command at 0, and a tripped or finished run
 * commands 0 until the next start.
 */
#ifndef ZWIDTH_IDENT_H
#define ZWIDTH_IDENT_H

#include <stdbool.h>
#include <stdint.h>

#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Excitation kinds (zw_ident_request.kind). */
#define ZW_IDENT_PRBS 1u  /* +-amplitude, a new pseudo-random level every `hold` samples */
#define ZW_IDENT_STEPS 2u /* +A, -A, -A, +A over four quarters: the device ends near its start */

/* Where a run is. */
#define ZW_IDENT_IDLE 0u     /* no run since init */
#define ZW_IDENT_RUNNING 1u  /* playing: zw_ident_step gives the command */
#define ZW_IDENT_DONE 2u     /* all samples played and recorded */
#define ZW_IDENT_TRIPPED 3u  /* stopped by a limit or an abort: output off; see trip */

/* Why a run tripped (ZW_IDENT_TRIP_NONE while it has not). */
#define ZW_IDENT_TRIP_NONE 0u
#define ZW_IDENT_TRIP_POSITION 1u   /* |x - x at start| above the window */
#define ZW_IDENT_TRIP_VELOCITY 2u   /* |v| above the velocity limit */
#define ZW_IDENT_TRIP_NOT_FINITE 3u /* x or v NaN or infinite */
#define ZW_IDENT_TRIP_ABORTED 4u    /* zw_ident_abort */

/* The firmware's ceilings: each > 0 and finite (samples_max >= 1). */
typedef struct zw_ident_limits {
    float amplitude_max;        /* largest |command| [N or N m, the drive's force unit] */
    float x_window;             /* largest |x - x at start| [m or rad] */
    float v_max;                /* largest |v| [m/s or rad/s] */
    uint_least32_t samples_max; /* longest run [samples] */
} zw_ident_limits;

/* One experiment, as the host asks for it. */
typedef struct zw_ident_request {
    uint_least16_t kind;    /* ZW_IDENT_PRBS or ZW_IDENT_STEPS */
    uint_least16_t hold;    /* PRBS: samples per level, >= 1 (ignored by STEPS) */
    uint_least32_t seed;    /* PRBS: the sequence's seed, any value (0 is taken as 1) */
    float amplitude;        /* in (0, amplitude_max] */
    uint_least32_t samples; /* in 1 .. min(samples_max, capacity) */
} zw_ident_request;

typedef struct zw_ident {
    zw_ident_limits limits;
    zw_ident_request request;
    float *command;          /* capacity entries each, the firmware's */
    float *position;
    uint_least32_t capacity;
    uint_least32_t lfsr;     /* xorshift32 state, never 0 */
    uint_least32_t recorded; /* samples recorded in this run */
    float x_start;
    float level;             /* the PRBS level in force, +-1 */
    uint_least16_t state;    /* ZW_IDENT_* state, written last by a step */
    uint_least16_t trip;     /* ZW_IDENT_TRIP_* */
} zw_ident;

/* Set up with the firmware's ceilings and buffers; state IDLE.  ZW_ERR_NULL for a NULL
 * pointer; ZW_ERR_NAN, ZW_ERR_INF or ZW_ERR_ARG for a ceiling not > 0 and finite, or
 * capacity 0.  On an error *id is left IDLE with capacity 0 (no run can start). */
zw_status zw_ident_init(zw_ident *id, const zw_ident_limits *limits, float *command, float *position,
                        uint_least32_t capacity);

/* Start a run from the position x_now.  Refused, changing nothing: ZW_ERR_NULL; ZW_ERR_BUSY
 * while a run is playing; ZW_ERR_NAN / ZW_ERR_INF for x_now or the amplitude; ZW_ERR_ARG for
 * an unknown kind, hold 0 (PRBS), an amplitude not in (0, amplitude_max], samples 0 or above
 * min(samples_max, capacity). */
zw_status zw_ident_start(zw_ident *id, const zw_ident_request *request, float x_now);

/* One control sample: the measured position x and velocity v.  While RUNNING and within the
 * limits, *command is the excitation's value for this sample, recorded with x; the run is
 * DONE after its last sample.  Out of a limit it trips (*command = 0, nothing recorded).
 * Not running: *command = 0.  ZW_ERR_NULL for NULL id (then *command = 0 if command is not
 * NULL) or NULL command. */
zw_status zw_ident_step(zw_ident *id, float x, float v, float *command);

/* Stop a playing run (TRIPPED, ZW_IDENT_TRIP_ABORTED); no effect otherwise or for NULL. */
void zw_ident_abort(zw_ident *id);

/* True while a run is playing (false for NULL). */
bool zw_ident_running(const zw_ident *id);

/* Sample i (< recorded) of the last run: ZW_ERR_ARG for i out of range or a run still
 * playing (the samples are read after it), ZW_ERR_NULL; on an error both outputs are NaN. */
zw_status zw_ident_sample(const zw_ident *id, uint_least32_t i, float *command, float *position);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_IDENT_H */
