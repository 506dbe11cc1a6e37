/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* sim.c - the sampled impedance loop of paper Fig. 13 with the effects a scene asks for.
 *
 * Two loops: run_linear for the ideal loop (no effect flag: the exact step and the
 * controller, nothing else), run_general for everything else, where each effect is one
 * branch on a loop-invariant flag.  See sim.h for the model and the contract.
 */
#include "zwidth/sim.h"

#include <stdint.h>
#include <string.h>

#include "zwidth/coeffs.h"
#include "zwidth/device.h"

#define ZW_TWO_PI ZW_R(6.28318530717958647692)
#define ZW_SIM_INF ZW_HUGE_VAL

/* ---- validation --------------------------------------------------------------------- */

/* NaN -> ZW_ERR_NAN, +-inf -> ZW_ERR_INF, else ZW_OK. */
static zw_status finite_value(zw_real x) {
    if (ZW_IS_NAN(x)) return ZW_ERR_NAN;
    if (!ZW_IS_FINITE(x)) return ZW_ERR_INF;
    return ZW_OK;
}

/* Check a list of values for NaN / inf in one place; the first bad one decides. */
static zw_status all_finite(const zw_real *values, size_t n) {
    size_t i;
    for (i = 0; i < n; ++i) {
        zw_status st = finite_value(values[i]);
        if (st != ZW_OK) return st;
    }
    return ZW_OK;
}

/* A value that may be +inf ("never", "at once") but not NaN or -inf. */
static zw_status not_nan_nor_minus_inf(zw_real x) {
    if (ZW_IS_NAN(x)) return ZW_ERR_NAN;
    if (x < -ZW_REAL_MAX) return ZW_ERR_INF;
    return ZW_OK;
}

#define ZW_TRY(expr)                       \
    do {                                   \
        zw_status zw_try_st_ = (expr);     \
        if (zw_try_st_ != ZW_OK) return zw_try_st_; \
    } while (0)
#define ZW_REQUIRE(cond) \
    do {                 \
        if (!(cond)) return ZW_ERR_ARG; \
    } while (0)

static zw_status validate_hand(const zw_sim_hand *h) {
    const zw_real finite[] = {h->mass, h->stiffness, h->damping, h->t_grasp, h->from, h->to};
    ZW_TRY(all_finite(finite, sizeof finite / sizeof finite[0]));
    ZW_TRY(not_nan_nor_minus_inf(h->t_release));
    ZW_TRY(not_nan_nor_minus_inf(h->speed));
    ZW_REQUIRE(h->mass >= 0 && h->stiffness >= 0 && h->damping >= 0);
    ZW_REQUIRE(h->t_grasp >= 0 && h->t_release > h->t_grasp && h->speed > 0);
    return ZW_OK;
}

static zw_status validate_knob(const zw_sim_knob *kb) {
    const zw_real finite[] = {kb->first, kb->pitch, kb->k_detent, kb->k_end, kb->damping};
    ZW_TRY(all_finite(finite, sizeof finite / sizeof finite[0]));
    ZW_REQUIRE(kb->pitch > 0 && kb->count >= 2 && kb->k_detent > 0 && kb->k_end > 0);
    /* The last detent must be a finite position. */
    ZW_REQUIRE(ZW_IS_FINITE(kb->first + (zw_real)(kb->count - 1) * kb->pitch));
    return ZW_OK;
}

static zw_status validate_schedule(const zw_sim_segment *seg, size_t len) {
    size_t i;
    if (seg == NULL) return ZW_ERR_NULL;
    if (len == 0) return ZW_ERR_ARG;
    for (i = 0; i < len; ++i) {
        const zw_real finite[] = {seg[i].t_start, seg[i].K, seg[i].B};
        ZW_TRY(all_finite(finite, sizeof finite / sizeof finite[0]));
        ZW_REQUIRE(i == 0 ? seg[i].t_start == 0 : seg[i].t_start > seg[i - 1].t_start);
    }
    return ZW_OK;
}

/* A bound on the modulus of every eigenvalue of the continuous part, m s^2 + c s + k:
 * |s| <= c/m + sqrt(k/m), for the plant alone and for the plant held by the hand. */
static zw_real fastest_rate(const zw_sim_scene *sc) {
    zw_real rate = sc->b / sc->m;
    if (sc->effects & ZW_SIM_HAND) {
        const zw_real m = sc->m + sc->hand.mass;
        const zw_real held = (sc->b + sc->hand.damping) / m + ZW_SQRT(sc->hand.stiffness / m);
        if (held > rate) rate = held;
    }
    if ((sc->effects & ZW_SIM_ACTUATOR_LAG) && 1 / sc->actuator_tau > rate) rate = 1 / sc->actuator_tau;
    return rate;
}

