/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth-limits: stability limits and advice for one drive, from the C core.
 *
 * The C-only form of `zwidth limits` / `zwidth check` (the Python command): the same
 * option names (--m | --J, --b, --T, --K, --B, --delay, --velocity-filter,
 * --differentiator, --preset) and exit statuses (0 ok or stable, 1 unstable, 2 usage,
 * 3 invalid values).  Nothing is filled in: the plant needs --m (or --J), --b and --T, and
 * the loop --delay, or an explicit --preset paper-drive (the paper's drive and its ideal
 * loop).  The first line of the output names the loop judged.
 */
#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/zwidth.h"
#include "zw_hostloop.h"

enum { EXIT_OK = 0, EXIT_UNSTABLE = 1, EXIT_USAGE = 2, EXIT_INVALID = 3 };

static void usage(FILE *to)
{
    fprintf(to,
            "usage: zwidth-limits (--m M | --J J) --b B --T T --delay D [--velocity-filter F]\n"
            "                     [--differentiator X] [--K K --B BV]\n"
            "       zwidth-limits --preset paper-drive [any option above, to override]\n"
            "\n"
            "Uncoupled stability limits of an impedance-controlled device: mass (or inertia)\n"
            "m behind a zero-order hold, physical damping b, sampling period T, rendering\n"
            "K + B v (v the drive's velocity estimate), in the loop the drive runs (its delay,\n"
            "velocity filter and differentiator: always stated, never assumed).  Prints the\n"
            "loop judged (first line), the largest stable K and B of the paper's ideal loop\n"
            "and of that loop, where the plant sits on the non-monotonic curves of K_mmax\n"
            "and B_mmax, which way to move m or T, and the verdict of a gain pair for the loop.\n"
            "The same option names and exit statuses as `zwidth limits` / `zwidth check`.\n"
            "\n"
            "  --m M        mass [kg]                                          (required,\n"
            "  --J J        or inertia [kg m^2] of a rotary device              one of them)\n"
            "  --b B        physical damping [N s/m | N m s/rad], >= 0          (required)\n"
            "  --T T        sampling period [s], > 0                            (required)\n"
            "  --delay D    samples between reading x_k and applying its force, 0..8\n"
            "               (required): 0 is the paper's ideal loop; most firmware computes\n"
            "               during the period and applies at the next tick: 1.  With 0 the\n"
            "               limits with 1 are shown too, and a pair is also judged with 1\n"
            "  --velocity-filter F\n"
            "               none (default), lowpass:F_C[Hz] (first order, cut-off in Hz,\n"
            "               e.g. lowpass:100Hz), pole:A (the drive's stored pole a in [0, 1))\n"
            "               or average:N (moving average over N samples, 1..16)\n"
            "  --differentiator X\n"
            "               backward (default, the paper's) or tustin\n"
            "  --K K        check this stiffness [N/m | N m/rad] ...\n"
            "  --B BV       ... with this virtual damping [N s/m | N m s/rad] (both or\n"
            "               neither), for the loop stated\n"
            "  --preset paper-drive\n"
            "               the paper's experimental drive, load motor short-circuited, and\n"
            "               its ideal loop: --J 85.78e-7 --b 2.197e-3 --T 0.02 --delay 0\n"
            "               (options given override it)\n"
            "  --version    print the version of zwidth and exit\n"
            "\n"
            "Exit status: 0 ok (and the pair, if given, is stable in the loop stated), 1 the\n"
            "pair is not stable, 2 usage error (unknown or missing option, the loop not\n"
            "stated, not a number), 3 invalid values (m <= 0, T <= 0, b < 0, NaN, delay\n"
            "outside 0..8, a filter the loop cannot run; the message names the option).\n");
}

/* A plant value given on the command line (or by the preset), and whether it was. */
typedef struct {
    const char *option;
    double value;
    int given;
} option_value;

/* 1 when text is a number (strtod's whole string); out of range gives +-inf or 0, which
 * the core then refuses by name, as the Python command does. */
