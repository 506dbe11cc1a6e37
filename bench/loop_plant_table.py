# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0
"""K_mmax of the paper's drive with each plant-side part added (issue 16): the table of
docs/plant-loop.md.  Certified limits of the general loop (zwidth.Device).

    python bench/loop_plant_table.py
"""
import zwidth

J, b, T = 85.78e-7, 2.197e-3, 0.02  # the paper's drive (rotary), load motor short-circuited
HAND = (J, 2 * b, 1e-4)              # a hand of the drive's inertia, twice its damping, a soft spring

ROWS = [
    ("the paper's ideal loop", {}),
    ("+ actuator lag tau = 1 ms", dict(actuator_tau=1e-3)),
    ("+ actuator lag tau = 10 ms (T/2)", dict(actuator_tau=1e-2)),
    ("+ device stiffness k_p = 1e-3 N m/rad", dict(stiffness=1e-3)),
    ("1 sample delay", dict(delay=1)),
    ("1 sample delay + lag 1 ms", dict(delay=1, actuator_tau=1e-3)),
    ("1 sample delay + lag 10 ms", dict(delay=1, actuator_tau=1e-2)),
    ("1 sample delay + hand", dict(delay=1, hand=HAND)),
    ("1 sample delay + lag 1 ms + hand", dict(delay=1, actuator_tau=1e-3, hand=HAND)),
    ("1 sample delay + lag 10 ms + hand", dict(delay=1, actuator_tau=1e-2, hand=HAND)),
]


def main():
    base = float(zwidth.Device(J, b, T, rotary=True).extremes().K_mmax)
    print("| loop and plant-side parts | K_mmax [N m/rad] | at B [N m s/rad] | K with B = 0 | B range (K -> 0+) | vs ideal |")
    print("|---|---|---|---|---|---|")
    for name, kw in ROWS:
        e = zwidth.Device(J, b, T, rotary=True, **kw).extremes()
        print(f"| {name} | {float(e.K_mmax):.4g} | {float(e.B_at_K_mmax):.3g} | {float(e.K_p_max):.4g} | "
              f"({float(e.B_mmin):.3g}, {float(e.B_mmax):.3g}) | {float(e.K_mmax) / base:.3f} |")


if __name__ == "__main__":
    main()