static zw_status validate_scene(const zw_sim_scene *sc) {
    const unsigned fx = sc->effects;
    {
        const zw_real finite[] = {sc->x_init, sc->v_init, sc->x_eq_before, sc->x_eq_after};
        ZW_TRY(all_finite(finite, sizeof finite / sizeof finite[0]));
    }
    ZW_TRY(not_nan_nor_minus_inf(sc->t_step));
    ZW_REQUIRE(sc->t_step >= 0);
    ZW_REQUIRE((fx & ~(unsigned)ZW_SIM_ALL_EFFECTS) == 0u);
    ZW_REQUIRE(!((fx & ZW_SIM_KNOB) && (fx & ZW_SIM_SCHEDULE)));
    if (!(fx & (ZW_SIM_KNOB | ZW_SIM_SCHEDULE))) {
        const zw_real gains[] = {sc->K, sc->B};
        ZW_TRY(all_finite(gains, 2));
    }
    if (fx & ZW_SIM_QUANTIZATION) {
        ZW_TRY(finite_value(sc->counts_per_unit));
        ZW_REQUIRE(sc->counts_per_unit > 0);
    }
    if (fx & ZW_SIM_FRICTION) {
        const zw_real forces[] = {sc->coulomb, sc->stiction};
        ZW_TRY(all_finite(forces, 2));
        ZW_REQUIRE(sc->coulomb >= 0 && sc->stiction >= sc->coulomb && sc->stiction > 0);
    }
    if (fx & ZW_SIM_DELAY) ZW_REQUIRE(sc->delay_samples >= 1 && sc->delay_samples <= ZW_SIM_MAX_DELAY);
    if (fx & ZW_SIM_SATURATION) {
        ZW_TRY(finite_value(sc->force_max));
        ZW_REQUIRE(sc->force_max > 0);
    }
    if (fx & ZW_SIM_VELOCITY_FILTER) {
        ZW_TRY(finite_value(sc->cutoff_hz));
        ZW_REQUIRE(sc->cutoff_hz > 0);
    }
    if (fx & ZW_SIM_AVERAGE) {
        ZW_REQUIRE(!(fx & ZW_SIM_VELOCITY_FILTER)); /* one velocity filter, as loop.h */
        ZW_REQUIRE(sc->average_samples >= 1 && sc->average_samples <= ZW_SIM_MAX_AVERAGE);
    }
    if (fx & ZW_SIM_ACTUATOR_LAG) {
        ZW_TRY(finite_value(sc->actuator_tau));
        ZW_REQUIRE(sc->actuator_tau > 0 && !(fx & ZW_SIM_FRICTION));
    }
    if (fx & ZW_SIM_HAND) ZW_TRY(validate_hand(&sc->hand));
    if (fx & ZW_SIM_WALL) {
        const zw_real finite[] = {sc->wall.position, sc->wall.stiffness, sc->wall.damping};
        ZW_TRY(all_finite(finite, 3));
        ZW_REQUIRE(sc->wall.stiffness > 0 && (sc->wall.side == 1 || sc->wall.side == -1));
    }
    if (fx & ZW_SIM_KNOB) ZW_TRY(validate_knob(&sc->knob));
    if (fx & ZW_SIM_SCHEDULE) ZW_TRY(validate_schedule(sc->schedule, sc->schedule_len));
    if (fx & ZW_SIM_CONTINUOUS) {
        ZW_REQUIRE(sc->substeps >= 1 && sc->substeps <= ZW_SIM_MAX_SUBSTEPS);
        ZW_REQUIRE(fastest_rate(sc) * (sc->T / (zw_real)sc->substeps) <= ZW_SIM_RK4_LIMIT);
    }
    return ZW_OK;
}

/* The first sample index k with k T >= t_step, computed the way the loop compares (k T in
 * zw_real); SIZE_MAX for t_step = +inf (no step).  ZW_ERR_RANGE when t_step / T is not
 * below 2^p (p = 24 float, 53 double), where consecutive counts stop being distinct
 * zw_real values and the search below would not end, or not below SIZE_MAX (16- and
 * 32-bit size_t).  Below both, k = (size_t)q is in range and one step up suffices: an
 * integer between q = fl(t_step / T) and t_step / T would be nearer to it than q. */
static zw_status first_sample_at(zw_real t_step, zw_real T, size_t *first) {
    const zw_real exact_counts = ZW_R(1.0) / ZW_UNIT_ROUNDOFF;   /* 2^p */
    /* May round up to 2^bits; q below it then still floors to at most SIZE_MAX - 1. */
    const zw_real counter_max = (zw_real)SIZE_MAX;
    zw_real q;
    size_t k;
    if (!(t_step <= ZW_REAL_MAX)) {   /* +inf: never */
        *first = SIZE_MAX;
        return ZW_OK;
    }
    q = t_step / T;
    if (!(q < exact_counts && q < counter_max)) return ZW_ERR_RANGE;   /* also q = +inf */
    k = (size_t)q;
    while (k > 0 && (zw_real)(k - 1) * T >= t_step) --k;
    while ((zw_real)k * T < t_step) ++k;
    *first = k;
    return ZW_OK;
}

