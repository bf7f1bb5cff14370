#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Write the planar N-link pendulum chain as an mbsc model.

Usage: /usr/bin/python3 bench/chain_model.py N [OUT.mbs]   (default: stdout)

N particle2d bobs b1..bN of mass m, massless rods of length l, gravity (0, -g).
The absolute rod angles th1..thN (from the downward vertical) are extra coordinates
of the top level with speeds wk = thk'; the bobs are tied to them by position
constraints (b0 = the origin) and w1..wN are the independent speeds.
"""
import sys


def chain_model(n: int) -> str:
    if n < 1:
        raise ValueError("N must be >= 1")
    lines = [
        f"# Planar {n}-link pendulum chain of point masses (benchmark model,",
        "# written by bench/chain_model.py). Absolute rod angles th1..thN from the",
        "# downward vertical; bob k hangs from bob k-1 (bob 0 is the origin).",
        f"model chain{n}",
        "",
        "parameter m = 1.0, l = 1.0, g = 9.81",
        "gravity (0, -g)",
        "",
    ]
    lines += [f"body b{k} : particle2d {{ mass m }}" for k in range(1, n + 1)]
    lines.append("")
    lines.append("coordinate " + ", ".join(f"th{k}" for k in range(1, n + 1)))
    lines.append("speed " + ", ".join(f"w{k} = th{k}'" for k in range(1, n + 1)))
    lines.append("")
    lines.append("constraint position {")
    for k in range(1, n + 1):
        if k == 1:
            lines.append(f"  b{k}x: b{k}.x = l*sin(th{k})")
            lines.append(f"  b{k}y: b{k}.y = -l*cos(th{k})")
        else:
            lines.append(f"  b{k}x: b{k}.x = b{k-1}.x + l*sin(th{k})")
            lines.append(f"  b{k}y: b{k}.y = b{k-1}.y - l*cos(th{k})")
    lines.append("}")
    lines.append("independent " + ", ".join(f"w{k}" for k in range(1, n + 1)))
    lines.append("")
    return "\n".join(lines)


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write(__doc__)
        return 2
    text = chain_model(int(argv[1]))
    if len(argv) == 3:
        with open(argv[2], "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
