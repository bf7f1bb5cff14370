#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Write the spatial N-link chain of issue 25 as an mbsc model.

Usage: /usr/bin/python3 bench/spatial_chain_model.py N [OUT.mbs]   (default: stdout)

N box-like links hang from the ground by spatial revolute joints with coordinates
q1..qN, axes alternating z, y, x; each link has a full mass-centre offset and inertia
tensor with products; every mass, length, offset and inertia is a run-time parameter.
"""
import sys


def spatial_chain(n: int) -> str:
    if n < 1:
        raise ValueError("N must be >= 1")
    axes = [(0, 0, 1), (0, 1, 0), (1, 0, 0)]
    out = [f"# Spatial {n}-link chain in joint coordinates (benchmark model, written by",
           "# bench/spatial_chain_model.py).", f"model spatial_chain{n}", "parameter g = 9.81"]
    for i in range(1, n + 1):
        out.append(f"parameter m{i} = {1 + 0.1 * i:.2f}, L{i} = {0.5 + 0.01 * i:.2f}")
        out.append(f"parameter cx{i} = 0.1, cy{i} = 0.02, cz{i} = {0.2 + 0.01 * i:.2f}")
        out.append(f"parameter Ixx{i} = 0.05, Iyy{i} = 0.06, Izz{i} = 0.04, Ixy{i} = 0.001, "
                   f"Ixz{i} = -0.002, Iyz{i} = 0.003")
    out.append("gravity (0, 0, -g)")
    for i in range(1, n + 1):
        a = axes[(i - 1) % 3]
        out += [f"body link{i} : rigid3d {{", f"  mass m{i}", f"  inertia (Ixx{i}, Iyy{i}, Izz{i}, Ixy{i}, Ixz{i}, Iyz{i})",
                f"  com (cx{i}, cy{i}, cz{i})", f"  axis top (0, 0, 0) ({a[0]}, {a[1]}, {a[2]})"]
        if i < n:
            b = axes[i % 3]
            out.append(f"  axis tip (0, 0, L{i}) ({b[0]}, {b[1]}, {b[2]})")
        out.append("}")
    out.append("joint j1 : revolute ground.z_axis link1.top coordinate q1")
    for i in range(2, n + 1):
        out.append(f"joint j{i} : revolute link{i - 1}.tip link{i}.top coordinate q{i}")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    text = spatial_chain(int(sys.argv[1]))
    if len(sys.argv) > 2:
        with open(sys.argv[2], "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