zw_status zw_sim_init(zw_sim *sim, const zw_sim_scene *scene) {
    zw_device dev;
    zw_sim s;
    size_t k_step;
    if (sim == NULL || scene == NULL) return ZW_ERR_NULL;
    ZW_TRY(zw_device_init(&dev, scene->m, scene->b, scene->T));
    ZW_TRY(validate_scene(scene));
    ZW_TRY(first_sample_at(scene->t_step, scene->T, &k_step));

    memset(&s, 0, sizeof s);
    s.scene = *scene;
    /* The exact ZOH step in the coefficients of coeffs.h: phi = (1 - e)/delta = s/2,
     * (1 - e) m / b = T phi, (T - (1 - e) m/b)/b = (T^2/m) c1/2, (1 - e)/b = (T/m) phi. */
    s.e = dev.co.e;
    s.phi_T = scene->T * (dev.co.s / 2);
    s.x_gain = (scene->T / scene->m) * scene->T * (dev.co.c1 / 2);
    s.v_gain = (scene->T / scene->m) * (dev.co.s / 2);
    s.k_step = k_step;
    if (scene->effects & ZW_SIM_VELOCITY_FILTER)
        s.filter_a = ZW_EXP(-ZW_TWO_PI * scene->cutoff_hz * scene->T);
    if (scene->effects & ZW_SIM_ACTUATOR_LAG) {
        s.lag_rate = 1 / scene->actuator_tau;
        s.lag_decay = ZW_EXP(-scene->T * s.lag_rate);
    }
    s.x = scene->x_init;
    s.v = scene->v_init;
    s.stuck = scene->v_init == 0;
    *sim = s;
    return ZW_OK;
}

/* ---- the pieces of one sample ------------------------------------------------------- */

/* Stiffness and equilibrium of the detent knob at x (paper Fig. 22(b)). */
static void knob_map(const zw_sim_knob *kb, zw_real x, zw_real *K, zw_real *x_eq) {
    const zw_real last = kb->first + (zw_real)(kb->count - 1) * kb->pitch;
    if (ZW_IS_NAN(x)) {   /* a run that blew up: keep the NaN, never convert it to int */
        *K = x;
        *x_eq = x;
        return;
    }
    if (x <= kb->first || x >= last) {
        *K = kb->k_end;
        *x_eq = x <= kb->first ? kb->first : last;
    } else {
        zw_real u = (x - kb->first) / kb->pitch;
        int i = (int)(u + ZW_R(0.5));   /* nearest detent; u > 0 so truncation is floor */
        zw_real p, d;
        if (i > kb->count - 1) i = kb->count - 1;
        p = kb->first + (zw_real)i * kb->pitch;
        d = x - p;
        if (ZW_FABS(d) <= kb->pitch / 4) {
            *K = kb->k_detent;
            *x_eq = p;
        } else {
            *K = -kb->k_detent;
            *x_eq = d > 0 ? p + kb->pitch / 2 : p - kb->pitch / 2;
        }
    }
}

/* The unilateral wall's force on the handle (never pulling it in). */
static zw_real wall_force(const zw_sim_wall *w, zw_real x_meas, zw_real v_est) {
    zw_real f;
    if (w->side > 0 ? !(x_meas > w->position) : !(x_meas < w->position)) return 0;
    f = w->stiffness * (w->position - x_meas) - w->damping * v_est;
    return w->side > 0 ? (f < 0 ? f : 0) : (f > 0 ? f : 0);
}

/* The pieces of the hand's motion: not held, held while its intended position moves,
 * held after that position arrived.  The integrator fixes the piece once per substep
 * (at its midpoint), so every RK4 stage sees one smooth force and stays 4th order away
 * from the few substeps that hold a grasp, a release or an arrival. */
typedef enum zw_hand_phase { ZW_HAND_OFF, ZW_HAND_MOVING, ZW_HAND_ARRIVED } zw_hand_phase;

static bool hand_arrived(const zw_sim_hand *h, zw_real t) {
    /* speed = +inf is a step (and inf * 0 at t_grasp must not make a NaN). */
    return !(h->speed <= ZW_REAL_MAX) || !(h->speed * (t - h->t_grasp) < ZW_FABS(h->to - h->from));
}

static zw_hand_phase hand_phase(const zw_sim_hand *h, zw_real t) {
    if (!(t >= h->t_grasp && t < h->t_release)) return ZW_HAND_OFF;
    return hand_arrived(h, t) ? ZW_HAND_ARRIVED : ZW_HAND_MOVING;
}

/* Intended position and velocity on a piece (MOVING extends the ramp past its end, so one
 * formula serves a whole substep). */
