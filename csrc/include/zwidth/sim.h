/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/sim.h - time-domain simulation of the sampled impedance loop (paper Fig. 13).
 *
 * Host side: never linked into firmware (it needs no heap or I/O either, but it is bigger
 * than a drive wants).  One scene is one plant, one controller and the effects the scene
 * asks for; an effect that is not asked for is not computed.
 *
 * The loop, at every sample k (t_k = k T):
 *   x_meas_k  = x(t_k), or floor(x(t_k) * counts) / counts       (ZW_SIM_QUANTIZATION)
 *   v_d_k     = (x_meas_k - x_meas_{k-1}) / T (x_meas_{-1} = x_meas_0), the backward
 *               difference; or Tustin's v_d_k = (2/T)(x_meas_k - x_meas_{k-1}) - v_d_{k-1},
 *               v_d_{-1} = 0                                       (ZW_SIM_TUSTIN)
 *   v_est_k   = v_d_k, or a first-order low-pass of it, v_f_k = a v_f_{k-1} + (1 - a) v_d_k,
 *               v_f_{-1} = 0, a = exp(-2 pi f_c T)                  (ZW_SIM_VELOCITY_FILTER)
 *               or the mean of v_d_k .. v_d_{k-n+1} (zero before the first sample)
 *                                                  (ZW_SIM_AVERAGE, n samples; not both)
 *               (the velocity estimates of loop.h, so a linear scene is a loop it certifies)
 *   K_k, B_k, x_eq_k: the constant gains; or the piecewise-constant time schedule
 *               (ZW_SIM_SCHEDULE); or the detent knob's map of x_meas_k (ZW_SIM_KNOB).
 *               x_eq_k is the reference: x_eq_before until t_step, x_eq_after from t_step on.
 *   F_cmd_k   = K_k (x_eq_k - x_meas_k) - B_k v_est_k   (F = F0 - H(z) x with F0 = K x_eq,
 *               H(z) = K + B (z - 1)/(T z): no derivative kick at the step)
 *             + the unilateral virtual wall's force                (ZW_SIM_WALL)
 *   F_k       = F_cmd_k clamped to [-F_max, F_max]                 (ZW_SIM_SATURATION)
 *   applied   = F_{k-n} (zero before the first n samples)          (ZW_SIM_DELAY, n samples)
 * and the plant m x'' + b x' = f + hand + friction (friction: the signed force on the
 * plant, opposing its motion) over [t_k, t_k + T), with f = applied held by the
 * zero-order hold, or, through an actuator (current-loop) lag tau f' + f = applied
 * (ZW_SIM_ACTUATOR_LAG, f(0) = 0), f(t) = applied + (f(t_k) - applied) e^{-(t - t_k)/tau}
 * within the sample (exact).
 *
 * The plant step: without a continuous effect it is the exact solution of the ODE under
 * the zero-order hold (no integration error, a constant 6 flops per sample), with the
 * coefficients of coeffs.h (no cancellation at any delta):
 *   x+ = x + T phi v + (T^2 / m)(c1 / 2) F,  v+ = e v + (T / m) phi F,  phi = (c1 + c2)/2.
 * The continuous effects (Coulomb friction, the hand, the actuator lag) need the state
 * between samples:
 * then the sample interval is cut into `substeps` classical Runge-Kutta (RK4) steps.
 *
 * Continuous effects:
 *   ZW_SIM_FRICTION: Coulomb friction F_c opposing the velocity, with stiction F_s >= F_c:
 *     a resting plant (v = 0) stays at rest while the other forces on it stay within F_s
 *     and breaks away at the time they leave that band (solved exactly: they are affine in
 *     time within a substep); a sliding plant stops where its velocity reaches 0 inside the
 *     substep (the stop located to rounding on the RK4 solution), and from there sticks or
 *     slips again.  Every piece between events is an RK4 step, so friction keeps RK4's
 *     4th order (the old stop at the substep's end was 1st order and removed energy at
 *     each reversal).  A velocity below the smallest normal number is flushed to 0 in
 *     the general loop (subnormals are slow; the position moves by less than T times it).
 *     A plant creeping toward the edge of the stiction band (the net force tending to 0,
 *     v decaying without reversing) keeps sliding, as in the ideal Coulomb model, and
 *     pays for RK4 while it does.  (A Karnopp velocity band would stop it sooner and
 *     cheaper, at the price of an O(h) error measured to dominate the benchmark.)
 *   ZW_SIM_HAND: a hand holding the handle rigidly during [t_grasp, t_release): its mass
 *     m_h adds to m, and its arm pulls it toward the operator's intended position
 *     x_h(t) with stiffness k_h and damping b_h:  F_hand = k_h (x_h - x) + b_h (x_h' - x').
 *     x_h(t) starts at `from` at t_grasp and moves at `speed` toward `to`, where it stays.
 *     Each substep takes the hand's piece (released / moving / arrived) at its midpoint, so
 *     RK4 keeps 4th order except in the substeps that hold a grasp, release or arrival.
 *   ZW_SIM_ACTUATOR_LAG: the force reaches the plant through 1 / (tau s + 1), tau > 0 (the
 *     force is a known exponential within each sample: RK4 evaluates it exactly at each
 *     stage).  Not with ZW_SIM_FRICTION (stiction's exact break-away assumes a force affine
 *     in time within a substep).
 *
 * Discrete effects (computed once per sample by the controller, as a drive would):
 *   ZW_SIM_WALL: a unilateral virtual spring-damper.  side = +1: the wall occupies
 *     x > x_wall and pushes back with  min(0, K_w (x_wall - x_meas) - B_w v_est)  while
 *     x_meas > x_wall; side = -1 mirrored.  It never pulls the handle into the wall.
 *   ZW_SIM_KNOB: the detent knob of paper Fig. 22(b) replaces K and x_eq by a map of
 *     x_meas: n detents p_i = p_0 + i pitch; within pitch/4 of p_i (boundary included) the stiffness is
 *     k_detent toward p_i; between two detents it is -k_detent away from their midpoint
 *     (the force is continuous and triangular); below p_0 and above p_{n-1} the end walls,
 *     stiffness k_end toward p_0 / p_{n-1}.  B is the knob's damping throughout.
 *   ZW_SIM_SCHEDULE: gains (K_i, B_i) from t_i on, t_0 = 0 < t_1 < ... (variable
 *     impedance); incompatible with ZW_SIM_KNOB (both set the gains).
 *
 * A linear scene (no effect flags) is the ideal loop the analysis covers: its simulated
 * verdict must agree with zw_check (tested).
 */