static int parse_real(const char *name, const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (end == text || *end != '\0') {
        fprintf(stderr, "zwidth-limits: error: argument %s: invalid number value: '%s'\n", name, text);
        return 0;
    }
    return 1;
}

typedef struct {
    const char *m, *b, *K, *B;
} unit_names;

static const unit_names LINEAR_UNITS = {"kg", "N s/m", "N/m", "N s/m"};
static const unit_names ROTARY_UNITS = {"kg m^2", "N m s/rad", "N m/rad", "N m s/rad"};

static const char *trend_word(zw_trend t)
{
    return t == ZW_RISES ? "rises" : t == ZW_FALLS ? "falls" : "is flat";
}

static const char *bound_advice(zw_bound b)
{
    switch (b) {
    case ZW_BOUND_DAMPING: return "B <= -b: the virtual damping cancels all physical damping";
    case ZW_BOUND_STIFFNESS: return "K <= 0";
    case ZW_BOUND_HYPERBOLA: return "K above the hyperbola f(B): lower K or move B toward the top";
    case ZW_BOUND_LINE: return "K beyond the line L(B) the legacy region misses: lower K or B";
    default: return "";
    }
}

/* The plant in a loop (device_loop.h): its certified limits, and how much of the ideal
 * loop's largest stiffness it keeps.  Large: static storage.  g_loop is the loop stated
 * (when it is not the ideal one), g_one the 1-sample loop shown beside the ideal one. */
static zw_device_loop g_loop, g_one;
static zw_loop_workspace g_ws; /* the checks' scratch (loop.h) */
static zw_device_loop_spec g_spec, g_one_spec; /* what g_loop and g_one were built from */

static zw_device_loop_spec spec_of(const zw_device_loop *dl)
{
    return dl == &g_one ? g_one_spec : g_spec;
}

/* "a delay of 1 sample", "a delay of 1 sample, velocity low-pass 100 Hz (pole 0.533488)",
 * "no delay, tustin differentiator": the loop's parts that are not the paper's */
static void loop_heading(const zw_device_loop *dl, char *buf, size_t cap)
{
    const zw_device_loop_spec spec = spec_of(dl);
    char vf[96];
    int n;
    if (spec.delay == 0u) n = snprintf(buf, cap, "no delay");
    else n = snprintf(buf, cap, "a delay of %u sample%s", spec.delay, spec.delay == 1u ? "" : "s");
    if (n >= 0 && (size_t)n < cap && spec.differentiator == ZW_DIFF_TUSTIN)
        n += snprintf(buf + n, cap - (size_t)n, ", tustin differentiator");
    if (n >= 0 && (size_t)n < cap && spec.filter != ZW_VFILTER_NONE) {
        zw_loop_filter_text(&spec, (double)dl->loop.spec.filter_pole, vf, sizeof vf);
        snprintf(buf + n, cap - (size_t)n, ", %s", vf);
    }
}

static zw_status print_loop_limits(const zw_device_loop *dl, const char *note, double K_mmax_ideal,
                                   const unit_names *u)
{
    zw_device_loop_extremes y;
    zw_status st;
    char heading[200];
    if ((st = zw_device_loop_extremes_compute(dl, &g_ws, &y)) != ZW_OK) return st;
    loop_heading(dl, heading, sizeof heading);
    printf("\nLimits with %s (%scertified, D-decomposition; loop.h)\n", heading, note);
    printf("  K_mmax   = %.6g %s at B = %.6g %s: %.2f %% of the ideal loop's\n", y.K_mmax, u->K,
           y.B_at_K_mmax, u->B, 100.0 * y.K_mmax / K_mmax_ideal);
    printf("  K with B = 0 (stiffness only): K < %.6g %s\n", y.K_p_max, u->K);
    printf("  B range  : %.6g < B < %.6g %s (as K -> 0+)\n", y.B_mmin, y.B_mmax, u->B);
    return ZW_OK;
}