static void hand_path(const zw_sim_hand *h, zw_hand_phase phase, zw_real t, zw_real *xh,
                      zw_real *vh) {
    if (phase == ZW_HAND_MOVING) {
        const zw_real velocity = h->to > h->from ? h->speed : -h->speed;
        *xh = h->from + velocity * (t - h->t_grasp);
        *vh = velocity;
    } else {
        *xh = h->to;
        *vh = 0;
    }
}

/* The intended position at t, for the trace: `from` until the grasp. */
static zw_real hand_target(const zw_sim_hand *h, zw_real t) {
    zw_real xh, vh;
    if (t <= h->t_grasp) return h->from;
    hand_path(h, hand_arrived(h, t) ? ZW_HAND_ARRIVED : ZW_HAND_MOVING, t, &xh, &vh);
    return xh;
}

/* Force of the hand on the handle at (t, x, v) on a piece; 0 when not held. */
static zw_real hand_force(const zw_sim_hand *h, zw_hand_phase phase, zw_real t, zw_real x,
                          zw_real v) {
    zw_real xh, vh;
    if (phase == ZW_HAND_OFF) return 0;
    hand_path(h, phase, t, &xh, &vh);
    return h->stiffness * (xh - x) + h->damping * (vh - v);
}

/* The continuous part over one substep. */
typedef struct zw_substep {
    const zw_sim_scene *sc;
    zw_hand_phase hand;  /* ZW_HAND_OFF also when the scene has no hand */
    zw_real applied;     /* the zero-order-held controller force */
    zw_real lag_start;   /* ACTUATOR_LAG: f(t0) - applied, decaying at lag_rate from t0 */
    zw_real lag_rate, t0;
    zw_real friction;    /* constant over the substep */
    zw_real inv_mass;    /* 1 / (m, plus m_h while held) */
} zw_substep;

static zw_real acceleration(const zw_substep *st, zw_real t, zw_real x, zw_real v) {
    zw_real f = st->applied + st->friction - st->sc->b * v;
    if (st->lag_start != 0) f += st->lag_start * ZW_EXP(-(t - st->t0) * st->lag_rate);
    if (st->hand != ZW_HAND_OFF) f += hand_force(&st->sc->hand, st->hand, t, x, v);
    return f * st->inv_mass;
}

/* Classical RK4 on (x, v) over [t, t + h]. */
static void rk4(const zw_substep *st, zw_real t, zw_real h, zw_real *x, zw_real *v) {
    const zw_real x0 = *x, v0 = *v, h2 = h / 2;
    const zw_real a1 = acceleration(st, t, x0, v0);
    const zw_real v1 = v0 + h2 * a1;
    const zw_real a2 = acceleration(st, t + h2, x0 + h2 * v0, v1);
    const zw_real v2 = v0 + h2 * a2;
    const zw_real a3 = acceleration(st, t + h2, x0 + h2 * v1, v2);
    const zw_real v3 = v0 + h * a3;
    const zw_real a4 = acceleration(st, t + h, x0 + h * v2, v3);
    *x = x0 + (h / 6) * (v0 + 2 * v1 + 2 * v2 + v3);
    *v = v0 + (h / 6) * (a1 + 2 * a2 + 2 * a3 + a4);
}

static zw_real sign_of(zw_real x) { return x > 0 ? ZW_R(1.0) : (x < 0 ? ZW_R(-1.0) : ZW_R(0.0)); }

/* Most friction events (stops, break-aways) located inside one substep; past that the
 * substep ends the old way (v = 0 at its end, an O(h) event).  Two suffice for any motion
 * resolved by the step; the bound only keeps a degenerate case (events rounding-sized
 * times apart) from looping. */
#define ZW_SIM_MAX_EVENTS 8
/* Illinois steps to locate a stop; it converges superlinearly (about 10 steps to the
 * tolerance below from any bracket), bisection-safe. */
#define ZW_SIM_STOP_ITERATIONS 100

/* The forces on a resting plant other than friction, at time t. */
static zw_real resting_force(const zw_substep *st, zw_real t, zw_real x) {
    return st->applied + hand_force(&st->sc->hand, st->hand, t, x, 0);
}

/* How long after t (within span) stiction holds a resting plant, and the direction it then
 * slides.  The resting force is affine in time on one hand piece (slope k_h times the
 * target's velocity while the hand moves, else constant: the force is zero-order held), so
 * the time it leaves the band [-F_s, F_s] is solved exactly.  Returns span when it holds
 * throughout.  A force that is not a number slides (direction 0) so the NaN propagates:
 * a blown-up run is never held at rest. */
