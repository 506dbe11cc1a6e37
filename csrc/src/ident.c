/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* The identification experiment on the drive, zwidth/ident.h: a bounded excitation played
 * from the control loop, its samples recorded, the output off on any limit. */
#include "zwidth/ident.h"

#include <float.h>
#include <stddef.h>

#include "internal.h"

/* |x| <= FLT_MAX and not NaN, with comparisons only (no libm call in the control loop). */
static bool finite_f(float x)
{
    return (x == x) && (x <= FLT_MAX) && (x >= -FLT_MAX);
}

static float abs_f(float x)
{
    return (x < 0.0f) ? -x : x;
}

/* A ceiling: > 0 and finite; the status of its failure otherwise. */
static zw_status ceiling_status(float c)
{
    if (c != c) {
        return ZW_ERR_NAN;
    }
    if (!finite_f(c)) {
        return ZW_ERR_INF;
    }
    return (c > 0.0f) ? ZW_OK : ZW_ERR_ARG;
}

zw_status zw_ident_init(zw_ident *id, const zw_ident_limits *limits, float *command, float *position,
                        uint_least32_t capacity)
{
    zw_status st;
    if (id == NULL) {
        return ZW_ERR_NULL;
    }
    id->command = NULL;
    id->position = NULL;
    id->capacity = 0u;
    id->lfsr = 1u;
    id->recorded = 0u;
    id->x_start = 0.0f;
    id->level = 1.0f;
    id->request.kind = 0u;
    id->request.hold = 1u;
    id->request.seed = 1u;
    id->request.amplitude = 0.0f;
    id->request.samples = 0u;
    id->limits.amplitude_max = 0.0f;
    id->limits.x_window = 0.0f;
    id->limits.v_max = 0.0f;
    id->limits.samples_max = 0u;
    id->trip = ZW_IDENT_TRIP_NONE;
    id->state = ZW_IDENT_IDLE;
    if ((limits == NULL) || (command == NULL) || (position == NULL)) {
        return ZW_ERR_NULL;
    }
    st = ceiling_status(limits->amplitude_max);
    if (st == ZW_OK) {
        st = ceiling_status(limits->x_window);
    }
    if (st == ZW_OK) {
        st = ceiling_status(limits->v_max);
    }
    if ((st == ZW_OK) && ((limits->samples_max == 0u) || (capacity == 0u))) {
        st = ZW_ERR_ARG;
    }
    if (st != ZW_OK) {
        return st;
    }
    id->limits = *limits;
    id->command = command;
    id->position = position;
    id->capacity = capacity;
    return ZW_OK;
}

zw_status zw_ident_start(zw_ident *id, const zw_ident_request *request, float x_now)
{
    uint_least32_t most;
    float a;
    if ((id == NULL) || (request == NULL)) {
        return ZW_ERR_NULL;
    }
    if (id->state == ZW_IDENT_RUNNING) {
        return ZW_ERR_BUSY;
    }
    a = request->amplitude;
    if ((x_now != x_now) || (a != a)) {
        return ZW_ERR_NAN;
    }
    if (!finite_f(x_now) || !finite_f(a)) {
        return ZW_ERR_INF;
    }
    most = (id->limits.samples_max < id->capacity) ? id->limits.samples_max : id->capacity;
    if (((request->kind != ZW_IDENT_PRBS) && (request->kind != ZW_IDENT_STEPS)) ||
        ((request->kind == ZW_IDENT_PRBS) && (request->hold == 0u)) || !(a > 0.0f) ||
        !(a <= id->limits.amplitude_max) || (request->samples == 0u) || (request->samples > most)) {
        return ZW_ERR_ARG; /* also every request to an instance whose init failed (capacity 0) */
    }
    id->request = *request;
    id->lfsr = (request->seed != 0u) ? (request->seed & 0xFFFFFFFFu) : 1u;
    id->level = 1.0f;
    id->recorded = 0u;
    id->x_start = x_now;
    id->trip = ZW_IDENT_TRIP_NONE;
    id->state = ZW_IDENT_RUNNING;
    return ZW_OK;
}

