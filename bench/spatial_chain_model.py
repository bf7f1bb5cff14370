#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Write the spatial N-link chain of issue 25 as an mbsc model.

Usage: /usr/bin/python3 bench/spatial_chain_model.py [--ball | --quat | --loop] N [OUT.mbs]   (default: stdout)

N box-like links hang from the ground by spatial revolute joints with coordinates
q1..qN, axes alternating z, y, x; each link has a full mass-centre offset and inertia
tensor with products; every mass, length, offset and inertia is a run-time parameter.
--ball: spherical joints instead, each with three zyx angles a_i, b_i, c_i (a chain of
ball joints: 3N degrees of freedom).
--quat: the ball joints with a quaternion each, e0_i (scalar), e1_i, e2_i, e3_i, and the
relative angular speeds j_i_wx, j_i_wy, j_i_wz in the link's axes (Pinocchio's
JointModelSpherical); every joint starts at the frames' coinciding attitude.
--loop: the revolute chain with the end of its last link held on the ground plane
x = 0.3 (`point_on_plane`: one loop row closed on the tree, N - 1 degrees of freedom).
"""
import sys


def spatial_chain(n: int, ball: bool = False, loop: bool = False, quat: bool = False) -> str:
    if n < 1:
        raise ValueError("N must be >= 1")
    axes = [(0, 0, 1), (0, 1, 0), (1, 0, 0)]
    ball = ball or quat
    name = f"quat_chain{n}" if quat else f"ball_chain{n}" if ball else f"loop_chain{n}" if loop else f"spatial_chain{n}"
    flag = " --quat" if quat else " --ball" if ball else " --loop" if loop else ""
    out = [f"# Spatial {n}-link chain in joint coordinates (benchmark model, written by",
           "# bench/spatial_chain_model.py" + flag + ").", f"model {name}",
           "parameter g = 9.81"]
    for i in range(1, n + 1):
        out.append(f"parameter m{i} = {1 + 0.1 * i:.2f}, L{i} = {0.5 + 0.01 * i:.2f}")
        out.append(f"parameter cx{i} = 0.1, cy{i} = 0.02, cz{i} = {0.2 + 0.01 * i:.2f}")
        out.append(f"parameter Ixx{i} = 0.05, Iyy{i} = 0.06, Izz{i} = 0.04, Ixy{i} = 0.001, "
                   f"Ixz{i} = -0.002, Iyz{i} = 0.003")
    out.append("gravity (0, 0, -g)")
    for i in range(1, n + 1):
        a = axes[(i - 1) % 3]
        out += [f"body link{i} : rigid3d {{", f"  mass m{i}", f"  inertia (Ixx{i}, Iyy{i}, Izz{i}, Ixy{i}, Ixz{i}, Iyz{i})",
                f"  com (cx{i}, cy{i}, cz{i})"]
        if loop and i == n:
            out.append(f"  point end (0, 0, L{i})")
        if ball:
            out.append("  point top (0, 0, 0)")
            if i < n:
                out.append(f"  point tip (0, 0, L{i})")
        else:
            out.append(f"  axis top (0, 0, 0) ({a[0]}, {a[1]}, {a[2]})")
            if i < n:
                b = axes[i % 3]
                out.append(f"  axis tip (0, 0, L{i}) ({b[0]}, {b[1]}, {b[2]})")
        out.append("}")
    if ball:
        for i in range(1, n + 1):
            parent = "ground.origin" if i == 1 else f"link{i - 1}.tip"
            coordinates = f"e0_{i}, e1_{i}, e2_{i}, e3_{i} quaternion" if quat else f"a{i}, b{i}, c{i} euler zyx"
            out.append(f"joint j{i} : spherical {parent} link{i}.top coordinate {coordinates}")
        if quat:
            out.append("initial " + ", ".join(f"e0_{i} = 1" for i in range(1, n + 1)))
        return "\n".join(out) + "\n"
    out.append("joint j1 : revolute ground.z_axis link1.top coordinate q1")
    for i in range(2, n + 1):
        out.append(f"joint j{i} : revolute link{i - 1}.tip link{i}.top coordinate q{i}")
    if loop:
        out += ["ground {", "  axis wall (0.3, 0, 0) (1, 0, 0)", "}", f"joint close : point_on_plane ground.wall link{n}.end"]
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    args = sys.argv[1:]
    ball, loop, quat = "--ball" in args, "--loop" in args, "--quat" in args
    args = [a for a in args if a not in ("--ball", "--loop", "--quat")]
    text = spatial_chain(int(args[0]), ball, loop, quat)
    if len(args) > 1:
        with open(args[1], "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
