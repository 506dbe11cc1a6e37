/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): the identification experiment
 * (zwidth/ident.h), with every input unconstrained.
 *
 * eva-modules: ident
 * eva-slevel: drive_run:40
 *
 * A read of a volatile is any value of its type (eva_any.h): the ceilings, the request's
 * fields, the start position and every sample's x and v (NaN and both infinities included),
 * the capacity any value up to the buffers' ZW_EVA_CAP.  Each entry point is called with
 * every pointer valid and with every pointer independently NULL or valid, and every output
 * is read afterwards (the fail-safe rule).  A run of ZW_EVA_STEPS samples (more than the
 * buffers hold) is played with the run aborted or not at any point, then every sample index
 * up to beyond the buffers is read.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/ident.h"
#include "eva_any.h"

#define ZW_EVA_CAP 8u
#define ZW_EVA_STEPS 12u

volatile float any_float_source;
volatile uint_least32_t any_u32_source;
volatile uint_least16_t any_u16_source;
volatile float sink_float;

static float any_float(void) { return any_float_source; }

static void drive_run(zw_ident *id)
{
    zw_ident_request r;
    unsigned i;
    float u = 0.0f, x = 0.0f;
    r.kind = any_u16_source;
    r.hold = any_u16_source;
    r.seed = any_u32_source;
    r.amplitude = any_float();
    r.samples = any_u32_source;
    sink_int = (int)zw_ident_start(id, &r, any_float());
    (void)zw_ident_start(maybe_null(id), maybe_null(&r), any_float());
    /*@ loop unroll ZW_EVA_STEPS; */
    for (i = 0u; i < ZW_EVA_STEPS; ++i) {
        sink_int = (int)zw_ident_step(id, any_float(), any_float(), &u);
        sink_float = u;
        if (any_bool()) {
            zw_ident_abort(id);
        }
        sink_int = zw_ident_running(id) ? 1 : 0;
    }
    (void)zw_ident_step(maybe_null(id), any_float(), any_float(), maybe_null(&u));
    sink_float = u;
    zw_ident_abort(maybe_null(id));
    sink_int = zw_ident_running(maybe_null(id)) ? 1 : 0;
    /*@ loop unroll ZW_EVA_CAP + 2u; */
    for (i = 0u; i < ZW_EVA_CAP + 2u; ++i) {
        sink_int = (int)zw_ident_sample(id, (uint_least32_t)i, &u, &x);
        sink_float = u;
        sink_float = x;
    }
    (void)zw_ident_sample(maybe_null(id), any_u32_source, maybe_null(&u), maybe_null(&x));
    sink_float = u;
    sink_float = x;
}

int main(void)
{
    static float command[ZW_EVA_CAP], position[ZW_EVA_CAP];
    zw_ident id;
    zw_ident_limits l;
    uint_least32_t cap = any_u32_source;
    l.amplitude_max = any_float();
    l.x_window = any_float();
    l.v_max = any_float();
    l.samples_max = any_u32_source;
    if (cap > ZW_EVA_CAP) {
        cap = ZW_EVA_CAP; /* the contract: capacity entries in each buffer */
    }
    (void)zw_ident_init(maybe_null(&id), maybe_null(&l), maybe_null(command), maybe_null(position), cap);
    sink_int = (int)zw_ident_init(&id, &l, command, position, cap);
    drive_run(&id);
    return 0;
}