#ifndef ZWIDTH_SIM_H
#define ZWIDTH_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "zwidth/real.h"
#include "zwidth/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Longest computation delay, in samples (the delay line lives inside zw_sim). */
#define ZW_SIM_MAX_DELAY 64
/* Longest moving average of the velocity estimate, in samples (as loop.h's). */
#define ZW_SIM_MAX_AVERAGE 16
/* Most integrator substeps per sample (above a 16-bit int: the field is int_least32_t). */
#define ZW_SIM_MAX_SUBSTEPS 100000
/* RK4 is stable for h |s| up to about 2.8 in the left half-plane (2.785 on the real axis,
 * 2.828 on the imaginary one); zw_sim_init refuses substeps that give h |s|max above this,
 * with |s|max <= (b + b_h)/(m + m_h) + sqrt(k_h/(m + m_h)) (and b/m), so an integrator
 * instability is never mistaken for the loop's. */
#define ZW_SIM_RK4_LIMIT ZW_R(2.5)

enum {
    ZW_SIM_QUANTIZATION = 1u << 0,
    ZW_SIM_FRICTION = 1u << 1,        /* continuous */
    ZW_SIM_DELAY = 1u << 2,
    ZW_SIM_SATURATION = 1u << 3,
    ZW_SIM_VELOCITY_FILTER = 1u << 4,
    ZW_SIM_HAND = 1u << 5,            /* continuous */
    ZW_SIM_WALL = 1u << 6,
    ZW_SIM_KNOB = 1u << 7,
    ZW_SIM_SCHEDULE = 1u << 8,
    ZW_SIM_TUSTIN = 1u << 9,
    ZW_SIM_AVERAGE = 1u << 10,
    ZW_SIM_ACTUATOR_LAG = 1u << 11,   /* continuous */
    ZW_SIM_ALL_EFFECTS = (1u << 12) - 1u,
    ZW_SIM_CONTINUOUS = ZW_SIM_FRICTION | ZW_SIM_HAND | ZW_SIM_ACTUATOR_LAG
};

typedef struct zw_sim_hand {
    zw_real mass;          /* m_h >= 0, added to m while held */
    zw_real stiffness;     /* k_h >= 0 */
    zw_real damping;       /* b_h >= 0 */
    zw_real t_grasp;       /* >= 0 */
    zw_real t_release;     /* > t_grasp; +inf: never released */
    zw_real from, to;      /* intended path: from `from` toward `to` ... */
    zw_real speed;         /* ... at this speed (> 0; +inf: a step to `to`) */
} zw_sim_hand;

typedef struct zw_sim_wall {
    zw_real position;      /* x_wall */
    zw_real stiffness;     /* K_w > 0 */
    zw_real damping;       /* B_w, any sign (rendered like B) */
    int side;              /* +1: wall occupies x > x_wall; -1: x < x_wall */
} zw_sim_wall;

