/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench_sim.c - cost per sample of zw_sim_run: the bare linear loop, each effect alone,
 * all effects together, and a minimal hand-written loop of the same linear recurrence.
 *
 * Scene (every row): m = 0.1 kg, b = 30 N s/m, T = 0.01 s (delta = 3), K = 2000 N/m,
 * B = 5 N s/m (a stable point, spectral radius ~0.37), equilibrium stepped 0 -> 1 m at
 * t = 0.  Each row adds one effect with the parameters below (chosen so that the effect
 * acts: the saturation clips the step, the wall is in contact, the hand pushes the handle
 * into it, the knob settles in a detent, the schedule switches twice).  KNOB and SCHEDULE
 * exclude each other, so "all effects" is two rows.
 *
 * Timing: a run is cut into episodes of --episode samples (default 2000 = 20 s), each
 * restarted from the same initialized zw_sim by struct copy, so that transients (contact,
 * grasp, stick-slip, switching) recur instead of the run idling at rest.  The plain loop
 * restarts its three state variables the same way.  Trace arrays hold one episode (they
 * stay in cache).  Each row is timed over enough episodes to last ~--time seconds (at
 * most --samples samples), rows interleaved round-robin, best of --repeats
 * (clock_gettime, CLOCK_MONOTONIC).  ns/sample = best time / samples timed.
 *
 * "plain C loop" is the linear recurrence written out by hand with the coefficients of
 * zw_coeffs (x+ = x + T phi v + (T^2/m)(c1/2) F, v+ = e v + (T/m) phi F,
 * F = K (x_eq - x) - (B/T) (x - x_prev)), recording x only: the lower bound of what the bare
 * zw_sim_run can cost.  Their ratio shows what the absent effects cost the bare loop.
 *
 *   bench_sim [--samples N] [--episode N] [--repeats R] [--time S] [--substeps N]
 *
 * Prints Markdown to stdout; exit status 0, 1 if the core refuses a scene, 2 on bad
 * arguments.  Built as bench-sim (double) and bench-sim-f (float) in the build tree.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "zwidth/coeffs.h"
#include "zwidth/sim.h"
#include "zwidth/status.h"

#define MAX_CASES 32
#define N_SIGNALS 13   /* every zw_sim_trace field */

typedef enum record { REC_NONE, REC_X, REC_ALL } record;

typedef struct bench_case {
    const char *name;
    zw_sim_scene scene;
    record rec;
    int plain;              /* 1: the hand-written loop instead of zw_sim_run */
    zw_sim fresh;           /* initialized once, copied at every episode */
    long episodes;          /* per timed run */
    double best;            /* seconds */
    const char *outcome;
    double x_end;
    double moving;          /* share of samples with v != 0 (friction: sliding) */
} bench_case;

typedef struct plain_loop {
    zw_real x0, v0, x_eq, K, B_over_T, phi_T, x_gain, v_gain, e;
} plain_loop;

static zw_real *g_sig[N_SIGNALS];   /* one episode per signal */
static volatile double g_sink;      /* keeps every timed run observable */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static long parse_long(const char *opt, const char *s, long lo, long hi)
{
    char *end = NULL;
    double v = strtod(s, &end);   /* accepts 1e6 */
    if (end == s || *end != '\0' || !(v >= (double)lo && v <= (double)hi) || v != floor(v)) {
        fprintf(stderr, "bench_sim: %s wants an integer in [%ld, %ld], got '%s'\n", opt, lo, hi, s);
        exit(2);
    }
    return (long)v;
}

static zw_sim_trace make_trace(record rec)
{
    zw_sim_trace tr;
    memset(&tr, 0, sizeof tr);
    if (rec == REC_NONE) {
        return tr;
    }
    tr.x = g_sig[1];
    if (rec == REC_ALL) {
        tr.t = g_sig[0];
        tr.v = g_sig[2];
        tr.x_measured = g_sig[3];
        tr.force = g_sig[4];
        tr.force_command = g_sig[5];
        tr.stiffness = g_sig[6];
        tr.stiffness_planned = g_sig[7];
        tr.damping = g_sig[8];
        tr.wall_force = g_sig[9];
        tr.friction = g_sig[10];
        tr.hand_force = g_sig[11];
        tr.hand_target = g_sig[12];
    }
    return tr;
}

