/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth-limits: stability limits and advice for one drive, from the C core.
 *
 * The C-only form of `zwidth limits` / `zwidth check` (the Python command): the same
 * option names (--m | --J, --b, --T, --K, --B, --delay, --preset) and exit statuses
 * (0 ok or stable, 1 unstable, 2 usage, 3 invalid values).  Nothing is filled in: the
 * plant needs --m (or --J), --b and --T, or an explicit --preset paper-drive.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/zwidth.h"

enum { EXIT_OK = 0, EXIT_UNSTABLE = 1, EXIT_USAGE = 2, EXIT_INVALID = 3 };

static void usage(FILE *to)
{
    fprintf(to,
            "usage: zwidth-limits (--m M | --J J) --b B --T T [--K K --B BV] [--delay D]\n"
            "       zwidth-limits --preset paper-drive [any option above, to override]\n"
            "\n"
            "Uncoupled stability limits of an impedance-controlled device: mass (or inertia)\n"
            "m behind a zero-order hold, physical damping b, sampling period T, rendering\n"
            "K + B (z-1)/(T z).  Prints the largest stable K and B, where the plant sits on\n"
            "the non-monotonic curves of K_mmax and B_mmax, and which way to move m or T.\n"
            "The same option names and exit statuses as `zwidth limits` / `zwidth check`.\n"
            "\n"
            "  --m M        mass [kg]                                          (required,\n"
            "  --J J        or inertia [kg m^2] of a rotary device              one of them)\n"
            "  --b B        physical damping [N s/m | N m s/rad], >= 0          (required)\n"
            "  --T T        sampling period [s], > 0                            (required)\n"
            "  --K K        check this stiffness [N/m | N m/rad] ...\n"
            "  --B BV       ... with this virtual damping [N s/m | N m s/rad] (both or neither)\n"
            "  --delay D    samples between reading x_k and applying its force, 0..8: the\n"
            "               limits of that loop and the verdict of --K/--B for it (without\n"
            "               --delay: the limits with 1, as firmware that computes during the\n"
            "               period has, beside the paper's 0; the verdict for 0)\n"
            "  --preset paper-drive\n"
            "               the paper's experimental drive, load motor short-circuited:\n"
            "               --J 85.78e-7 --b 2.197e-3 --T 0.02 (options given override it)\n"
            "  --version    print the version of zwidth and exit\n"
            "\n"
            "Exit status: 0 ok (and the pair, if given, is stable), 1 the pair is not stable,\n"
            "2 usage error (unknown or missing option, not a number), 3 invalid values\n"
            "(m <= 0, T <= 0, b < 0, NaN, delay outside 0..8; the message names the option).\n");
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

/* The same plant with a delay of d samples (device_loop.h): its certified limits, and how
 * much of the ideal loop's largest stiffness it keeps.  Large: static storage. */
static zw_device_loop g_delayed;
static zw_loop_workspace g_ws; /* the checks' scratch (loop.h) */

static zw_status print_delayed(double m, double b, double T, unsigned d, double K_mmax_ideal,
                               const unit_names *u)
{
    zw_device_loop_spec spec;
    zw_device_loop_extremes y;
    zw_status st;
    memset(&spec, 0, sizeof spec);
    spec.delay = d;
    if ((st = zw_device_loop_init(&g_delayed, m, b, T, &spec)) != ZW_OK ||
        (st = zw_device_loop_extremes_compute(&g_delayed, &g_ws, &y)) != ZW_OK)
        return st;
    printf("\nLimits with a delay of %u sample%s (certified, D-decomposition; loop.h)\n", d,
           d == 1 ? "" : "s");
    printf("  K_mmax   = %.6g %s at B = %.6g %s: %.2f %% of the ideal loop's\n", y.K_mmax, u->K,
           y.B_at_K_mmax, u->B, 100.0 * y.K_mmax / K_mmax_ideal);
    printf("  K with B = 0 (proportional only): K < %.6g %s\n", y.K_p_max, u->K);
    printf("  B range  : %.6g < B < %.6g %s (as K -> 0+)\n", y.B_mmin, y.B_mmax, u->B);
    return ZW_OK;
}

/* M names the mass ("m", or "J" for a rotary plant), u its units. */
static void print_advice(const zw_device *dev, const zw_influence *inf, const char *M, const unit_names *u)
{
    printf("\nInfluence (paper Section IV)\n");
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

int main(int argc, char **argv)
{
    option_value m = {"--m", 0.0, 0}, b = {"--b", 0.0, 0}, T = {"--T", 0.0, 0};
    option_value K = {"--K", 0.0, 0}, B = {"--B", 0.0, 0}, delay = {"--delay", 1.0, 0};
    int rotary = 0, preset = 0, i;
    unsigned d;
    const unit_names *u;
    zw_device dev;
    zw_device_extremes x;
    zw_influence inf;
    zw_status st;

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
    if (preset) { /* the paper's drive (load motor short-circuited), where not given */
        if (!m.given) { m.value = 85.78e-7; m.option = "--J"; rotary = 1; }
        if (!b.given) b.value = 2.197e-3;
        if (!T.given) T.value = 0.02;
    } else if (!m.given || !b.given || !T.given) {
        fprintf(stderr, "zwidth-limits: error: the plant needs %s%s%s%s%s (or --preset paper-drive)\n",
                m.given ? "" : "--m (or --J)", !m.given && !b.given ? ", " : "", b.given ? "" : "--b",
                (!m.given || !b.given) && !T.given ? ", " : "", T.given ? "" : "--T");
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
    d = (unsigned)delay.value;
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
    if (preset)
        printf("Preset paper-drive: the paper's drive, load motor short-circuited\n");
    printf("Plant: %s = %.6g %s, b = %.6g %s, T = %.6g s  ->  delta = bT/%s = %.6g\n",
           rotary ? "J" : "m", m.value, u->m, b.value, u->b, T.value, rotary ? "J" : "m", dev.co.delta);
    printf("\nLimits (exact region, paper eq (10))\n");
    printf("  K_mmax   = %.6g %s at B = %.6g %s (%s)\n", x.K_mmax, u->K, x.B_at_K_mmax, u->B,
           x.at_corner ? "corner of hyperbola and line" : "top of the hyperbola");
    printf("  K with B = 0 (proportional only): K < %.6g %s\n", x.K_p_max, u->K);
    printf("  B range  : %.6g < B < %.6g %s (as K -> 0+)\n", x.B_mmin, x.B_mmax, u->B);
    if (x.at_corner) { /* the legacy region's optimum (the hyperbola top) lies beyond the line */
        zw_real a1, b1;
        if (zw_hyperbola_top(&dev.co, &a1, &b1) == ZW_OK)
            printf("  legacy region (no line) would claim K_mmax = %.6g %s at B = %.6g %s: unsafe\n",
                   a1 * dev.k_scale, u->K, b1 * dev.b_scale, u->B);
    }
    if (d > 0u && (st = print_delayed(m.value, b.value, T.value, d, x.K_mmax, u)) != ZW_OK) {
        fprintf(stderr, "zwidth-limits: error: limits with a delay of %u: %s\n", d, zw_status_name(st));
        return EXIT_INVALID;
    }
    print_advice(&dev, &inf, rotary ? "J" : "m", u);

    if (K.given && delay.given && d > 0u) { /* the verdict for the loop the drive runs */
        zw_loop_verdict v;
        if ((st = zw_device_loop_check(&g_delayed, &g_ws, K.value, B.value, &v)) != ZW_OK) {
            fprintf(stderr, "zwidth-limits: error: invalid value of --K or --B: K=%g, B=%g [%s]\n",
                    K.value, B.value, zw_status_name(st));
            return EXIT_INVALID;
        }
        printf("\nGains K = %.6g %s, B = %.6g %s with a delay of %u: %s%s\n", K.value, u->K, B.value,
               u->B, d, v.stable ? "STABLE" : "UNSTABLE",
               v.marginal ? ", within rounding of the boundary" : "");
        if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_COMPLEX)
            printf("  - a complex pair of poles leaves the unit circle: oscillation at %.6g Hz\n",
                   (double)v.theta / (2.0 * 3.14159265358979323846 * T.value));
        else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_MINUS1)
            printf("  - a pole leaves the unit circle at z = -1: oscillation at Nyquist\n");
        else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_PLUS1)
            printf("  - a pole leaves the unit circle at z = 1: K <= 0\n");
        return v.stable ? EXIT_OK : EXIT_UNSTABLE;
    }
    if (K.given) {
        zw_verdict v;
        zw_real rho;
        if ((st = zw_device_check(&dev, K.value, B.value, &v)) != ZW_OK ||
            (st = zw_device_spectral_radius(&dev, K.value, B.value, &rho)) != ZW_OK) {
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
        return v.stable ? EXIT_OK : EXIT_UNSTABLE;
    }
    return EXIT_OK;
}
