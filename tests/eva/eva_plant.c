/* SPDX-FileCopyrightText: 2026 The zwidth authors
   SPDX-License-Identifier: Apache-2.0 */
/* Frama-C Eva driver (tools/eva.sh, docs/eva.md): every public entry point of the plant
 * with its plant-side parts (plant.h) and of its enclosure over a delta interval
 * (plant_box.h), every input unconstrained.
 *
 * eva-modules: plant plant_box
 * eva-support: status coeffs
 *
 * As eva_ideal.c: a read of a volatile is any value of its type (NaN and infinities
 * included); a spec, a zw_coeffs and a zw_plant passed in have every field any value (a
 * plant with any order, garbage coefficients); every output is uninitialized before the
 * call and read after it, and each call is repeated with every pointer independently NULL
 * or valid.
 */
#include <stdbool.h>
#include <stddef.h>

#include "zwidth/plant.h"
#include "zwidth/plant_box.h"
#include "eva_any.h"

static void any_spec(zw_plant_spec *s)
{
    s->delta = any_real();
    s->kappa = any_real();
    s->lambda = any_real();
    s->delta_relerr = any_real();
    s->kappa_relerr = any_real();
    s->lambda_relerr = any_real();
}

static void any_plant(zw_plant *p)
{
    unsigned i;
    any_spec(&p->spec);
    p->order = any_unsigned_source;
    /*@ loop unroll ZW_PLANT_MAX_ORDER + 1u; */
    for (i = 0u; i <= ZW_PLANT_MAX_ORDER; ++i) {
        p->den[i] = any_real();
        p->den_err[i] = any_real();
        p->den_s[i] = any_real();
        p->den_s_err[i] = any_real();
        p->den_w[i] = any_real();
        p->den_w_err[i] = any_real();
    }
    /*@ loop unroll ZW_PLANT_MAX_ORDER; */
    for (i = 0u; i < ZW_PLANT_MAX_ORDER; ++i) {
        p->num[i] = any_real();
        p->num_err[i] = any_real();
        p->num_s[i] = any_real();
        p->num_s_err[i] = any_real();
    }
    any_coeffs(&p->c);
}

static void read_spec(const zw_plant_spec *s)
{
    sink_real = s->delta;
    sink_real = s->kappa;
    sink_real = s->lambda;
    sink_real = s->delta_relerr;
    sink_real = s->kappa_relerr;
    sink_real = s->lambda_relerr;
}

/* Every field, on every return: the fail-safe plant (order 0, every number NaN) on error,
 * and on success the coefficients with the unused entries NaN. */
static void read_plant(const zw_plant *p)
{
    unsigned i;
    sink_unsigned = p->order;
    read_spec(&p->spec);
    /*@ loop unroll ZW_PLANT_MAX_ORDER + 1u; */
    for (i = 0u; i <= ZW_PLANT_MAX_ORDER; ++i) {
        sink_real = p->den[i];
        sink_real = p->den_err[i];
        sink_real = p->den_s[i];
        sink_real = p->den_s_err[i];
        sink_real = p->den_w[i];
        sink_real = p->den_w_err[i];
    }
    /*@ loop unroll ZW_PLANT_MAX_ORDER; */
    for (i = 0u; i < ZW_PLANT_MAX_ORDER; ++i) {
        sink_real = p->num[i];
        sink_real = p->num_err[i];
        sink_real = p->num_s[i];
        sink_real = p->num_s_err[i];
    }
    sink_real = p->c.delta;
    sink_real = p->c.e;
    sink_real = p->c.c1;
    sink_real = p->c.c2;
    sink_real = p->c.d12;
    sink_real = p->c.s;
    sink_real = p->c.g;
    sink_real = p->c.sigma;
    sink_real = p->c.hs;
    sink_real = p->c.delta_relerr;
}

static void drive_init(void)
{
    zw_plant_spec spec;
    zw_plant plant;
    any_spec(&spec);
    (void)zw_plant_init(&plant, &spec);
    read_plant(&plant);
    (void)zw_plant_init(maybe_null(&plant), maybe_null(&spec));
}

static void drive_from_coeffs(void)
{
    zw_coeffs c;
    zw_plant plant;
    any_coeffs(&c);
    (void)zw_plant_from_coeffs(&plant, &c);
    read_plant(&plant);
    (void)zw_plant_from_coeffs(maybe_null(&plant), maybe_null(&c));
}

static void drive_enclose(void)
{
    zw_plant plant;
    (void)zw_plant_enclose(&plant, any_real(), any_real());
    read_plant(&plant);
    (void)zw_plant_enclose(maybe_null(&plant), any_real(), any_real());
    (void)zw_plant_enclose2(&plant, any_real(), any_real(), any_real(), any_real());
    read_plant(&plant);
    (void)zw_plant_enclose2(maybe_null(&plant), any_real(), any_real(), any_real(), any_real());
}

static void drive_eval(void)
{
    zw_plant plant;
    zw_real nr, ni, ne, dr, di, de;
    any_plant(&plant);
    (void)zw_plant_eval(&plant, any_real(), any_real(), &nr, &ni, &ne, &dr, &di, &de);
    sink_real = nr;
    sink_real = ni;
    sink_real = ne;
    sink_real = dr;
    sink_real = di;
    sink_real = de;
    (void)zw_plant_eval(maybe_null(&plant), any_real(), any_real(), maybe_null(&nr),
                        maybe_null(&ni), maybe_null(&ne), maybe_null(&dr), maybe_null(&di),
                        maybe_null(&de));
}

static void drive_spec_from_device(void)
{
    zw_plant_spec spec;
    zw_real mass;
    (void)zw_plant_spec_from_device(any_real(), any_real(), any_real(), any_real(), any_real(),
                                    any_real(), any_real(), any_real(), &spec, &mass);
    read_spec(&spec);
    sink_real = mass;
    (void)zw_plant_spec_from_device(any_real(), any_real(), any_real(), any_real(), any_real(),
                                    any_real(), any_real(), any_real(), maybe_null(&spec),
                                    maybe_null(&mass));
}

int main(void)
{
    drive_init();
    drive_from_coeffs();
    drive_enclose();
    drive_eval();
    drive_spec_from_device();
    return 0;
}