/* The minimal loop: the exact ZOH step and the impedance controller, nothing else. */
static void plain_run(const plain_loop *p, size_t n, zw_real *x_out)
{
    zw_real x = p->x0, v = p->v0, x_prev = p->x0;
    size_t k;
    for (k = 0; k < n; ++k) {
        zw_real F = p->K * (p->x_eq - x) - p->B_over_T * (x - x_prev);
        zw_real x_next = x + p->phi_T * v + p->x_gain * F;
        x_out[k] = x;
        v = p->e * v + p->v_gain * F;
        x_prev = x;
        x = x_next;
    }
}

static int plain_init(plain_loop *p, const zw_sim_scene *s)
{
    zw_coeffs co;
    zw_real phi;
    if (zw_coeffs_init(&co, s->b * s->T / s->m) != ZW_OK) {
        return -1;
    }
    phi = co.s / ZW_R(2.0);   /* (c1 + c2) / 2 */
    p->x0 = s->x_init;
    p->v0 = s->v_init;
    p->x_eq = s->x_eq_after;  /* t_step = 0: the step is in force from the first sample */
    p->K = s->K;
    p->B_over_T = s->B / s->T;   /* the division out of the loop, as anyone would */
    p->phi_T = s->T * phi;
    p->x_gain = (s->T * s->T / s->m) * (co.c1 / ZW_R(2.0));
    p->v_gain = (s->T / s->m) * phi;
    p->e = co.e;
    return 0;
}

/* One timed run of a case: its episodes, back to back. */
static double time_case(bench_case *c, const plain_loop *p, size_t episode)
{
    zw_sim_trace tr = make_trace(c->rec);
    zw_sim sim;
    double t0, t1;
    long i;
    t0 = now_s();
    if (c->plain) {
        for (i = 0; i < c->episodes; ++i) {
            plain_run(p, episode, g_sig[1]);
            g_sink = (double)g_sig[1][episode - 1];
        }
    } else {
        for (i = 0; i < c->episodes; ++i) {
            sim = c->fresh;
            (void)zw_sim_run(&sim, episode, &tr);
            g_sink = (double)sim.x;
        }
    }
    t1 = now_s();
    return t1 - t0;
}

static zw_sim_scene base_scene(void)
{
    zw_sim_scene s;
    memset(&s, 0, sizeof s);
    s.m = ZW_R(0.1);
    s.b = ZW_R(30.0);
    s.T = ZW_R(0.01);
    s.K = ZW_R(2000.0);
    s.B = ZW_R(5.0);
    s.x_eq_before = ZW_R(0.0);
    s.x_eq_after = ZW_R(1.0);
    s.t_step = ZW_R(0.0);
    s.substeps = 1;
    return s;
}

static const zw_sim_segment g_schedule[3] = {
    {ZW_R(0.0), ZW_R(2000.0), ZW_R(5.0)},
    {ZW_R(5.0), ZW_R(4000.0), ZW_R(3.0)},
    {ZW_R(10.0), ZW_R(1000.0), ZW_R(8.0)},
};

/* Parameters of each effect (read only when its flag is set, so one scene carries all). */
static void set_effect_params(zw_sim_scene *s, int substeps)
{
    s->counts_per_unit = ZW_R(1.0e4);          /* 0.1 mm */
    s->coulomb = ZW_R(2.0);
    s->stiction = ZW_R(3.0);
    s->delay_samples = 1;
    s->force_max = ZW_R(200.0);                /* the 1 m step asks for 2000 N */
    s->cutoff_hz = ZW_R(20.0);
    s->hand.mass = ZW_R(0.05);
    s->hand.stiffness = ZW_R(500.0);
    s->hand.damping = ZW_R(5.0);
    s->hand.t_grasp = ZW_R(2.0);
    s->hand.t_release = ZW_R(12.0);
    s->hand.from = ZW_R(1.0);
    s->hand.to = ZW_R(1.3);
    s->hand.speed = ZW_R(0.1);
    s->wall.position = ZW_R(0.9);              /* x_eq = 1 is inside: steady contact */
    s->wall.stiffness = ZW_R(1000.0);
    s->wall.damping = ZW_R(1.0);
    s->wall.side = 1;
    s->knob.first = ZW_R(0.0);
    s->knob.pitch = ZW_R(0.1);
    s->knob.count = 10;
    s->knob.k_detent = ZW_R(2000.0);
    s->knob.k_end = ZW_R(5000.0);
    s->knob.damping = ZW_R(5.0);
    s->schedule = g_schedule;
    s->schedule_len = sizeof g_schedule / sizeof g_schedule[0];
    s->substeps = substeps;
}