static zw_real held_for(const zw_substep *st, zw_real t, zw_real span, zw_real x, zw_real *direction) {
    const zw_sim_hand *hd = &st->sc->hand;
    const zw_real now = resting_force(st, t, x), band = st->sc->stiction;
    zw_real slope = 0, dt;
    if (!(ZW_FABS(now) <= band)) {
        *direction = sign_of(now);
        return 0;
    }
    if (st->hand == ZW_HAND_MOVING) slope = hd->stiffness * (hd->to > hd->from ? hd->speed : -hd->speed);
    *direction = sign_of(slope);
    if (!(slope != 0)) return span;
    dt = ((slope > 0 ? band : -band) - now) / slope;
    if (!(dt < span)) return span;
    return dt > 0 ? dt : 0;
}

/* The stop of a slide: the s in (0, span] where the velocity of an RK4 step of length s
 * from (x, v) reaches 0, by Illinois regula falsi on g(s) = direction v(s), g(0) >= 0 >=
 * g(span) (g_span, at the position x_span); *x becomes the position there.  Located to a few roundings of the
 * substep, far below RK4's error, so the stop adds none of its own. */
static zw_real stop_time(const zw_substep *st, zw_real t, zw_real span, zw_real direction,
                         zw_real *x, zw_real v, zw_real g_span, zw_real x_span) {
    const zw_real tolerance = ZW_R(8.0) * ZW_UNIT_ROUNDOFF * span;
    zw_real lo = 0, hi = span, g_lo = direction * v, g_hi = g_span, x_hi = x_span;
    int side = 0, i;
    for (i = 0; i < ZW_SIM_STOP_ITERATIONS && g_hi < 0 && hi - lo > tolerance; ++i) {
        zw_real s = lo + (hi - lo) * (g_lo / (g_lo - g_hi)), xs = *x, vs = v, g;
        if (!(s > lo && s < hi)) s = lo + (hi - lo) / 2;
        rk4(st, t, s, &xs, &vs);
        g = direction * vs;
        if (g > 0) {
            lo = s;
            g_lo = g;
            if (side == -1) g_hi /= 2;
            side = -1;
        } else {
            hi = s;
            g_hi = g;
            x_hi = xs;
            if (side == 1) g_lo /= 2;
            side = 1;
        }
    }
    *x = x_hi;
    return hi;
}

/* The plant under Coulomb friction over one substep [t, t + h]: it slides with the
 * friction of its direction, stops where that RK4 solution's velocity reaches 0 (located,
 * not at the substep's end), and from the stop, as from any rest, stiction holds it or it
 * slips, at the exact time the other forces leave the stiction band.  Each piece between
 * events is an RK4 step of a smooth ODE, so friction keeps RK4's 4th order (tested
 * against an event-located reference).  Returns the friction force at t (for the trace). */
static zw_real friction_substep(zw_substep *st, zw_real t, zw_real h, zw_real *x, zw_real *v,
                                bool *stuck) {
    const zw_real coulomb = st->sc->coulomb;
    zw_real at_start = 0, done = 0;
    int events;
    for (events = 0; done < h; ++events) {
        zw_real direction, xe, ve;
        if (*v == 0) *stuck = true;   /* at rest (also a velocity the loop flushed to 0) */
        if (*stuck) {
            const zw_real hold = held_for(st, t + done, h - done, *x, &direction);
            /* At t: the holding force, or the sliding friction of a break-away at t. */
            if (events == 0) at_start = hold > 0 ? -resting_force(st, t, *x) : -coulomb * direction;
            *v = 0;
            if (!(hold < h - done)) return at_start;   /* held to the substep's end */
            done += hold;
            *stuck = false;
        } else {
            direction = sign_of(*v);
            if (events == 0) at_start = -coulomb * direction;
        }
        st->friction = -coulomb * direction;
        xe = *x;
        ve = *v;
        rk4(st, t + done, h - done, &xe, &ve);
        if (!(ve * direction <= 0) || !(direction != 0) || events >= ZW_SIM_MAX_EVENTS) {
            /* Still sliding at the end (or NaN, propagated; or out of events: stop there). */
            *x = xe;
            *v = ve;
            if (ve * direction <= 0 && direction != 0) {
                *v = 0;
                *stuck = true;
            }
            return at_start;
        }
        done += stop_time(st, t + done, h - done, direction, x, *v, direction * ve, xe);
        *v = 0;
        *stuck = true;
    }
    return at_start;
}

/* Advance the plant over one sample under the continuous effects (and *lagged, the
 * actuator's force, with ACTUATOR_LAG); returns the friction force at the sample's start
 * (for the trace). */
