#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Write the planar N-link pendulum chain as an SD/FAST input file (.sd).

Usage: /usr/bin/python3 bench/sdfast_chain.py N [OUT.sd]   (default: stdout)

The same system as bench/chain_model.py, in SD/FAST's own terms: bodies b1..bN, each
hung from the one before (b1 from $ground) by a pin joint about z. A body is a point
mass m (zero inertia) whose joint sits a distance l above its centre of mass
(`bodytojoint = 0 l 0`) and at the centre of mass of the body before
(`inbtojoint = 0 0 0`); gravity is (0, -g, 0). Every value that is a parameter of the
mbsc model (m, l, g) is marked `?`, so it is a run-time input of SD/FAST's code too
(set with sdmass, sdbtj and sdgrav before sdinit).

SD/FAST's coordinates are the joint angles: q_k = th_k - th_(k-1), where th_k is the
absolute rod angle of the mbsc model (measured from the downward vertical, like
SD/FAST's pin angle from this reference configuration).
"""
import sys


def sdfast_chain(n: int) -> str:
    if n < 1:
        raise ValueError("N must be >= 1")
    lines = [
        f"# Planar {n}-link pendulum chain of point masses (benchmark model,",
        "# written by bench/sdfast_chain.py); '?' marks a run-time parameter.",
        "language = c",
        "gravity = 0 -9.81? 0",
        "",
    ]
    for k in range(1, n + 1):
        inb = "$ground" if k == 1 else f"b{k - 1}"
        lines += [
            f"body = b{k} inb = {inb} joint = pin",
            "  mass = 1.0?",
            "  inertia = 0 0 0",
            "  bodytojoint = 0 1.0? 0",
            "  inbtojoint = 0 0 0",
            "  pin = 0 0 1",
            "",
        ]
    return "\n".join(lines)


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write(__doc__)
        return 2
    text = sdfast_chain(int(argv[1]))
    if len(argv) == 3:
        with open(argv[2], "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
