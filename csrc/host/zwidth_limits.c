/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth-limits: stability limits and advice for one drive, from the C core.
 *
 * Without arguments it reports on the paper's experimental drive (load motor short-
 * circuited: J = 85.78e-7 kg m^2, b = 2.197e-3 N m s/rad, T = 0.02 s).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "zwidth/zwidth.h"

static void usage(FILE *to)
{
    fprintf(to,
            "usage: zwidth-limits [--m M] [--b B] [--T T] [--delay D] [--K K --B_gain BV]\n"
            "\n"
            "Uncoupled stability limits of an impedance-controlled device: mass (or inertia)\n"
            "m behind a zero-order hold, physical damping b, sampling period T, rendering\n"
            "K + B (z-1)/(T z).  Prints the largest stable K and B, where the plant sits on\n"
            "the non-monotonic curves of K_mmax and B_mmax, and which way to move m or T.\n"
            "\n"
            "  --m M        mass [kg] or inertia J [kg m^2]  (default 85.78e-7)\n"
            "  --b B        physical damping [N s/m or N m s/rad] (default 2.197e-3)\n"
            "  --T T        sampling period [s] (default 0.02)\n"
            "  --delay D    samples between reading x_k and applying its force, 0..8: the\n"
            "               limits of that loop and the verdict of --K/--B_gain for it\n"
            "               (default: the limits with 1, as firmware that computes during the\n"
            "               period has, beside the paper's 0; the verdict for 0)\n"
            "  --K K        also check this stiffness [N/m or N m/rad] (default 0) ...\n"
            "  --B_gain BV  ... with this virtual damping [N s/m or N m s/rad] (default 0)\n"
            "  --version    print the version of zwidth and exit\n"
            "\n"
            "Exit status: 0 ok (and the pair, if given, is stable), 1 the pair is unstable,\n"
            "2 bad arguments.\n");
}

static int parse_real(const char *name, const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (errno != 0 || end == text || *end != '\0') {
        fprintf(stderr, "zwidth-limits: %s expects a number, got '%s'\n", name, text);
        return 0;
    }
    return 1;
}

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

static zw_status print_delayed(double m, double b, double T, unsigned d, double K_mmax_ideal)
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
    printf("  K_mmax   = %.6g at B = %.6g: %.2f %% of the ideal loop's\n", y.K_mmax,
           y.B_at_K_mmax, 100.0 * y.K_mmax / K_mmax_ideal);
    printf("  K with B = 0 (proportional only): K < %.6g\n", y.K_p_max);
    printf("  B range  : %.6g < B < %.6g (as K -> 0+)\n", y.B_mmin, y.B_mmax);
    return ZW_OK;
}

static void print_advice(const zw_device *dev, const zw_influence *inf)
{
    printf("\nInfluence (paper Section IV)\n");
    printf("  K_mmax %s with m, %s with b, %s with T\n", trend_word(inf->K_vs_m),
           trend_word(inf->K_vs_b), trend_word(inf->K_vs_T));
    printf("  B_mmax %s with m, %s with b, %s with T\n", trend_word(inf->B_vs_m),
           trend_word(inf->B_vs_b), trend_word(inf->B_vs_T));
    if (dev->b <= 0.0) {
        printf("  b = 0: delta = 0 for every m and T; K_mmax = 0.686 m/T^2, B_mmax = 2 m/T\n");
        return;
    }
    printf("  critical masses: m_K2 = %.4g (local max of K_mmax = %.4g), m_K1 = %.4g "
           "(local min = %.4g)\n", inf->m_K2, inf->K_mmax_at_m_K2, inf->m_K1, inf->K_mmax_at_m_K1);
    printf("                   m_0 = %.4g, m_B = %.4g; periods T_B = %.4g s, T_0 = %.4g s\n",
           inf->m_0, inf->m_B, inf->T_B, inf->T_0);
    if (inf->K_vs_m == ZW_FALLS)
        printf("  advice: m sits on the falling stretch (m_K2, m_K1). Reduce m to m_K2 = %.4g\n"
               "          for K_mmax = %.4g (from %.4g); raising m only helps past %.4g.\n",
               inf->m_K2, inf->K_mmax_at_m_K2, inf->K_mmax, inf->m_K_match);
    else if (dev->m < inf->m_K2)
        printf("  advice: raising m toward m_K2 = %.4g raises K_mmax up to %.4g.\n", inf->m_K2,
               inf->K_mmax_at_m_K2);
    else
        printf("  advice: raising m raises K_mmax; so does shortening T.\n");
}

