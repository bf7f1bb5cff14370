#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""The sympy peer of the bicycle benchmark: the Whipple bicycle of models/whipple_bicycle.mbs
(Meijaard, Papadopoulos, Ruina and Schwab 2007, Table 1) with sympy.physics.mechanics
KanesMethod, laid out as PyDy's published Whipple model is (yaw-lean-pitch frames, the
rear contact point as the origin of the rear wheel's velocity, the front contact's
velocity as the three nonholonomic rows, the pitch a dependent coordinate), then C code
for its mass matrix and forcing.

Usage: /usr/bin/python3 bench/sympy_bicycle.py OUTDIR

Axes as in the paper and the mbsc model: x forward, y right, z down. Frames: Y = yaw q1
about N.z, R = lean q2 about Y.x, B (rear frame) = pitch q3 about R.y, with B's axes the
paper's axes at the reference pose; H (front frame) = steer q4 about the steering axis
s = sin(lambda) B.x + cos(lambda) B.z. Speeds (PyDy's order of roles): u1 yaw rate, u2
lean rate, u3 rear wheel rate relative to B, u4 pitch rate, u5 steer rate, u6 front
wheel rate relative to H; independent u2, u3, u5, dependent u1, u4, u6. The rear
contact point is fixed in the rear wheel (its velocity is 0: rear no-slip), the front
contact point's velocity along Y.x, Y.y, Y.z is 0 (front no-slip and the derivative of
the contact height), and the contact height from the rear contact, along Y.z, is the
configuration constraint that makes q3 dependent. The wheel angles and the rear contact
point's x, y are ignorable and, as in PyDy's model, not part of the state.

KanesMethod returns mass_matrix (6 x 6: the 3 dynamic rows and the 3 differentiated
velocity constraints) and forcing (6) over the speeds in the order (u2, u3, u5, u1, u4,
u6). Writes
  OUTDIR/sympy_bicycle.c     void sympy_bicycle_mass_forcing(const double* q, const double* u,
                                const double* p, double* M, double* F)
                             (q = (q1, q2, q4, q3): yaw, lean, steer, pitch; u in the order
                             above; p in the order of sympy_bicycle_pnames; M row-major);
  OUTDIR/sympy_bicycle.json  timings and operation counts (mbsc's convention on the CSE'd
                             expressions and sympy.count_ops; the driver's LU solve is not
                             included).