static zw_real integrate_sample(const zw_sim *sim, zw_real t, zw_real applied,
                               zw_real *x, zw_real *v, bool *stuck, zw_real *lagged) {
    const zw_sim_scene *sc = &sim->scene;
    const bool friction = (sc->effects & ZW_SIM_FRICTION) != 0;
    const bool hand = (sc->effects & ZW_SIM_HAND) != 0;
    const zw_real h = sc->T / (zw_real)sc->substeps;
    zw_real friction_at_start = 0;
    zw_substep st;
    int_least32_t i;
    st.sc = sc;
    st.applied = applied;
    st.friction = 0;
    st.lag_start = 0;
    st.lag_rate = 0;
    st.t0 = t;
    if (sc->effects & ZW_SIM_ACTUATOR_LAG) {
        st.lag_rate = sim->lag_rate;
        st.lag_start = *lagged - applied;
        *lagged = applied + st.lag_start * sim->lag_decay;
    }
    /* Without a hand the force on a resting plant is the held one for the whole sample:
     * within the stiction band it holds every substep, so skip them. */
    if (friction && !hand && *v == 0 && ZW_FABS(applied) <= sc->stiction) {
        *stuck = true;
        return -applied;
    }
    for (i = 0; i < sc->substeps; ++i) {
        const zw_real ts = t + (zw_real)i * h;
        zw_real mass = sc->m;
        st.hand = hand ? hand_phase(&sc->hand, ts + h / 2) : ZW_HAND_OFF;
        if (st.hand != ZW_HAND_OFF) mass += sc->hand.mass;
        st.inv_mass = 1 / mass;
        if (friction) {
            const zw_real f = friction_substep(&st, ts, h, x, v, stuck);
            if (i == 0) friction_at_start = f;
        } else {
            rk4(&st, ts, h, x, v);
        }
    }
    return friction_at_start;
}

/* Store a value if the signal is recorded.  Both loops write their trace entry by entry:
 * gathering a sample into a struct for one shared store function made the bare loop 1.4x
 * slower (bench-sim), which is the price an absent effect must not pay. */
#define ZW_RECORD(array, j, value) \
    do {                           \
        if ((array) != NULL) (array)[j] = (value); \
    } while (0)

/* ---- the loops ---------------------------------------------------------------------- */

/* The ideal loop: constant gains, the reference step, the exact step.  Kept apart so a
 * scene without effects pays for none of their flags. */
static void run_linear(zw_sim *sim, size_t n, const zw_sim_trace *tr) {
    const zw_sim_scene *sc = &sim->scene;
    const zw_real K = sc->K, B_over_T = sc->B / sc->T, T = sc->T;
    const zw_real e = sim->e, phi_T = sim->phi_T, x_gain = sim->x_gain, v_gain = sim->v_gain;
    zw_real x = sim->x, v = sim->v;
    zw_real x_prev = sim->started ? sim->x_meas_prev : x;
    /* The step's index within this call, so the loop compares a local. */
    const size_t j_step = sim->k_step > sim->k ? sim->k_step - sim->k : 0;
    size_t j;
    for (j = 0; j < n; ++j) {
        const size_t k = sim->k + j;
        const zw_real x_eq = j >= j_step ? sc->x_eq_after : sc->x_eq_before;
        const zw_real F = K * (x_eq - x) - B_over_T * (x - x_prev);
        ZW_RECORD(tr->t, j, (zw_real)k * T);
        ZW_RECORD(tr->x, j, x);
        ZW_RECORD(tr->v, j, v);
        ZW_RECORD(tr->x_measured, j, x);
        ZW_RECORD(tr->force, j, F);
        ZW_RECORD(tr->force_command, j, F);
        ZW_RECORD(tr->stiffness, j, K);
        ZW_RECORD(tr->stiffness_planned, j, K);
        ZW_RECORD(tr->damping, j, sc->B);
        ZW_RECORD(tr->wall_force, j, 0);
        ZW_RECORD(tr->friction, j, 0);
        ZW_RECORD(tr->hand_force, j, 0);
        ZW_RECORD(tr->hand_target, j, 0);
        x_prev = x;
        {
            const zw_real x_next = x + phi_T * v + x_gain * F;
            v = e * v + v_gain * F;
            x = x_next;
        }
    }
    sim->x = x;
    sim->v = v;
    if (n > 0) {
        sim->x_meas_prev = x_prev;
        sim->started = true;
    }
    sim->k += n;
}

/* The velocity estimate v_est_k of sim.h from the measured step dx: the differentiator,
 * then the low-pass or the moving average. */
static zw_real velocity_estimate(zw_sim *sim, zw_real dx, zw_real *v_filtered) {
    const zw_sim_scene *sc = &sim->scene;
    const unsigned fx = sc->effects;
    zw_real v_d = dx / sc->T;
    if (fx & ZW_SIM_TUSTIN) {
        v_d = 2 * v_d - sim->v_diff;
        sim->v_diff = v_d;
    }
    if (fx & ZW_SIM_VELOCITY_FILTER) {
        *v_filtered = sim->filter_a * *v_filtered + (1 - sim->filter_a) * v_d;
        return *v_filtered;
    }
    if (fx & ZW_SIM_AVERAGE) {
        zw_real sum = 0;
        int i;
        sim->average_line[sim->average_head] = v_d;
        if (++sim->average_head == sc->average_samples) sim->average_head = 0;
        for (i = 0; i < sc->average_samples; ++i) sum += sim->average_line[i];
        return sum / (zw_real)sc->average_samples;
    }
    return v_d;
}