typedef struct zw_sim_knob {
    zw_real first;         /* p_0 */
    zw_real pitch;         /* > 0 */
    int count;             /* n >= 2 detents */
    zw_real k_detent;      /* > 0: intermediate peak stiffness (IPS) */
    zw_real k_end;         /* > 0: end stiffness (ES) */
    zw_real damping;       /* the knob's B */
} zw_sim_knob;

typedef struct zw_sim_segment {
    zw_real t_start;       /* [s], strictly increasing, the first one 0 */
    zw_real K, B;
} zw_sim_segment;

typedef struct zw_sim_scene {
    zw_real m, b, T;               /* plant and period, as in device.h */
    zw_real K, B;                  /* controller gains (ignored under KNOB / SCHEDULE) */
    zw_real x_init, v_init;        /* initial state */
    zw_real x_eq_before, x_eq_after, t_step;   /* the equilibrium's step (t_step >= 0;
                                                  +inf: no step, x_eq_before throughout) */
    unsigned effects;              /* ZW_SIM_* flags; 0: the ideal linear loop */
    /* Parameters of each effect, read only when its flag is set. */
    zw_real counts_per_unit;       /* QUANTIZATION: > 0 (counts per m, or per rad) */
    zw_real coulomb, stiction;     /* FRICTION: 0 <= F_c <= F_s, not both 0 */
    int delay_samples;             /* DELAY: 1 .. ZW_SIM_MAX_DELAY */
    zw_real force_max;             /* SATURATION: > 0 */
    zw_real cutoff_hz;             /* VELOCITY_FILTER: > 0 */
    int average_samples;           /* AVERAGE: 1 .. ZW_SIM_MAX_AVERAGE */
    zw_real actuator_tau;          /* ACTUATOR_LAG: > 0 [s] */
    zw_sim_hand hand;              /* HAND */
    zw_sim_wall wall;              /* WALL */
    zw_sim_knob knob;              /* KNOB */
    const zw_sim_segment *schedule;   /* SCHEDULE: caller-owned, must outlive the zw_sim */
    size_t schedule_len;              /* >= 1 */
    int_least32_t substeps;        /* RK4 steps per sample when a continuous effect is on:
                                      1 .. ZW_SIM_MAX_SUBSTEPS (ignored otherwise) */
} zw_sim_scene;

/* Everything a run carries from one sample to the next; caller-allocated, no heap.
 * Treat as opaque: read it through the trace. */
typedef struct zw_sim {
    zw_sim_scene scene;
    zw_real phi_T, x_gain, v_gain, e;   /* exact step: x += phi_T v + x_gain F ... */
    zw_real filter_a;
    zw_real lag_rate, lag_decay;        /* ACTUATOR_LAG: 1 / tau, exp(-T / tau) */
    size_t k;                           /* next sample index */
    size_t k_step;                      /* first sample of the equilibrium x_eq_after */
    zw_real x, v;                       /* state at t_k */
    zw_real x_meas_prev, v_filtered;
    bool started, stuck;
    size_t schedule_index;
    int delay_head;
    zw_real delay_line[ZW_SIM_MAX_DELAY];
    zw_real v_diff;                     /* the differentiator's last output (Tustin) */
    int average_head;
    zw_real average_line[ZW_SIM_MAX_AVERAGE];
    zw_real force_lagged;               /* f at t_k (ACTUATOR_LAG) */
} zw_sim;

/* Validate the scene and set the run to t = 0.  Errors: ZW_ERR_NULL (also a NULL schedule
 * under SCHEDULE); the plant's errors as in zw_device_init (ZW_ERR_MASS, ZW_ERR_PERIOD,
 * ZW_ERR_DAMPING, ZW_ERR_RANGE); ZW_ERR_RANGE also for a finite t_step whose sample index
 * t_step / T is not below 2^24 (float build) / 2^53 (double build), the counts the real type
 * holds exactly, or not below SIZE_MAX (a 16- or 32-bit size_t): a step meant as "never"
 * is t_step = +inf; ZW_ERR_NAN for a NaN in any field that is read;
 * ZW_ERR_INF for an infinity where only finite values mean anything (everywhere except
 * t_step, hand.t_release and hand.speed, where +inf means "never" / "at once");
 * ZW_ERR_ARG for any other field outside its documented domain (unknown flag bits, KNOB
 * with SCHEDULE, VELOCITY_FILTER with AVERAGE, ACTUATOR_LAG with FRICTION, delay 0,
 * stiction < coulomb, too few substeps for ZW_SIM_RK4_LIMIT, ...).  Fields of effects that are off are
 * not read.  *sim is untouched on error. */
zw_status zw_sim_init(zw_sim *sim, const zw_sim_scene *scene);