/* M names the mass ("m", or "J" for a rotary plant), u its units. */
static void print_advice(const zw_device *dev, const zw_influence *inf, const char *M, const unit_names *u,
                         int ideal)
{
    printf("\nInfluence (paper Section IV%s)\n", ideal ? "" : ", of the paper's ideal loop");
    printf("  K_mmax %s with %s, %s with b, %s with T\n", trend_word(inf->K_vs_m), M,
           trend_word(inf->K_vs_b), trend_word(inf->K_vs_T));
    printf("  B_mmax %s with %s, %s with b, %s with T\n", trend_word(inf->B_vs_m), M,
           trend_word(inf->B_vs_b), trend_word(inf->B_vs_T));
    if (dev->b <= 0.0) {
        printf("  b = 0: delta = 0 for every %s and T; K_mmax = 0.686 %s/T^2, B_mmax = 2 %s/T\n", M, M, M);
        return;
    }
    printf("  critical %s: %s_K2 = %.4g %s (local max of K_mmax = %.4g), %s_K1 = %.4g (local min = %.4g)\n",
           M[0] == 'J' ? "inertias" : "masses", M, inf->m_K2, u->m, inf->K_mmax_at_m_K2, M, inf->m_K1,
           inf->K_mmax_at_m_K1);
    printf("                   %s_0 = %.4g, %s_B = %.4g; periods T_B = %.4g s, T_0 = %.4g s\n",
           M, inf->m_0, M, inf->m_B, inf->T_B, inf->T_0);
    if (inf->K_vs_m == ZW_FALLS)
        printf("  advice: %s sits on the falling stretch (%s_K2, %s_K1). Reduce %s to %s_K2 = %.4g\n"
               "          for K_mmax = %.4g (from %.4g); raising %s only helps past %.4g.\n",
               M, M, M, M, M, inf->m_K2, inf->K_mmax_at_m_K2, inf->K_mmax, M, inf->m_K_match);
    else if (dev->m < inf->m_K2)
        printf("  advice: raising %s toward %s_K2 = %.4g raises K_mmax up to %.4g.\n", M, M, inf->m_K2,
               inf->K_mmax_at_m_K2);
    else
        printf("  advice: raising %s raises K_mmax; so does shortening T.\n", M);
}

static int is_option(const char *arg, const char *name)
{
    return strcmp(arg, name) == 0;
}

/* The verdict of (K, B) in a loop: one line, and why not; *stable set.  0 on error. */
static zw_status print_loop_verdict(const zw_device_loop *dl, double K, double B, double T,
                                    const unit_names *u, int *stable)
{
    zw_loop_verdict v;
    zw_real K_max;
    zw_status st;
    char heading[200];
    if ((st = zw_device_loop_check(dl, &g_ws, K, B, &v)) != ZW_OK ||
        (st = zw_device_loop_k_max(dl, &g_ws, B, &K_max)) != ZW_OK)
        return st;
    loop_heading(dl, heading, sizeof heading);
    printf("\nGains K = %.6g %s, B = %.6g %s with %s: %s%s\n", K, u->K, B, u->B, heading,
           v.stable ? "STABLE" : "UNSTABLE", v.marginal ? ", within rounding of the boundary" : "");
    printf("  K_max(B) = %.6g %s in this loop\n", (double)K_max, u->K);
    if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_COMPLEX)
        printf("  - a complex pair of poles leaves the unit circle: oscillation at %.6g Hz\n",
               (double)v.theta / (2.0 * 3.14159265358979323846 * T));
    else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_MINUS1)
        printf("  - a pole leaves the unit circle at z = -1: oscillation at Nyquist\n");
    else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_PLUS1)
        printf("  - a pole leaves the unit circle at z = 1: K <= 0\n");
    *stable = v.stable;
    return ZW_OK;
}