"""
import json
import os
import resource
import sys
import time

import sympy as sm
import sympy.physics.mechanics as me

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sympy_chain import Printer, mbsc_convention_ops  # noqa: E402

# Table 1 of the paper, in the order of the mbsc model's parameters.
PARAMS = [("w", 1.02), ("c", 0.08), ("lam", "pi/10"), ("g", 9.81),
          ("rR", 0.3), ("mR", 2.0), ("IRxx", 0.0603), ("IRyy", 0.12),
          ("xB", 0.3), ("zB", -0.9), ("mB", 85.0), ("IBxx", 9.2), ("IByy", 11.0), ("IBzz", 2.8), ("IBxz", 2.4),
          ("xH", 0.9), ("zH", -0.7), ("mH", 4.0), ("IHxx", 0.05892), ("IHyy", 0.06), ("IHzz", 0.00708),
          ("IHxz", -0.00756),
          ("rF", 0.35), ("mF", 3.0), ("IFxx", 0.1405), ("IFyy", 0.28)]


def kanes_method(dependent_order=(0, 1, 2), numeric_data=False):
    """The bicycle's KanesMethod after kanes_equations, its parameter symbols, coordinates
    (q1, q2, q3, q4) and speeds (u1 .. u6); bench/sympy_linearize.py linearizes it.
    dependent_order permutes the dependent speeds (u1, u4, u6): sympy eliminates them by
    an LU without pivoting on symbolic entries, in this order. numeric_data: Table 1's
    values in place of the parameter symbols from the start."""
    P = {name: (sm.sympify(v) if numeric_data else sm.Symbol(name)) for name, v in PARAMS}
    w, c, lam, g = P["w"], P["c"], P["lam"], P["g"]
    rR, rF = P["rR"], P["rF"]
    q1, q2, q3, q4 = me.dynamicsymbols("q1 q2 q3 q4")
    u1, u2, u3, u4, u5, u6 = me.dynamicsymbols("u1 u2 u3 u4 u5 u6")
    t = me.dynamicsymbols._t

    N = me.ReferenceFrame("N")
    Y = N.orientnew("Y", "Axis", [q1, N.z])
    R = Y.orientnew("R", "Axis", [q2, Y.x])
    B = R.orientnew("B", "Axis", [q3, R.y])
    s_axis = sm.sin(lam) * B.x + sm.cos(lam) * B.z
    H = B.orientnew("H", "Axis", [q4, s_axis])
    WR = me.ReferenceFrame("WR")  # the wheels' spin angles are ignorable: no orientation
    WF = me.ReferenceFrame("WF")

    Y.set_ang_vel(N, u1 * Y.z)
    R.set_ang_vel(Y, u2 * R.x)
    B.set_ang_vel(R, u4 * B.y)
    WR.set_ang_vel(B, u3 * B.y)
    H.set_ang_vel(B, u5 * s_axis)
    WF.set_ang_vel(H, u6 * H.y)

    # Points, from the rear contact along the chain (B and H coordinates are the paper's
    # at the reference pose, relative to the point named).
    rear_contact = me.Point("rear_contact")
    rear_contact.set_vel(N, 0)
    rear_centre = rear_contact.locatenew("rear_centre", -rR * R.z)
    frame_com = rear_centre.locatenew("frame_com", P["xB"] * B.x + (P["zB"] + rR) * B.z)
    steer_pt = rear_centre.locatenew("steer_pt", (w + c) * B.x + rR * B.z)  # steering axis on the ground
    fork_com = steer_pt.locatenew("fork_com", (P["xH"] - w - c) * H.x + P["zH"] * H.z)
    front_centre = steer_pt.locatenew("front_centre", -c * H.x - rF * H.z)
    down = (Y.z - me.dot(Y.z, H.y) * H.y)
    front_contact = front_centre.locatenew("front_contact", rF * down.normalize())

    rear_centre.v2pt_theory(rear_contact, N, WR)
    frame_com.v2pt_theory(rear_centre, N, B)
    steer_pt.v2pt_theory(rear_centre, N, B)
    fork_com.v2pt_theory(steer_pt, N, H)
    front_centre.v2pt_theory(steer_pt, N, H)
    front_contact.v2pt_theory(front_centre, N, WF)

    bodies = [
        me.RigidBody("rear_wheel", rear_centre, WR, P["mR"], (me.inertia(B, P["IRxx"], P["IRyy"], P["IRxx"]), rear_centre)),
        me.RigidBody("rear_frame", frame_com, B, P["mB"],
                     (me.inertia(B, P["IBxx"], P["IByy"], P["IBzz"], 0, 0, P["IBxz"]), frame_com)),
        me.RigidBody("front_frame", fork_com, H, P["mH"],
                     (me.inertia(H, P["IHxx"], P["IHyy"], P["IHzz"], 0, 0, P["IHxz"]), fork_com)),
        me.RigidBody("front_wheel", front_centre, WF, P["mF"], (me.inertia(H, P["IFxx"], P["IFyy"], P["IFxx"]), front_centre)),
    ]
    loads = [(rear_centre, P["mR"] * g * N.z), (frame_com, P["mB"] * g * N.z),
             (fork_com, P["mH"] * g * N.z), (front_centre, P["mF"] * g * N.z)]

    kd = [q1.diff(t) - u1, q2.diff(t) - u2, q3.diff(t) - u4, q4.diff(t) - u5]
    config = [me.dot(front_contact.pos_from(rear_contact), Y.z)]
    vel = [me.dot(front_contact.vel(N), Y.x), me.dot(front_contact.vel(N), Y.y), me.dot(front_contact.vel(N), Y.z)]
    kane = me.KanesMethod(N, q_ind=[q1, q2, q4], u_ind=[u2, u3, u5], kd_eqs=kd, q_dependent=[q3],
                          configuration_constraints=config, u_dependent=[[u1, u4, u6][k] for k in dependent_order], velocity_constraints=vel)
    kane.kanes_equations(bodies, loads)
    return kane, P, (q1, q2, q3, q4), (u1, u2, u3, u4, u5, u6)


def derive():
    kane, P, (q1, q2, q3, q4), (u1, u2, u3, u4, u5, u6) = kanes_method()
    M, F = kane.mass_matrix, kane.forcing
    sub = {}
    for k, q in enumerate([q1, q2, q4, q3]):
        sub[q] = sm.Symbol(f"q[{k}]")
    for k, u in enumerate([u2, u3, u5, u1, u4, u6]):
        sub[u] = sm.Symbol(f"u[{k}]")
    for k, (name, _) in enumerate(PARAMS):
        sub[P[name]] = sm.Symbol(f"p[{k}]")
    return M.xreplace(sub), F.xreplace(sub)


def codegen(M, F, outdir):
    name = "sympy_bicycle"
    o = M.shape[0]
    entries = [M[i, j] for i in range(o) for j in range(o)] + [F[i] for i in range(o)]
    temps, reduced = sm.cse(entries, symbols=sm.numbered_symbols("x"))
    pr = Printer()
    ops_sympy = 0
    ops_conv = {"adds": 0, "muls": 0, "divs": 0, "calls": 0}
    pnames = ", ".join(f'"{n}"' for n, _ in PARAMS)
    pvals = ", ".join(str(float(sm.sympify(v))) for _, v in PARAMS)
    lines = [
        f"/* Generated by bench/sympy_bicycle.py (sympy {sm.__version__}, KanesMethod, PyDy's layout of",
        f"   the Whipple bicycle): M u' = F, {o} speeds (u2, u3, u5, u1, u4, u6). */",
        "#include <math.h>",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        f"extern const int {name}_nu;\nconst int {name}_nu = {o};",
        f"extern const int {name}_np;\nconst int {name}_np = {len(PARAMS)};",
        f"extern const char* const {name}_pnames[];\nconst char* const {name}_pnames[] = {{{pnames}}};",
        f"extern const double {name}_pvalues[];\nconst double {name}_pvalues[] = {{{pvals}}};",
        f"void {name}_mass_forcing(const double* q, const double* u, const double* p, double* M, double* F) {{",
        "  (void)q; (void)u; (void)p;",
    ]
    for sym, ex in temps:
        lines.append(f"  const double {sym} = {pr.doprint(ex)};")
        ops_sympy += sm.count_ops(ex, visual=False)
        for k, v in mbsc_convention_ops(ex).items():
            ops_conv[k] += v
    for i, ex in enumerate(reduced):
        dest = f"M[{i}]" if i < o * o else f"F[{i - o * o}]"
        lines.append(f"  {dest} = {pr.doprint(ex)};")
        ops_sympy += sm.count_ops(ex, visual=False)
        for k, v in mbsc_convention_ops(ex).items():
            ops_conv[k] += v
    lines += ["}", "#ifdef __cplusplus", "}", "#endif", ""]
    path = os.path.join(outdir, f"{name}.c")
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return path, len(temps), int(ops_sympy), ops_conv


def main(argv):
    if len(argv) != 2:
        sys.stderr.write(__doc__)
        return 2
    outdir = argv[1]
    os.makedirs(outdir, exist_ok=True)
    t0 = time.perf_counter()
    M, F = derive()
    t1 = time.perf_counter()
    sys.stderr.write(f"sympy_bicycle: derived in {t1 - t0:.1f} s\n")
    path, ntemps, ops_sympy, ops_conv = codegen(M, F, outdir)
    t2 = time.perf_counter()
    stats = {
        "model": "whipple_bicycle",
        "sympy": sm.__version__,
        "speeds": M.shape[0],
        "derive_s": round(t1 - t0, 4),
        "codegen_s": round(t2 - t1, 4),
        "cse_temporaries": ntemps,
        "count_ops": ops_sympy,
        "ops_mbsc_conv": sum(ops_conv.values()),
        "ops_mbsc_conv_detail": ops_conv,
        "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
        "file": path,
    }
    with open(os.path.join(outdir, "sympy_bicycle.json"), "w") as f:
        json.dump(stats, f, indent=1)
    print(json.dumps(stats))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