/* Everything else: one branch per effect on a loop-invariant flag.  The state lives in
 * locals (the trace arrays could alias *sim) and is written back at the end. */

static void run_general(zw_sim *sim, size_t n, const zw_sim_trace *tr) {
    const zw_sim_scene *sc = &sim->scene;
    const unsigned fx = sc->effects;
    const zw_real T = sc->T;
    const unsigned ESTIMATORS = ZW_SIM_TUSTIN | ZW_SIM_VELOCITY_FILTER | ZW_SIM_AVERAGE;
    zw_real x = sim->x, v = sim->v, x_meas_prev = sim->x_meas_prev, v_filtered = sim->v_filtered;
    zw_real lagged = sim->force_lagged;
    bool stuck = sim->stuck;
    size_t j;
    for (j = 0; j < n; ++j) {
        const size_t k = sim->k + j;
        const zw_real t = (zw_real)k * T;
        zw_real x_meas = x, dx, K, B, x_eq, K_planned, F_cmd, F, applied, friction = 0, v_est;
        zw_real wall = 0;

        if (fx & ZW_SIM_QUANTIZATION) x_meas = ZW_FLOOR(x * sc->counts_per_unit) / sc->counts_per_unit;
        if (k == 0 && !sim->started) x_meas_prev = x_meas;
        dx = x_meas - x_meas_prev;

        /* Gains and equilibrium: the knob's map, the schedule, or the constants. */
        if (fx & ZW_SIM_KNOB) {
            zw_real unused;
            knob_map(&sc->knob, x_meas, &K, &x_eq);
            knob_map(&sc->knob, x, &K_planned, &unused);
            B = sc->knob.damping;
        } else {
            if (fx & ZW_SIM_SCHEDULE) {
                while (sim->schedule_index + 1 < sc->schedule_len &&
                       t >= sc->schedule[sim->schedule_index + 1].t_start)
                    ++sim->schedule_index;
                K = sc->schedule[sim->schedule_index].K;
                B = sc->schedule[sim->schedule_index].B;
            } else {
                K = sc->K;
                B = sc->B;
            }
            K_planned = K;
            x_eq = k >= sim->k_step ? sc->x_eq_after : sc->x_eq_before;
        }

        if (fx & ESTIMATORS) {
            v_est = velocity_estimate(sim, dx, &v_filtered);
            F_cmd = K * (x_eq - x_meas) - B * v_est;
        } else {
            /* (B / T) dx, as run_linear: the same numbers bit for bit */
            v_est = dx / T;
            F_cmd = K * (x_eq - x_meas) - (B / T) * dx;
        }
        if (fx & ZW_SIM_WALL) {
            wall = wall_force(&sc->wall, x_meas, v_est);
            F_cmd += wall;
        }
        F = F_cmd;
        if (fx & ZW_SIM_SATURATION) {
            if (F > sc->force_max) F = sc->force_max;
            if (F < -sc->force_max) F = -sc->force_max;
        }
        applied = F;
        if (fx & ZW_SIM_DELAY) {
            applied = sim->delay_line[sim->delay_head];
            sim->delay_line[sim->delay_head] = F;
            if (++sim->delay_head == sc->delay_samples) sim->delay_head = 0;
        }

        ZW_RECORD(tr->t, j, t);
        ZW_RECORD(tr->x, j, x);
        ZW_RECORD(tr->v, j, v);
        ZW_RECORD(tr->x_measured, j, x_meas);
        ZW_RECORD(tr->force, j, applied);
        ZW_RECORD(tr->force_command, j, F_cmd);
        ZW_RECORD(tr->stiffness, j, K);
        ZW_RECORD(tr->stiffness_planned, j, K_planned);
        ZW_RECORD(tr->damping, j, B);
        ZW_RECORD(tr->velocity_estimate, j, v_est);
        ZW_RECORD(tr->wall_force, j, wall);
        if (fx & ZW_SIM_HAND) {
            ZW_RECORD(tr->hand_force, j, hand_force(&sc->hand, hand_phase(&sc->hand, t), t, x, v));
            ZW_RECORD(tr->hand_target, j, hand_target(&sc->hand, t));
        } else {
            ZW_RECORD(tr->hand_force, j, 0);
            ZW_RECORD(tr->hand_target, j, 0);
        }

        x_meas_prev = x_meas;
        if (fx & ZW_SIM_CONTINUOUS) {
            friction = integrate_sample(sim, t, applied, &x, &v, &stuck, &lagged);
        } else {
            const zw_real x_next = x + sim->phi_T * v + sim->x_gain * applied;
            v = sim->e * v + sim->v_gain * applied;
            x = x_next;
        }
        /* A velocity below the smallest normal number is 0: a plant settled under a
         * constant force (a quantized loop at rest) would otherwise decay through
         * subnormals, about 10x slower on x86; what it moves x by is below T ZW_REAL_MIN. */
        if (ZW_FABS(v) < ZW_REAL_MIN) v = 0;
        ZW_RECORD(tr->friction, j, friction);
    }
    sim->x = x;
    sim->v = v;
    sim->x_meas_prev = x_meas_prev;
    sim->v_filtered = v_filtered;
    sim->force_lagged = lagged;
    sim->stuck = stuck;
    if (n > 0) sim->started = true;
    sim->k += n;
}

