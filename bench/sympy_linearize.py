#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""The sympy peer of the linearization benchmark (bench/run_linearize.sh): the ring-disc of
models/ring_disc.mbs (thesis Ex 4.2 / 4.7) and the Whipple bicycle of bench/sympy_bicycle.py
(PyDy's layout) linearized with sympy.physics.mechanics.

Per model it times
  derive:  KanesMethod.kanes_equations (not compared: mbsc compiles once, into a cache);
  linearize: KanesMethod.linearize(A_and_B=False): the symbolic M, A of
           M [q, u]' = A [q_ind, u_ind] (sympy's Linearizer, every Jacobian symbolic);
  op_point: the operating point (and the data) substituted into M and A with
           sympy's msubs, then A_and_B's step A = P^T M^-1 A (Linearizer's documented
           route; M^-1 A by sympy's LUsolve) at the check point;
  sweep:   1000 points: M and A lambdified once in the swept quantities (the
           set-up timed apart), then per point the numeric M^-1 A (numpy.linalg.solve),
           P^T and numpy.linalg.eigvals. This is the fastest honest sympy route found:
           substituting the point symbolically (msubs + LUsolve per point) costs
           the op_point time per point.
The ring-disc sweeps the mass ratio m2/m1 over (0, 5] at the thesis incline with the
steady angle theta_bar solved per point (the relation of Ex 4.2(h), Newton); the bicycle
sweeps the forward speed v over [0, 10] m/s, upright and straight.

Usage: /usr/bin/python3 bench/sympy_linearize.py OUTDIR [NPTS] [--numeric-data]
(--numeric-data: the bicycle derived with its data as numbers from the start, a smaller
symbolic problem; the ring-disc always keeps its data symbolic.)
Writes OUTDIR/sympy_linearize.json (timings, the check-point eigenvalues) and
OUTDIR/sympy_sweep.txt (every sweep point's eigenvalues, as the mbsc driver writes them).
"""
import json
import math
import os
import sys
import time

import numpy as np
import sympy as sm
import sympy.physics.mechanics as me

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sympy_bicycle import PARAMS as BIKE_PARAMS, kanes_method  # noqa: E402

T = me.dynamicsymbols._t
NUMERIC_DATA = False  # --numeric-data: the bicycle derived with Table 1's numbers, not symbols


# ---------------- the ring-disc (models/ring_disc.mbs) ----------------
RING = {"m1": 0.67, "m2": 0.08, "r1": 1.0, "r2": 0.3, "g": 9.8, "xi": 0.9272952180016122}


def ring_kane():
    """The ring R and disc D as planar rigid bodies with the mbsc model's coordinates
    (x, y, angle of each mass centre; the angle theta of the centre line) and speeds (the
    mass centres' velocities in space, the angular rates, theta'), the five velocity rows
    of the model, independent speeds theta' and D.w."""
    m1, m2, r1, r2, g, xi = sm.symbols("m1 m2 r1 r2 g xi")
    Rx, Ry, Rth, Dx, Dy, Dth, th = me.dynamicsymbols("Rx Ry Rth Dx Dy Dth th")
    Ru, Rv, Rw, Du, Dv, Dw, dth = me.dynamicsymbols("Ru Rv Rw Du Dv Dw dth")
    N = me.ReferenceFrame("N")
    RF = N.orientnew("RF", "Axis", [Rth, N.z])
    DF = N.orientnew("DF", "Axis", [Dth, N.z])
    RF.set_ang_vel(N, Rw * N.z)
    DF.set_ang_vel(N, Dw * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    Rc = O.locatenew("Rc", Rx * N.x + Ry * N.y)
    Dc = O.locatenew("Dc", Dx * N.x + Dy * N.y)
    Rc.set_vel(N, Ru * N.x + Rv * N.y)
    Dc.set_vel(N, Du * N.x + Dv * N.y)
    bodies = [me.RigidBody("R", Rc, RF, m1, (me.inertia(RF, 0, 0, m1 * r1**2), Rc)),
              me.RigidBody("D", Dc, DF, m2, (me.inertia(DF, 0, 0, m2 * r2**2 / 2), Dc))]
    grav = g * sm.sin(xi) * N.x - g * sm.cos(xi) * N.y
    loads = [(Rc, m1 * grav), (Dc, m2 * grav)]
    c, s = sm.cos(xi - th), sm.sin(xi - th)
    vel = [Ru + Rw * r1, Rv,
           Ru - Du + c * (Rw * r1 - Dw * r2),
           Rv - Dv + s * (Rw * r1 - Dw * r2),
           Du - Ru + c * dth * (r1 - r2)]
    qs = [Rx, Ry, Rth, Dx, Dy, Dth, th]
    us = [Ru, Rv, Rw, Du, Dv, Dw, dth]
    kd = [q.diff(T) - u for q, u in zip(qs, us)]
    kane = me.KanesMethod(N, q_ind=qs, u_ind=[dth, Dw], kd_eqs=kd, u_dependent=[Ru, Rv, Rw, Du, Dv],
                          velocity_constraints=vel)
    kane.kanes_equations(bodies, loads)
    params = dict(zip([m1, m2, r1, r2, g, xi], [RING[k] for k in ("m1", "m2", "r1", "r2", "g", "xi")]))
    return kane, params, qs, us, (m1, m2)


def ring_steady_theta(mu, guess):
    """theta_bar of Ex 4.2(h): sin T = (mu + 1)(sin xi - 3 sin T + 2 cos(T - xi) sin xi)."""
    k, X, t = mu + 1.0, RING["xi"], guess
    for _ in range(50):
        f = math.sin(t) - k * (math.sin(X) - 3 * math.sin(t) + 2 * math.cos(t - X) * math.sin(X))
        df = math.cos(t) - k * (-3 * math.cos(t) - 2 * math.sin(t - X) * math.sin(X))
        step = f / df
        t -= step
        if abs(step) < 1e-15:
            break
    return t


def ring_op(qs, us, th_val, a_sym_or_val):
    """The reference of Ex 4.7: theta = theta_bar at rest, with the steady accelerations
    u1' = u2' = a, w1' = -a/r1, w2' = -a/r2 (a = 2 g sin T / (2 cos(T - xi) + 1))."""
    Rx, Ry, Rth, Dx, Dy, Dth, th = qs
    Ru, Rv, Rw, Du, Dv, Dw, dth = us
    r1, r2, xi = RING["r1"], RING["r2"], RING["xi"]
    a = a_sym_or_val
    op = {Rx: 0, Ry: r1, Rth: 0, Dx: (r1 - r2) * sm.sin(xi - th_val), Dy: r1 - (r1 - r2) * sm.cos(xi - th_val), Dth: 0,
          th: th_val}
    op.update({q.diff(T): 0 for q in qs})
    op.update({u: 0 for u in us})
    op.update({Ru.diff(T): a, Rv.diff(T): 0, Rw.diff(T): -a / r1, Du.diff(T): a, Dv.diff(T): 0, Dw.diff(T): -a / r2,
               dth.diff(T): 0})
    return op


def ring_accel(th_val):
    return 2 * RING["g"] * math.sin(th_val) / (2 * math.cos(th_val - RING["xi"]) + 1)


# ---------------- the bicycle (bench/sympy_bicycle.py) ----------------
def bike_op(P, qs, us, v):
    """Upright and straight at forward speed v: every angle and rate zero but the wheels'
    spin rates relative to their frames, -v/rR and -v/rF; every acceleration zero."""
    q1, q2, q3, q4 = qs
    u1, u2, u3, u4, u5, u6 = us
    pv = {} if NUMERIC_DATA else {P[n]: sm.sympify(val) for n, val in BIKE_PARAMS}
    rR, rF = sm.sympify(dict(BIKE_PARAMS)["rR"]), sm.sympify(dict(BIKE_PARAMS)["rF"])
    op = {q: 0 for q in qs}
    op.update({q.diff(T): 0 for q in qs})
    op.update({u1: 0, u2: 0, u4: 0, u5: 0, u3: -v / rR, u6: -v / rF})
    op.update({u.diff(T): 0 for u in us})
    return op, pv


def eig_list(A):
    return [[float(z.real), float(z.imag)] for z in sorted(np.linalg.eigvals(A), key=lambda z: (z.real, z.imag))]


def numeric(Mx):
    return np.array(Mx.evalf(), dtype=float)


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    global NUMERIC_DATA
    if "--numeric-data" in argv:
        NUMERIC_DATA = True
        argv = [a for a in argv if a != "--numeric-data"]
    outdir = argv[1]
    npts = int(argv[2]) if len(argv) > 2 else 1000
    os.makedirs(outdir, exist_ok=True)
    out = {"sympy": sm.__version__, "numpy": np.__version__, "npts": npts}
    sweep_lines = []

    # ---- ring-disc ----
    t0 = time.perf_counter()
    kane, params, qs, us, (m1, m2) = ring_kane()
    t1 = time.perf_counter()
    lin = kane.to_linearizer()
    M, A, _ = lin.linearize(A_and_B=False)
    t2 = time.perf_counter()
    th_bar = ring_steady_theta(RING["m2"] / RING["m1"], 0.6)
    op = ring_op(qs, us, th_bar, ring_accel(th_bar))
    Ms = msubs_all(M, op, params)
    As = msubs_all(A, op, params)
    Amin = lin.perm_mat.T * Ms.LUsolve(As)
    t3 = time.perf_counter()
    eig = eig_list(numeric(Amin))
    out["ring"] = {"derive_s": t1 - t0, "linearize_s": t2 - t1, "op_point_s": t3 - t2, "m": Amin.shape[0],
                   "theta_bar": th_bar, "eigenvalues": eig, "omega": max(z[1] for z in eig)}
    # The sweep: M, A lambdified in (theta_bar, m2, a), the other data substituted.
    t4 = time.perf_counter()
    th_s, a_s = sm.symbols("theta_bar a_ref")
    op_s = ring_op(qs, us, th_s, a_s)
    pm = {k: v for k, v in params.items() if k != m2}
    fM = sm.lambdify((th_s, m2, a_s), msubs_all(M, op_s, pm), "numpy")
    fA = sm.lambdify((th_s, m2, a_s), msubs_all(A, op_s, pm), "numpy")
    P = np.array(lin.perm_mat, dtype=float)
    t5 = time.perf_counter()
    th, omegas = 0.6, []
    for k in range(npts):
        mu = 5.0 * (k + 1) / npts
        th = ring_steady_theta(mu, th)
        a = ring_accel(th)
        Ak = P.T @ np.linalg.solve(np.array(fM(th, mu * RING["m1"], a), dtype=float), np.array(fA(th, mu * RING["m1"], a), dtype=float))
        omegas.append(float(np.max(np.linalg.eigvals(Ak).imag)))
    t6 = time.perf_counter()
    out["ring"].update({"sweep_setup_s": t5 - t4, "sweep_s": t6 - t5})
    sweep_lines += [f"ring {k} {w!r}" for k, w in enumerate(omegas)]
    sys.stderr.write(f"sympy_linearize: ring-disc {json.dumps(out['ring'])}\n")
    write(outdir, out, sweep_lines)  # kept should the bicycle not finish

    # ---- bicycle ----
    t0 = time.perf_counter()
    # The dependent speeds in the order (u6, u1, u4): upright, the velocity rows' Jacobian
    # in them is triangular with a non-zero diagonal (front contact along Y.x: the front
    # wheel's spin; along Y.y: the yaw; along Y.z: the pitch). In sympy_bicycle.py's order
    # (u1, u4, u6) the first pivot, d(front contact along Y.x)/d(yaw rate), vanishes
    # upright and sympy's elimination gives 0/0 there (that file's C code returns NaN
    # exactly upright): the same equations, the elimination ordered to be finite at the
    # operating point.
    kane, Pb, qs, us = kanes_method(dependent_order=(2, 0, 1), numeric_data=NUMERIC_DATA)
    t1 = time.perf_counter()
    lin = kane.to_linearizer()
    M, A, _ = lin.linearize(A_and_B=False)
    t2 = time.perf_counter()
    op, pv = bike_op(Pb, qs, us, sm.Float(5.0))
    Ms = msubs_all(M, op, pv)
    As = msubs_all(A, op, pv)
    Amin = lin.perm_mat.T * Ms.LUsolve(As)
    t3 = time.perf_counter()
    eig = eig_list(numeric(Amin))
    out["bike"] = {"numeric_data": NUMERIC_DATA, "derive_s": t1 - t0, "linearize_s": t2 - t1, "op_point_s": t3 - t2, "m": Amin.shape[0], "eigenvalues": eig}
    t4 = time.perf_counter()
    v_s = sm.Symbol("v")
    op_s, _ = bike_op(Pb, qs, us, v_s)
    fM = sm.lambdify((v_s,), msubs_all(M, op_s, pv), "numpy")
    fA = sm.lambdify((v_s,), msubs_all(A, op_s, pv), "numpy")
    P = np.array(lin.perm_mat, dtype=float)
    t5 = time.perf_counter()
    eigs = []
    for k in range(npts):
        v = 10.0 * k / (npts - 1)
        Ak = P.T @ np.linalg.solve(np.array(fM(v), dtype=float), np.array(fA(v), dtype=float))
        eigs.append(np.linalg.eigvals(Ak))
    t6 = time.perf_counter()
    out["bike"].update({"sweep_setup_s": t5 - t4, "sweep_s": t6 - t5})
    for k, e in enumerate(eigs):
        sweep_lines.append(f"bike {k} " + " ".join(f"{float(z.real)!r} {float(z.imag)!r}" for z in e))
    sys.stderr.write(f"sympy_linearize: bicycle {json.dumps(out['bike'])}\n")

    write(outdir, out, sweep_lines)
    return 0


def write(outdir, out, sweep_lines):
    with open(os.path.join(outdir, "sympy_linearize.json"), "w") as f:
        json.dump(out, f, indent=1)
    with open(os.path.join(outdir, "sympy_sweep.txt"), "w") as f:
        f.write("\n".join(sweep_lines) + "\n")


def msubs_all(Mx, op, params):
    """The operating point, then the data, substituted with sympy's msubs (derivatives
    first: msubs replaces q' before q)."""
    return me.msubs(Mx, op, params)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