int main(int argc, char **argv)
{
    double m = 85.78e-7, b = 2.197e-3, T = 0.02, K = 0.0, B = 0.0, delay = 1.0;
    int have_pair = 0, have_delay = 0, i;
    unsigned d;
    zw_device dev;
    zw_device_extremes x;
    zw_influence inf;
    zw_status st;

    for (i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        double *target = NULL;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(arg, "--version") == 0) {
            printf("zwidth-limits %s\n", ZW_VERSION_STRING);
            return 0;
        }
        if (strcmp(arg, "--m") == 0 || strcmp(arg, "--J") == 0) target = &m;
        else if (strcmp(arg, "--b") == 0) target = &b;
        else if (strcmp(arg, "--T") == 0) target = &T;
        else if (strcmp(arg, "--delay") == 0) { target = &delay; have_delay = 1; }
        else if (strcmp(arg, "--K") == 0) { target = &K; have_pair = 1; }
        else if (strcmp(arg, "--B_gain") == 0) { target = &B; have_pair = 1; }
        if (target == NULL || i + 1 >= argc) {
            fprintf(stderr, "zwidth-limits: %s '%s'\n",
                    target == NULL ? "unknown option" : "missing value for", arg);
            usage(stderr);
            return 2;
        }
        if (!parse_real(arg, argv[++i], target)) return 2;
    }
    if (!(delay >= 0.0 && delay <= (double)ZW_LOOP_MAX_DELAY && delay == (double)(unsigned)delay)) {
        fprintf(stderr, "zwidth-limits: --delay expects a whole number of samples 0..%u, got %g\n",
                ZW_LOOP_MAX_DELAY, delay);
        return 2;
    }
    d = (unsigned)delay;

    if ((st = zw_device_init(&dev, m, b, T)) != ZW_OK ||
        (st = zw_device_extremes_compute(&dev, &x)) != ZW_OK ||
        (st = zw_device_influence(&dev, &inf)) != ZW_OK) {
        fprintf(stderr, "zwidth-limits: invalid plant (m=%g, b=%g, T=%g): %s\n", m, b, T,
                zw_status_name(st));
        return 2;
    }
    printf("Plant: m = %.6g, b = %.6g, T = %.6g s  ->  delta = bT/m = %.6g\n", m, b, T,
           dev.co.delta);
    printf("\nLimits (exact region, paper eq (10))\n");
    printf("  K_mmax   = %.6g at B = %.6g (%s)\n", x.K_mmax, x.B_at_K_mmax,
           x.at_corner ? "corner of hyperbola and line" : "top of the hyperbola");
    printf("  K with B = 0 (proportional only): K < %.6g\n", x.K_p_max);
    printf("  B range  : %.6g < B < %.6g (as K -> 0+)\n", x.B_mmin, x.B_mmax);
    if (x.at_corner) { /* the legacy region's optimum (the hyperbola top) lies beyond the line */
        zw_real a1, b1;
        if (zw_hyperbola_top(&dev.co, &a1, &b1) == ZW_OK)
            printf("  legacy region (no line) would claim K_mmax = %.6g at B = %.6g: unsafe\n",
                   a1 * dev.k_scale, b1 * dev.b_scale);
    }
    if (d > 0u && (st = print_delayed(m, b, T, d, x.K_mmax)) != ZW_OK) {
        fprintf(stderr, "zwidth-limits: limits with a delay of %u: %s\n", d, zw_status_name(st));
        return 2;
    }
    print_advice(&dev, &inf);

    if (have_pair && have_delay && d > 0u) { /* the verdict for the loop the drive runs */
        zw_loop_verdict v;
        if ((st = zw_device_loop_check(&g_delayed, &g_ws, K, B, &v)) != ZW_OK) {
            fprintf(stderr, "zwidth-limits: cannot check K=%g, B=%g: %s\n", K, B, zw_status_name(st));
            return 2;
        }
        printf("\nGains K = %.6g, B = %.6g with a delay of %u: %s%s\n", K, B, d,
               v.stable ? "STABLE" : "UNSTABLE", v.marginal ? ", within rounding of the boundary" : "");
        if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_COMPLEX)
            printf("  - a complex pair of poles leaves the unit circle: oscillation at %.6g Hz\n",
                   (double)v.theta / (2.0 * 3.14159265358979323846 * T));
        else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_MINUS1)
            printf("  - a pole leaves the unit circle at z = -1: oscillation at Nyquist\n");
        else if (!v.stable && v.deciding == ZW_LOOP_BOUNDARY_Z_PLUS1)
            printf("  - a pole leaves the unit circle at z = 1: K <= 0\n");
        return v.stable ? 0 : 1;
    }
    if (have_pair) {
        zw_verdict v;
        zw_real rho;
        if ((st = zw_device_check(&dev, K, B, &v)) != ZW_OK ||
            (st = zw_device_spectral_radius(&dev, K, B, &rho)) != ZW_OK) {
            fprintf(stderr, "zwidth-limits: cannot check K=%g, B=%g: %s\n", K, B, zw_status_name(st));
            return 2;
        }
        printf("\nGains K = %.6g, B = %.6g: %s (spectral radius %.6f)%s\n", K, B,
               v.stable ? "STABLE" : "UNSTABLE", rho,
               v.marginal ? ", within rounding of the boundary" : "");
        {
            unsigned bit; /* every violated constraint, the deciding one first */
            if (!v.stable) printf("  - %s\n", bound_advice(v.deciding));
            for (bit = ZW_BOUND_DAMPING; bit <= ZW_BOUND_LINE; bit <<= 1)
                if ((v.violated & bit) && bit != (unsigned)v.deciding)
                    printf("  - %s\n", bound_advice((zw_bound)bit));
        }
        return v.stable ? 0 : 1;
    }
    return 0;
}
