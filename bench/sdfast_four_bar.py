#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Write models/four_bar.mbs's four-bar linkage as an SD/FAST input file (.sd).

Usage: /usr/bin/python3 bench/sdfast_four_bar.py [OUT.sd]   (default: stdout)

SD/FAST describes a closed loop as a tree plus a loop joint: crank (pin at the ground
pivot O = origin), coupler (pin on the crank's far end A), rocker (pin at the ground
pivot Q = (d, 0)), and a loop pin joint B between the coupler's far end and the
rocker's. Each bar lies along its body x axis with its joints at -L/2 and +L/2 from the
mass centre, so a pin angle of 0 is a bar along the ground x axis: the tree coordinates
are q0 = crank.theta, q1 = coupler.theta - crank.theta, q2 = rocker.theta of the mbsc
model. Every value that is a parameter there (a, b, c, d, g, m1..m3, and so the
inertias m L^2/12 about z) is marked `?`: a run-time input, set before sdinit. The
in-plane motion leaves the inertias about x and y without effect; they are 0.
"""
import sys


def four_bar() -> str:
    def bar(name, inb, length, itj):
        return [
            f"body = {name} inb = {inb} joint = pin",
            "  mass = 1.0?",
            "  inertia = 0 0 1.0?",
            f"  bodytojoint = -{length}? 0 0",
            f"  inbtojoint = {itj}",
            "  pin = 0 0 1",
            "",
        ]

    lines = [
        "# Planar four-bar linkage of models/four_bar.mbs (benchmark model, written by",
        "# bench/sdfast_four_bar.py); '?' marks a run-time parameter.",
        "language = c",
        "gravity = 0 -9.81? 0",
        "",
    ]
    lines += bar("crank", "$ground", "0.15", "0 0 0")
    lines += bar("coupler", "crank", "0.5", "0.15? 0 0")
    lines += bar("rocker", "$ground", "0.4", "0.9? 0 0")
    lines += [
        "# the loop joint B: the rocker's far end on the coupler's far end",
        "body = rocker inb = coupler joint = pin",
        "  bodytojoint = 0.4? 0 0",
        "  inbtojoint = 0.5? 0 0",
        "  pin = 0 0 1",
        "",
    ]
    return "\n".join(lines)


def main(argv):
    if len(argv) > 2:
        sys.stderr.write(__doc__)
        return 2
    text = four_bar()
    if len(argv) == 2:
        with open(argv[1], "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