/* xorshift32 (Marsaglia): period 2^32 - 1 over the nonzero states. */
static uint_least32_t xorshift32(uint_least32_t s)
{
    uint_least32_t x = s & 0xFFFFFFFFu;
    x ^= (x << 13) & 0xFFFFFFFFu;
    x ^= x >> 17;
    x ^= (x << 5) & 0xFFFFFFFFu;
    return x;
}

/* The excitation's value at sample n of the run (advances the PRBS at each new level). */
static float excitation(zw_ident *id, uint_least32_t n)
{
    const zw_ident_request *r = &id->request;
    float sign;
    if (r->kind == ZW_IDENT_PRBS) {
        /* hold >= 1 by zw_ident_start; 1 if the struct was written around it */
        uint_least32_t hold = (r->hold > 0u) ? (uint_least32_t)r->hold : 1u;
        if ((n % hold) == 0u) {
            id->lfsr = xorshift32(id->lfsr);
            id->level = ((id->lfsr & 1u) != 0u) ? 1.0f : -1.0f;
        }
        sign = id->level;
    } else {
        uint_least32_t quarter = r->samples / 4u;
        sign = ((n < quarter) || (n >= (3u * quarter))) ? 1.0f : -1.0f;
    }
    return sign * r->amplitude;
}

zw_status zw_ident_step(zw_ident *id, float x, float v, float *command)
{
    uint_least16_t trip = ZW_IDENT_TRIP_NONE;
    uint_least32_t n;
    float u;
    if (command != NULL) {
        *command = 0.0f;
    }
    if ((id == NULL) || (command == NULL)) {
        return ZW_ERR_NULL;
    }
    if (id->state != ZW_IDENT_RUNNING) {
        return ZW_OK;
    }
    n = id->recorded;
    if (!finite_f(x) || !finite_f(v)) {
        trip = ZW_IDENT_TRIP_NOT_FINITE;
    } else if (!(abs_f(x - id->x_start) <= id->limits.x_window)) {
        trip = ZW_IDENT_TRIP_POSITION; /* x - x_start overflowing to inf trips too */
    } else if (!(abs_f(v) <= id->limits.v_max)) {
        trip = ZW_IDENT_TRIP_VELOCITY;
    } else if ((n >= id->request.samples) || (n >= id->capacity) || (id->command == NULL) ||
               (id->position == NULL)) {
        id->state = ZW_IDENT_DONE; /* not reached through the API: the last sample ends the run */
        return ZW_OK;
    } else {
        /* within every limit: play and record */
    }
    if (trip != ZW_IDENT_TRIP_NONE) {
        id->trip = trip;
        id->state = ZW_IDENT_TRIPPED;
        return ZW_OK;
    }
    u = excitation(id, n);
    id->command[n] = u;
    id->position[n] = x;
    id->recorded = n + 1u;
    *command = u;
    if (id->recorded >= id->request.samples) {
        id->state = ZW_IDENT_DONE; /* written last: a reader seeing DONE sees every sample */
    }
    return ZW_OK;
}

void zw_ident_abort(zw_ident *id)
{
    if ((id != NULL) && (id->state == ZW_IDENT_RUNNING)) {
        id->trip = ZW_IDENT_TRIP_ABORTED;
        id->state = ZW_IDENT_TRIPPED;
    }
}

bool zw_ident_running(const zw_ident *id)
{
    return (id != NULL) && (id->state == ZW_IDENT_RUNNING);
}

zw_status zw_ident_sample(const zw_ident *id, uint_least32_t i, float *command, float *position)
{
    if (command != NULL) {
        *command = (float)ZW_NAN;
    }
    if (position != NULL) {
        *position = (float)ZW_NAN;
    }
    if ((id == NULL) || (command == NULL) || (position == NULL)) {
        return ZW_ERR_NULL;
    }
    if ((id->state == ZW_IDENT_RUNNING) || (i >= id->recorded) || (i >= id->capacity) || (id->command == NULL) ||
        (id->position == NULL)) {
        return ZW_ERR_ARG;
    }
    *command = id->command[i];
    *position = id->position[i];
    return ZW_OK;
}