int main(int argc, char **argv)
{
    option_value m = {"--m", 0.0, 0}, b = {"--b", 0.0, 0}, T = {"--T", 0.0, 0};
    option_value K = {"--K", 0.0, 0}, B = {"--B", 0.0, 0}, delay = {"--delay", 0.0, 0};
    int rotary = 0, preset = 0, filter_given = 0, diff_given = 0, ideal, i;
    double cutoff = 0.0, pole = 0.0;
    unsigned average = 0u;
    zw_velocity_filter vfilter = ZW_VFILTER_NONE;
    zw_differentiator diff = ZW_DIFF_BACKWARD;
    const unit_names *u;
    zw_device dev;
    zw_device_extremes x;
    zw_influence inf;
    zw_status st;
    char statement[200];

    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        option_value *target = NULL;
        if (is_option(arg, "--help") || is_option(arg, "-h")) {
            usage(stdout);
            return EXIT_OK;
        }
        if (is_option(arg, "--preset")) {
            if (i + 1 >= argc || strcmp(argv[i + 1], "paper-drive") != 0) {
                fprintf(stderr, "zwidth-limits: error: argument --preset: expected 'paper-drive'%s%s%s\n",
                        i + 1 < argc ? ", got '" : "", i + 1 < argc ? argv[i + 1] : "",
                        i + 1 < argc ? "'" : "");
                return EXIT_USAGE;
            }
            preset = 1;
            ++i;
            continue;
        }
        if (is_option(arg, "--velocity-filter") || is_option(arg, "--differentiator")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "zwidth-limits: error: missing value for '%s'\n", arg);
                return EXIT_USAGE;
            }
            if (arg[2] == 'v') {
                if (!zw_parse_velocity_filter("zwidth-limits: error", argv[i + 1], &vfilter, &cutoff,
                                              &pole, &average))
                    return EXIT_USAGE;
                filter_given = 1;
            } else {
                if (!zw_parse_differentiator("zwidth-limits: error", argv[i + 1], &diff)) return EXIT_USAGE;
                diff_given = 1;
            }
            ++i;
            continue;
        }
        if (is_option(arg, "--m") || is_option(arg, "--J")) {
            if (m.given && rotary != is_option(arg, "--J")) {
                fprintf(stderr, "zwidth-limits: error: argument %s: not allowed with argument %s\n", arg,
                        rotary ? "--J" : "--m");
                return EXIT_USAGE;
            }
            rotary = is_option(arg, "--J");
            m.option = arg;
            target = &m;
        } else if (is_option(arg, "--b")) target = &b;
        else if (is_option(arg, "--T")) target = &T;
        else if (is_option(arg, "--delay")) target = &delay;
        else if (is_option(arg, "--K")) target = &K;
        else if (is_option(arg, "--B")) target = &B;
        else if (is_option(arg, "--B_gain")) {
            fprintf(stderr, "zwidth-limits: error: --B_gain is now --B (the same names as `zwidth`)\n");
            return EXIT_USAGE;
        }
        else if (is_option(arg, "--version")) {
            printf("zwidth-limits %s\n", ZW_VERSION_STRING);
            return EXIT_OK;
        }
        if (target == NULL || i + 1 >= argc) {
            fprintf(stderr, "zwidth-limits: error: %s '%s'\n",
                    target == NULL ? "unknown option" : "missing value for", arg);
            usage(stderr);
            return EXIT_USAGE;
        }
        if (!parse_real(arg, argv[++i], &target->value)) return EXIT_USAGE;
        target->given = 1;
    }
    if (preset) { /* the paper's drive (load motor short-circuited) and its loop, where not given */
        if (!m.given) { m.value = 85.78e-7; m.option = "--J"; rotary = 1; }
        if (!b.given) b.value = 2.197e-3;
        if (!T.given) T.value = 0.02;
    } else if (!m.given || !b.given || !T.given) {
        fprintf(stderr, "zwidth-limits: error: the plant needs %s%s%s%s%s (or --preset paper-drive)\n",
                m.given ? "" : "--m (or --J)", !m.given && !b.given ? ", " : "", b.given ? "" : "--b",
                (!m.given || !b.given) && !T.given ? ", " : "", T.given ? "" : "--T");
        return EXIT_USAGE;
    }
    if (!preset && !delay.given) { /* the loop is always stated, never assumed */
        fprintf(stderr, "zwidth-limits: error: " ZW_LOOP_NOT_STATED "\n");
        return EXIT_USAGE;
    }
    if (K.given != B.given) {
        fprintf(stderr, "zwidth-limits: error: give both --K and --B (or neither)\n");
        return EXIT_USAGE;
    }
    if (!(floor(delay.value) == delay.value && fabs(delay.value) < 1e9)) { /* argparse's int: usage */
        fprintf(stderr, "zwidth-limits: error: argument --delay: invalid int value: '%g'\n", delay.value);
        return EXIT_USAGE;
    }
    if (!(delay.value >= 0.0 && delay.value <= (double)ZW_LOOP_MAX_DELAY)) {
        fprintf(stderr, "zwidth-limits: error: invalid value of --delay: must be in 0..%u samples, "
                "got %g [ZW_ERR_DELAY]\n", ZW_LOOP_MAX_DELAY, delay.value);
        return EXIT_INVALID;
    }
    memset(&g_spec, 0, sizeof g_spec);
    g_spec.delay = (unsigned)delay.value;
    g_spec.differentiator = diff;
    g_spec.filter = vfilter;
    g_spec.cutoff_hz = cutoff;
    g_spec.pole = pole;
    g_spec.average = average;
    ideal = zw_loop_spec_ideal(&g_spec);
    u = rotary ? &ROTARY_UNITS : &LINEAR_UNITS;

    if ((st = zw_device_init(&dev, m.value, b.value, T.value)) != ZW_OK ||
        (st = zw_device_extremes_compute(&dev, &x)) != ZW_OK ||
        (st = zw_device_influence(&dev, &inf)) != ZW_OK) {
        /* name the option whose value the core refused */
        const char *which = st == ZW_ERR_MASS ? m.option : st == ZW_ERR_DAMPING ? "--b"
                          : st == ZW_ERR_PERIOD ? "--T" : "--m, --b or --T";
        fprintf(stderr, "zwidth-limits: error: invalid value of %s: %s=%g, b=%g, T=%g [%s]\n", which,
                rotary ? "J" : "m", m.value, b.value, T.value, zw_status_name(st));
        return EXIT_INVALID;
    }
    /* the loop stated (when not the ideal one) and the 1-sample loop beside the ideal one */
    if (!ideal && (st = zw_device_loop_init(&g_loop, m.value, b.value, T.value, &g_spec)) != ZW_OK) {
        fprintf(stderr, "zwidth-limits: error: invalid value of %s: the loop cannot be built [%s]\n",
                st == ZW_ERR_FILTER || (filter_given && st == ZW_ERR_NAN) ? "--velocity-filter"
                : st == ZW_ERR_DELAY ? "--delay" : diff_given ? "--differentiator or --velocity-filter"
                : "--velocity-filter", zw_status_name(st));
        return EXIT_INVALID;
    }
    memset(&g_one_spec, 0, sizeof g_one_spec);
    g_one_spec.delay = 1u;
    if (ideal && (st = zw_device_loop_init(&g_one, m.value, b.value, T.value, &g_one_spec)) != ZW_OK) {
        fprintf(stderr, "zwidth-limits: error: limits with a delay of 1: %s\n", zw_status_name(st));
        return EXIT_INVALID;
    }

    if (ideal) {
        printf("Loop: the paper's ideal loop (delay 0, backward difference, no velocity filter)%s\n",
               preset && !delay.given && !filter_given && !diff_given ? ", from --preset paper-drive" : "");
    } else {
        zw_loop_statement(&g_spec, (double)g_loop.loop.spec.filter_pole, statement, sizeof statement);
        printf("Loop: %s\n", statement);
    }
    if (preset)
        printf("Preset paper-drive: the paper's drive, load motor short-circuited\n");
    printf("Plant: %s = %.6g %s, b = %.6g %s, T = %.6g s  ->  delta = bT/%s = %.6g\n",
           rotary ? "J" : "m", m.value, u->m, b.value, u->b, T.value, rotary ? "J" : "m", dev.co.delta);
    printf("\nLimits %s(exact region, paper eq (10))\n", ideal ? "" : "of the paper's ideal loop, for comparison ");
    printf("  K_mmax   = %.6g %s at B = %.6g %s (%s)\n", x.K_mmax, u->K, x.B_at_K_mmax, u->B,
           x.at_corner ? "corner of hyperbola and line" : "top of the hyperbola");
    printf("  K with B = 0 (stiffness only): K < %.6g %s\n", x.K_p_max, u->K);
    printf("  B range  : %.6g < B < %.6g %s (as K -> 0+)\n", x.B_mmin, x.B_mmax, u->B);
    if (x.at_corner) { /* the legacy region's optimum (the hyperbola top) lies beyond the line */
        zw_real a1, b1;
        if (zw_hyperbola_top(&dev.co, &a1, &b1) == ZW_OK)
            printf("  legacy region (no line) would claim K_mmax = %.6g %s at B = %.6g %s: unsafe\n",
                   a1 * dev.k_scale, u->K, b1 * dev.b_scale, u->B);
    }
    st = print_loop_limits(ideal ? &g_one : &g_loop, ideal ? "most firmware; " : "the loop stated; ",
                           x.K_mmax, u);
    if (st != ZW_OK) {
        fprintf(stderr, "zwidth-limits: error: limits of the loop: %s\n", zw_status_name(st));
        return EXIT_INVALID;
    }
    print_advice(&dev, &inf, rotary ? "J" : "m", u, ideal);

    if (K.given && !ideal) { /* the verdict for the loop the drive runs */
        int stable = 0;
        if ((st = print_loop_verdict(&g_loop, K.value, B.value, T.value, u, &stable)) != ZW_OK) {
            fprintf(stderr, "zwidth-limits: error: invalid value of --K or --B: K=%g, B=%g [%s]\n",
                    K.value, B.value, zw_status_name(st));
            return EXIT_INVALID;
        }
        return stable ? EXIT_OK : EXIT_UNSTABLE;
    }
    if (K.given) {
        zw_verdict v;
        zw_real rho, K_one;
        bool one_stable;
        if ((st = zw_device_check(&dev, K.value, B.value, &v)) != ZW_OK ||
            (st = zw_device_spectral_radius(&dev, K.value, B.value, &rho)) != ZW_OK ||
            (st = zw_device_loop_is_stable(&g_one, &g_ws, K.value, B.value, &one_stable)) != ZW_OK ||
            (st = zw_device_loop_k_max(&g_one, &g_ws, B.value, &K_one)) != ZW_OK) {
            fprintf(stderr, "zwidth-limits: error: invalid value of --K or --B: K=%g, B=%g [%s]\n",
                    K.value, B.value, zw_status_name(st));
            return EXIT_INVALID;
        }
        printf("\nGains K = %.6g %s, B = %.6g %s: %s (spectral radius %.6f)%s\n", K.value, u->K,
               B.value, u->B, v.stable ? "STABLE" : "UNSTABLE", rho,
               v.marginal ? ", within rounding of the boundary" : "");
        {
            unsigned bit; /* every violated constraint, the deciding one first */
            if (!v.stable) printf("  - %s\n", bound_advice(v.deciding));
            for (bit = ZW_BOUND_DAMPING; bit <= ZW_BOUND_LINE; bit <<= 1)
                if ((v.violated & bit) && bit != (unsigned)v.deciding)
                    printf("  - %s\n", bound_advice((zw_bound)bit));
        }
        printf("  with 1 sample of delay (most firmware): %s, K_max(B) = %.6g %s\n",
               one_stable ? "STABLE" : "UNSTABLE", (double)K_one, u->K);
        if (v.stable && !one_stable)
            printf("warning: this pair is stable only in the paper's ideal loop; if the drive "
                   "applies the force one sample late (most firmware) it is UNSTABLE: state that "
                   "loop with --delay 1 (and --velocity-filter)\n");
        return v.stable ? EXIT_OK : EXIT_UNSTABLE;
    }
    return EXIT_OK;
}