static const char *outcome_name(zw_sim_outcome o)
{
    return o == ZW_SIM_STABLE ? "stable" : o == ZW_SIM_UNSTABLE ? "unstable" : "undecided";
}

static const char *si(double v, char *buf, size_t len)
{
    if (v >= 1e9) {
        snprintf(buf, len, "%.3g G", v / 1e9);
    } else if (v >= 1e6) {
        snprintf(buf, len, "%.3g M", v / 1e6);
    } else if (v >= 1e3) {
        snprintf(buf, len, "%.3g k", v / 1e3);
    } else {
        snprintf(buf, len, "%.3g", v);
    }
    return buf;
}

int main(int argc, char **argv)
{
    long samples = 10000000L, episode_l = 2000, repeats = 7, substeps = 10;
    double target = 0.1;
    bench_case cases[MAX_CASES];
    plain_loop plain;
    size_t n_cases = 0, i, episode;
    int a, r;
    long bare_idx = -1, plain_idx = -1, bare_all_idx = -1, all_x_idx = -1, all_all_idx = -1;
    double max_diff = 0.0;

    for (a = 1; a < argc; ++a) {
        const char *opt = argv[a];
        if (strcmp(opt, "--samples") != 0 && strcmp(opt, "--episode") != 0 && strcmp(opt, "--repeats") != 0
            && strcmp(opt, "--substeps") != 0 && strcmp(opt, "--time") != 0) {
            fprintf(stderr, "bench_sim: unknown option %s (options: --samples --episode --repeats --time "
                            "--substeps)\n", opt);
            return 2;
        }
        if (a + 1 >= argc) {
            fprintf(stderr, "bench_sim: %s: missing value (options: --samples --episode --repeats "
                            "--time --substeps)\n", opt);
            return 2;
        }
        if (strcmp(opt, "--samples") == 0) {
            samples = parse_long(opt, argv[++a], 1, 1000000000L);
        } else if (strcmp(opt, "--episode") == 0) {
            episode_l = parse_long(opt, argv[++a], 100, 10000000L);
        } else if (strcmp(opt, "--repeats") == 0) {
            repeats = parse_long(opt, argv[++a], 1, 1000);
        } else if (strcmp(opt, "--substeps") == 0) {
            substeps = parse_long(opt, argv[++a], 1, ZW_SIM_MAX_SUBSTEPS);
        } else if (strcmp(opt, "--time") == 0) {
            char *end = NULL;
            target = strtod(argv[++a], &end);
            if (*end != '\0' || !(target > 0.0 && target <= 60.0)) {
                fprintf(stderr, "bench_sim: --time wants seconds in (0, 60]\n");
                return 2;
            }
        } else {
            fprintf(stderr, "bench_sim: unknown option %s\n", opt);
            return 2;
        }
    }
    episode = (size_t)episode_l;
    for (i = 0; i < N_SIGNALS; ++i) {
        g_sig[i] = malloc(episode * sizeof(zw_real));
        if (g_sig[i] == NULL) {
            fprintf(stderr, "bench_sim: out of memory\n");
            return 1;
        }
    }

    {
        static const struct {
            const char *name;
            unsigned effects;
            record rec;
        } rows[] = {
            {"bare (linear), x recorded", 0u, REC_X},
            {"plain C loop, x recorded", 0u, REC_X},
            {"bare, nothing recorded", 0u, REC_NONE},
            {"bare, all 13 signals recorded", 0u, REC_ALL},
            {"quantization", ZW_SIM_QUANTIZATION, REC_X},
            {"friction (RK4)", ZW_SIM_FRICTION, REC_X},
            {"delay", ZW_SIM_DELAY, REC_X},
            {"saturation", ZW_SIM_SATURATION, REC_X},
            {"velocity_filter", ZW_SIM_VELOCITY_FILTER, REC_X},
            {"hand (RK4)", ZW_SIM_HAND, REC_X},
            {"wall", ZW_SIM_WALL, REC_X},
            {"knob", ZW_SIM_KNOB, REC_X},
            {"schedule", ZW_SIM_SCHEDULE, REC_X},
            {"discrete effects together (all but friction, hand, knob)",
             ZW_SIM_ALL_EFFECTS & ~(unsigned)(ZW_SIM_CONTINUOUS | ZW_SIM_KNOB), REC_X},
            {"all effects but knob, x recorded", ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_KNOB, REC_X},
            {"all effects but knob, all 13 signals", ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_KNOB, REC_ALL},
            {"all effects but schedule, x recorded", ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_SCHEDULE, REC_X},
        };
        for (i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
            bench_case *c = &cases[n_cases];
            zw_status st;
            memset(c, 0, sizeof *c);
            c->name = rows[i].name;
            c->rec = rows[i].rec;
            c->plain = strncmp(c->name, "plain", 5) == 0;
            c->scene = base_scene();
            set_effect_params(&c->scene, (int)substeps);
            c->scene.effects = rows[i].effects;
            if (rows[i].effects & ZW_SIM_KNOB) {
                c->scene.x_init = ZW_R(0.33);   /* starts between two detents */
            }
            st = zw_sim_init(&c->fresh, &c->scene);
            if (st != ZW_OK) {
                fprintf(stderr, "bench_sim: zw_sim_init refused '%s': %s\n", c->name, zw_status_name(st));
                return 1;
            }
            if (c->plain) {
                plain_idx = (long)n_cases;
            } else if (rows[i].effects == 0u && c->rec == REC_X) {
                bare_idx = (long)n_cases;
            } else if (rows[i].effects == 0u && c->rec == REC_ALL) {
                bare_all_idx = (long)n_cases;
            } else if (rows[i].effects == (ZW_SIM_ALL_EFFECTS & ~(unsigned)ZW_SIM_KNOB)) {
                if (c->rec == REC_X) {
                    all_x_idx = (long)n_cases;
                } else {
                    all_all_idx = (long)n_cases;
                }
            }
            ++n_cases;
        }
    }
    if (plain_init(&plain, &cases[bare_idx].scene) != 0) {
        fprintf(stderr, "bench_sim: zw_coeffs_init failed\n");
        return 1;
    }

    /* What each scene does over one episode (all signals recorded), and the plain loop's
     * trajectory against the bare zw_sim_run's. */
    for (i = 0; i < n_cases; ++i) {
        bench_case *c = &cases[i];
        zw_sim_trace tr = make_trace(REC_ALL);
        zw_sim sim = c->fresh;
        zw_sim_verdict vd;
        if (c->plain) {
            plain_run(&plain, episode, g_sig[1]);
        } else {
            (void)zw_sim_run(&sim, episode, &tr);
        }
        c->x_end = (double)g_sig[1][episode - 1];
        if (!c->plain) {
            size_t j, moving = 0;
            for (j = 0; j < episode; ++j) {
                moving += g_sig[2][j] != ZW_R(0.0);
            }
            c->moving = (double)moving / (double)episode;
        }
        /* settled: the last 10 % of the episode moves by less than 1e-3 m */
        if (zw_sim_judge(g_sig[1], episode, episode / 20, 2, ZW_R(1e-3), &vd) == ZW_OK) {
            c->outcome = outcome_name(vd.outcome);
        } else {
            c->outcome = "?";
        }
    }
    {
        zw_sim_trace tr = make_trace(REC_X);
        zw_sim sim = cases[bare_idx].fresh;
        zw_real *xs = malloc(episode * sizeof(zw_real));
        if (xs == NULL) {
            return 1;
        }
        (void)zw_sim_run(&sim, episode, &tr);
        memcpy(xs, g_sig[1], episode * sizeof(zw_real));
        plain_run(&plain, episode, g_sig[1]);
        for (i = 0; i < episode; ++i) {
            double d = fabs((double)xs[i] - (double)g_sig[1][i]);
            if (d > max_diff || d != d) {
                max_diff = d;
            }
        }
        free(xs);
    }

    /* Calibrate: episodes per timed run so that a run lasts about `target` seconds. */
    for (i = 0; i < n_cases; ++i) {
        bench_case *c = &cases[i];
        long max_ep = samples / episode_l > 0 ? samples / episode_l : 1;
        double t1;
        c->episodes = 1;
        t1 = time_case(c, &plain, episode);
        t1 = time_case(c, &plain, episode);   /* second call: warm */
        c->episodes = t1 > 0.0 ? (long)ceil(target / t1) : max_ep;
        if (c->episodes > max_ep) {
            c->episodes = max_ep;
        }
        if (c->episodes < 1) {
            c->episodes = 1;
        }
        c->best = HUGE_VAL;
    }
    /* The two rows whose ratio matters run the same samples. */
    cases[plain_idx].episodes = cases[bare_idx].episodes;

    for (r = 0; r < (int)repeats; ++r) {
        for (i = 0; i < n_cases; ++i) {
            double t = time_case(&cases[i], &plain, episode);
            if (t < cases[i].best) {
                cases[i].best = t;
            }
        }
    }

    {
        double bare_ns = cases[bare_idx].best / ((double)cases[bare_idx].episodes * (double)episode) * 1e9;
        double plain_ns = cases[plain_idx].best / ((double)cases[plain_idx].episodes * (double)episode) * 1e9;
        char buf[32];
        printf("# zw_sim_run: cost per sample (%s)\n\n", ZW_REAL_NAME);
        printf("- scene: m = 0.1 kg, b = 30 N s/m, T = 0.01 s, K = 2000 N/m, B = 5 N s/m, step 0 -> 1 m "
               "at t = 0; RK4 substeps per sample for friction / hand: %ld\n", substeps);
        printf("- episodes of %zu samples (%.3g s) restarted from the same state; best of %ld "
               "interleaved runs of ~%.2g s each\n", episode, (double)episode * 0.01, repeats, target);
        printf("- sliding: share of an episode's samples with v != 0 (friction integrates with RK4 only "
               "while the plant slides; at rest it checks stiction and skips the substep)\n");
        printf("- outcome: zw_sim_judge over one episode (2 windows of %zu samples, tolerance 1 mm)\n\n",
               episode / 20);
        printf("| case | substeps | samples timed | ns/sample | samples/s | vs bare | sliding | outcome "
               "| x at end [m] |\n");
        printf("|---|---|---|---|---|---|---|---|---|\n");
        for (i = 0; i < n_cases; ++i) {
            bench_case *c = &cases[i];
            double n = (double)c->episodes * (double)episode;
            double ns = c->best / n * 1e9;
            char sub[24], rate[32], sliding[24];
            snprintf(sub, sizeof sub, "-");
            snprintf(sliding, sizeof sliding, "-");
            if ((c->scene.effects & (unsigned)ZW_SIM_CONTINUOUS) != 0u) {
                snprintf(sub, sizeof sub, "%ld", substeps);
            }
            if ((c->scene.effects & (unsigned)ZW_SIM_FRICTION) != 0u) {
                snprintf(sliding, sizeof sliding, "%.0f %%", 100.0 * c->moving);
            }
            printf("| %s | %s | %s | %.3g | %s | %.3gx | %s | %s | %.4g |\n", c->name, sub,
                   si(n, buf, sizeof buf), ns, si(1e9 / ns, rate, sizeof rate), ns / bare_ns,
                   sliding, c->outcome, c->x_end);
        }
        printf("\n- bare zw_sim_run / plain C loop (x recorded, same samples): %.3f "
               "(%.3g vs %.3g ns/sample); max |x_sim - x_plain| over one episode: %.3g m\n",
               bare_ns / plain_ns, bare_ns, plain_ns, max_diff);
        printf("- all %d signals / x only: bare %.3g, all effects but knob %.3g\n", N_SIGNALS,
               cases[bare_all_idx].best / (double)cases[bare_all_idx].episodes
                   / (cases[bare_idx].best / (double)cases[bare_idx].episodes),
               cases[all_all_idx].best / (double)cases[all_all_idx].episodes
                   / (cases[all_x_idx].best / (double)cases[all_x_idx].episodes));
    }
    for (i = 0; i < N_SIGNALS; ++i) {
        free(g_sig[i]);
    }
    return 0;
}