zw_status zw_sim_run(zw_sim *sim, size_t n, const zw_sim_trace *trace) {
    if (sim == NULL || trace == NULL) return ZW_ERR_NULL;
    /* The ideal loop does not store the velocity estimate (one more store made it 1.13x
     * slower, bench-sim); who asks for it gets the general loop, which gives the same
     * numbers bit for bit with no effect on. */
    if (sim->scene.effects == 0u && trace->velocity_estimate == NULL)
        run_linear(sim, n, trace);
    else
        run_general(sim, n, trace);
    return ZW_OK;
}

zw_status zw_sim_set_gains(zw_sim *sim, zw_real K, zw_real B) {
    const zw_real gains[] = {K, B};
    if (sim == NULL) return ZW_ERR_NULL;
    ZW_TRY(all_finite(gains, 2));
    ZW_REQUIRE(!(sim->scene.effects & (ZW_SIM_KNOB | ZW_SIM_SCHEDULE)));
    sim->scene.K = K;
    sim->scene.B = B;
    return ZW_OK;
}

/* ---- the verdict -------------------------------------------------------------------- */

/* Peak-to-peak of x[0 .. n-1]; +inf if any is not finite. */
static zw_real peak_to_peak(const zw_real *x, size_t n) {
    zw_real lo = x[0], hi = x[0];
    size_t i;
    for (i = 0; i < n; ++i) {
        if (!ZW_IS_FINITE(x[i])) return ZW_SIM_INF;
        if (x[i] < lo) lo = x[i];
        if (x[i] > hi) hi = x[i];
    }
    return hi - lo;
}

static zw_status judge(const zw_real *x, size_t n, size_t window, size_t windows,
                       zw_real tolerance, zw_sim_verdict *out) {
    zw_sim_verdict r;
    size_t i;
    if (x == NULL || out == NULL) return ZW_ERR_NULL;
    ZW_TRY(finite_value(tolerance));
    ZW_REQUIRE(tolerance >= 0 && window >= 1 && windows >= 2 && windows <= n / window);

    r.first_nonfinite = n;
    for (i = 0; i < n; ++i) {
        if (!ZW_IS_FINITE(x[i])) {
            r.first_nonfinite = i;
            break;
        }
    }
    r.amplitude_first = peak_to_peak(x + (n - windows * window), window);
    r.amplitude_last = peak_to_peak(x + (n - window), window);
    if (r.first_nonfinite < n) {
        r.outcome = ZW_SIM_UNSTABLE;
        r.growth = ZW_SIM_INF;
    } else {
        const zw_real a1 = r.amplitude_first, aw = r.amplitude_last;
        if (a1 > 0)
            r.growth = ZW_POW(aw / a1, ZW_R(1.0) / ((zw_real)(windows - 1) * (zw_real)window));
        else
            r.growth = aw > 0 ? ZW_SIM_INF : 0;
        if (aw <= tolerance) {
            /* Settled, but only a record that moved by more than the tolerance shows it
             * settling: one that never did (a loop nothing excites, or a growth still
             * below the tolerance) is no evidence of stability. */
            r.outcome = (peak_to_peak(x, n) > tolerance) ? ZW_SIM_STABLE : ZW_SIM_UNDECIDED;
        } else {
            /* Dying out means every window smaller than the one before: a linear decay is,
             * a sustained (limit-cycle, chaotic) oscillation is not, whatever its noise. */
            bool decaying = true;
            zw_real before = a1;
            for (i = 1; i < windows && decaying; ++i) {
                const zw_real a = peak_to_peak(x + (n - (windows - i) * window), window);
                decaying = a < before;
                before = a;
            }
            r.outcome = decaying ? ZW_SIM_UNDECIDED : ZW_SIM_UNSTABLE;
        }
    }
    *out = r;
    return ZW_OK;
}

zw_status zw_sim_judge(const zw_real *x, size_t n, size_t window, size_t windows,
                       zw_real tolerance, zw_sim_verdict *out) {
    const zw_status st = judge(x, n, window, windows, tolerance, out);
    if (st != ZW_OK && out != NULL) { /* fail-safe (sim.h): no answer, never "stable" */
        out->outcome = ZW_SIM_UNDECIDED;
        out->amplitude_first = out->amplitude_last = out->growth = ZW_SIM_INF;
        out->first_nonfinite = 0;
    }
    return st;
}