/* Per-sample outputs; any pointer may be NULL (that signal is not recorded).  Entry j of
 * a call that starts at sample k describes sample k + j: the state at t = (k + j) T, and
 * the forces over [t, t + T). */
typedef struct zw_sim_trace {
    zw_real *t;                 /* [s] */
    zw_real *x, *v;             /* true position and velocity at t */
    zw_real *x_measured;        /* what the controller saw */
    zw_real *force;             /* applied over [t, t + T) (after saturation, delay; before
                                   the actuator lag: the plant gets f(t), see above) */
    zw_real *force_command;     /* controller output before saturation and delay */
    zw_real *stiffness;         /* K the controller used at this sample */
    zw_real *stiffness_planned; /* K the schedule or knob map gives at the true position */
    zw_real *damping;           /* B used at this sample */
    zw_real *velocity_estimate; /* v_est the damping terms used (filtered with a filter);
                                   asking for it in a scene without effects costs the
                                   general loop's speed instead of the ideal loop's */
    zw_real *wall_force;        /* the wall's part of force_command */
    zw_real *friction;          /* signed friction force on the plant at t (substep start) */
    zw_real *hand_force;        /* F_hand at t */
    zw_real *hand_target;       /* the hand's intended position x_h(t) (0 without a hand) */
} zw_sim_trace;

/* Advance n samples from where the run stands, writing entries 0 .. n-1 of every non-NULL
 * trace array.  Call again to continue (progress reporting, long runs in pieces).
 * Errors: ZW_ERR_NULL (sim or trace NULL).  A state that overflows to inf or NaN is not an
 * error: it is recorded, it is the simulation's answer (see zw_sim_judge). */
zw_status zw_sim_run(zw_sim *sim, size_t n, const zw_sim_trace *trace);

/* Change the constant gains of a run between two zw_sim_run calls (a drive's gains written
 * while its loop runs: zwidth-drive --simulate); the next sample uses them.  Errors:
 * ZW_ERR_NULL, ZW_ERR_NAN / ZW_ERR_INF (K or B), ZW_ERR_ARG (a KNOB or SCHEDULE scene,
 * whose gains come from elsewhere); *sim is untouched on error. */
zw_status zw_sim_set_gains(zw_sim *sim, zw_real K, zw_real B);

/* The simulated verdict.  The criterion, on the position record x[0 .. n-1]:
 *   take the last `windows` windows of `window` samples each and their peak-to-peak
 *   amplitudes A_1 .. A_w (oldest first);
 *   UNSTABLE  if any x is not finite, or A_w > tolerance and the amplitudes do not
 *             strictly decrease window by window (the motion is not dying out: a growing or
 *             sustained oscillation, a limit cycle, a drift);
 *   STABLE    if A_w <= tolerance (settled: what still moves is below tolerance) and the
 *             whole record moved by more than the tolerance (so it shows the settling);
 *   UNDECIDED otherwise: above tolerance but decaying in every window (run longer), or a
 *             record whose peak-to-peak never exceeded the tolerance (nothing excited the
 *             loop, or too little to see: no evidence either way).
 * Windows should be longer than the slowest oscillation, so that a decay shows in each.
 * A growth that stays below tolerance to the end of the record is not seen: pick the
 * tolerance and the duration for the scene (the Python layer's defaults are documented).
 * growth = (A_w / A_1)^(1 / ((w - 1) window)) is the envelope's factor per sample (0 when
 * A_1 = A_w = 0, +inf when A_1 = 0 < A_w or x is not finite); for a linear scene it
 * estimates the spectral radius.
 * Errors: ZW_ERR_NULL (x or out); ZW_ERR_NAN / ZW_ERR_INF (tolerance); ZW_ERR_ARG
 * (window < 1, windows < 2, windows * window > n, tolerance < 0).  Fail-safe (status.h): on
 * each error *out (when not NULL) is UNDECIDED (no answer: never STABLE, whose value is 0),
 * with amplitudes and growth +inf and first_nonfinite 0 (no sample vouched for). */
typedef enum zw_sim_outcome {
    ZW_SIM_STABLE = 0,
    ZW_SIM_UNSTABLE = 1,
    ZW_SIM_UNDECIDED = 2
} zw_sim_outcome;

typedef struct zw_sim_verdict {
    zw_sim_outcome outcome;
    zw_real amplitude_first;    /* A_1 */
    zw_real amplitude_last;     /* A_w */
    zw_real growth;             /* per sample; +inf when A_1 = 0 < A_w or x not finite */
    size_t first_nonfinite;     /* index of the first non-finite x, n if none */
} zw_sim_verdict;

zw_status zw_sim_judge(const zw_real *x, size_t n, size_t window, size_t windows,
                       zw_real tolerance, zw_sim_verdict *out);

#ifdef __cplusplus
}
#endif

#endif /* ZWIDTH_SIM_H */
