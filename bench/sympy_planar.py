#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""The sympy peer of the planar benchmark: four-bar, slider-crank, Whitworth and 3RRR
with sympy.physics.mechanics (KanesMethod with dependent coordinates and speeds), then
C code for its mass matrix and forcing.

Usage: /usr/bin/python3 bench/sympy_planar.py MODEL OUTDIR
       MODEL = four_bar | slider_crank | whitworth | three_rrr
               | four_bar_abs (the four-bar in mbsc's absolute coordinates, a variant)

Same data as models/MODEL.mbs. Formulation, as a sympy user writes a closed loop: the
generalized coordinates are the link angles (absolute, from the ground x axis) and the
slider positions -- a minimal-but-for-the-loops set, not mbsc's (x, y, theta) of every
body --, u_k = q_k', the loop-closure equations are configuration constraints
(q_dependent) and their time derivatives velocity constraints (u_dependent).
KanesMethod then eliminates the dependent speeds from Fr + Fr* with the symbolic
solution of the velocity constraints (B_dep^-1 B_ind) and returns
  mass_matrix (o x o) u' = forcing (o)
where o = all speeds: p dynamic rows plus the m differentiated velocity constraints.
Independent speeds: the crank rate (one-DOF loops); for the 3RRR the platform's
(x', y', theta'): then B_dep is block diagonal (one 2x2 block per leg, the legs'
inverse kinematics), where the base rates would need a full 6x6 symbolic solve.
The coordinate names are mbsc's state names (absolute angles are mbsc's theta), so the
driver maps states and accelerations by name.

Writes
  OUTDIR/sympy_MODEL.c     void sympy_MODEL_mass_forcing(const double* q, const double* u,
                              const double* p, const double* in, double* M, double* F)
                           (M o x o row-major, F o; p in the order of sympy_MODEL_pnames,
                           in = inputs in the order of sympy_MODEL_inames) and the name
                           tables sympy_MODEL_qnames / _unames / _pnames / _inames, sizes
                           sympy_MODEL_nq, _np, _nin;
  OUTDIR/sympy_MODEL.json  timings and operation counts (as bench/sympy_chain.py: mbsc's
                           convention on the CSE'd expressions and sympy.count_ops; the
                           driver's LU solve is not included).
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

t = me.dynamicsymbols._t


def e(th):
    return sm.Matrix([sm.cos(th), sm.sin(th)])


class Planar:
    """Bookkeeping for one planar model: coordinates, bodies, loads, constraints."""

    def __init__(self, name):
        self.name = name
        self.N = me.ReferenceFrame("N")
        self.O = me.Point("O")
        self.O.set_vel(self.N, 0)
        self.q, self.u, self.qnames, self.unames = [], [], [], []
        self.params, self.pnames, self.inputs, self.inames = [], [], [], []
        self.bodies, self.loads, self.constraints = [], [], []

    def coord(self, name, speed):
        k = len(self.q)
        q = me.dynamicsymbols(f"q{k}")
        u = me.dynamicsymbols(f"u{k}")
        self.q.append(q)
        self.u.append(u)
        self.qnames.append(name)
        self.unames.append(speed)
        return q

    def param(self, name):
        s = sm.Symbol(name)
        self.params.append(s)
        self.pnames.append(name)
        return s

    def inp(self, name):
        s = sm.Symbol(name)
        self.inputs.append(s)
        self.inames.append(name)
        return s

    def vec(self, v2):
        return v2[0] * self.N.x + v2[1] * self.N.y

    def point(self, name, pos2):
        P = self.O.locatenew(name, self.vec(pos2))
        P.set_vel(self.N, P.pos_from(self.O).dt(self.N))
        return P

    def rigid(self, name, com2, theta, mass, inertia, gvec=None):
        A = self.N.orientnew(f"F_{name}", "Axis", [theta, self.N.z])
        P = self.point(f"G_{name}", com2)
        body = me.RigidBody(name, P, A, mass, (me.inertia(A, 0, 0, inertia), P))
        self.bodies.append(body)
        if gvec is not None:
            self.loads.append((P, mass * self.vec(gvec)))
        return body, A, P

    def particle(self, name, pos2, mass, gvec=None):
        P = self.point(f"P_{name}", pos2)
        self.bodies.append(me.Particle(name, P, mass))
        if gvec is not None:
            self.loads.append((P, mass * self.vec(gvec)))
        return P

    def close(self, *eqs):
        self.constraints.extend(eqs)

    def equations(self, independent):
        """KanesMethod with the speeds named in `independent` independent."""
        kd = [qk.diff(t) - uk for qk, uk in zip(self.q, self.u)]
        qdot = {qk.diff(t): uk for qk, uk in zip(self.q, self.u)}
        fc = sm.Matrix(self.constraints)
        fv = fc.diff(t).xreplace(qdot)
        ind = [self.unames.index(s) for s in independent]
        dep = [k for k in range(len(self.u)) if k not in ind]
        kane = me.KanesMethod(self.N, q_ind=[self.q[k] for k in ind], u_ind=[self.u[k] for k in ind],
                              kd_eqs=kd, q_dependent=[self.q[k] for k in dep],
                              configuration_constraints=list(fc), u_dependent=[self.u[k] for k in dep],
                              velocity_constraints=list(fv))
        kane.kanes_equations(self.bodies, self.loads)
        M, F = kane.mass_matrix, kane.forcing
        # KanesMethod orders the speeds (independent, dependent): record that order
        order = ind + dep
        sub = {}
        for slot, k in enumerate(order):
            sub[self.q[k]] = sm.Symbol(f"q[{slot}]")
            sub[self.u[k]] = sm.Symbol(f"u[{slot}]")
        for i, s in enumerate(self.params):
            sub[s] = sm.Symbol(f"p[{i}]")
        for i, s in enumerate(self.inputs):
            sub[s] = sm.Symbol(f"in[{i}]")
        self.qnames = [self.qnames[k] for k in order]
        self.unames = [self.unames[k] for k in order]
        return M.xreplace(sub), F.xreplace(sub)


def four_bar():
    s = Planar("four_bar")
    a, b, c, d, g = (s.param(n) for n in ("a", "b", "c", "d", "g"))
    m1, m2, m3, tau0 = (s.param(n) for n in ("m1", "m2", "m3", "tau0"))
    t1 = s.coord("crank.theta", "crank.w")
    t2 = s.coord("coupler.theta", "coupler.w")
    t3 = s.coord("rocker.theta", "rocker.w")
    grav = (0, -g)
    _, A1, _ = s.rigid("crank", a / 2 * e(t1), t1, m1, m1 * a**2 / 12, grav)
    pa = a * e(t1)
    s.rigid("coupler", pa + b / 2 * e(t2), t2, m2, m2 * b**2 / 12, grav)
    q0 = sm.Matrix([d, 0])
    s.rigid("rocker", q0 + c / 2 * e(t3), t3, m3, m3 * c**2 / 12, grav)
    s.loads.append((A1, tau0 * s.N.z))
    loop = pa + b * e(t2) - q0 - c * e(t3)
    s.close(loop[0], loop[1])
    return s, ["crank.w"]


def four_bar_abs():
    """The four-bar in mbsc's own coordinates (x, y, theta of every bar, 8 joint
    equations as in models/four_bar.mbs): a variant that separates the choice of
    coordinates from the formulation."""
    s = Planar("four_bar_abs")
    a, b, c, d, g = (s.param(n) for n in ("a", "b", "c", "d", "g"))
    m1, m2, m3, tau0 = (s.param(n) for n in ("m1", "m2", "m3", "tau0"))
    grav = (0, -g)
    X = {}
    for name, length, mass in (("crank", a, m1), ("coupler", b, m2), ("rocker", c, m3)):
        X[name] = [s.coord(f"{name}.{k}", f"{name}.{v}") for k, v in (("x", "u"), ("y", "v"), ("theta", "w"))]
        _, frame, _ = s.rigid(name, sm.Matrix(X[name][:2]), X[name][2], mass, mass * length**2 / 12, grav)
        if name == "crank":
            s.loads.append((frame, tau0 * s.N.z))

    def end(name, length, sign):
        return sm.Matrix(X[name][:2]) + sign * length / 2 * e(X[name][2])

    s.close(*end("crank", a, -1), *(end("coupler", b, -1) - end("crank", a, 1)),
            *(end("coupler", b, 1) - end("rocker", c, 1)), *(end("rocker", c, -1) - sm.Matrix([d, 0])))
    return s, ["crank.w"]


def slider_crank():
    s = Planar("slider_crank")
    r, l, m1, J1, m2, J2, m3, g = (s.param(n) for n in ("r", "l", "m1", "J1", "m2", "J2", "m3", "g"))
    tau, f_load = s.inp("tau"), s.inp("F_load")
    t1 = s.coord("crank.theta", "crank.w")
    t2 = s.coord("rod.theta", "rod.w")
    xs = s.coord("slider.x", "slider.u")
    grav = (0, -g)
    _, A1, _ = s.rigid("crank", r / 2 * e(t1), t1, m1, J1, grav)
    pa = r * e(t1)
    s.rigid("rod", pa + l / 2 * e(t2), t2, m2, J2, grav)
    ps = s.particle("slider", sm.Matrix([xs, 0]), m3, grav)
    s.loads.append((A1, tau * s.N.z))
    s.loads.append((ps, f_load * s.N.x))
    loop = pa + l * e(t2) - sm.Matrix([xs, 0])
    s.close(loop[0], loop[1])
    return s, ["crank.w"]


def whitworth():
    s = Planar("whitworth")
    m1, m2, I2, L2 = (s.param(n) for n in ("m1", "m2", "I2", "L2"))
    m3, I3, L3, m4, I4, L4 = (s.param(n) for n in ("m3", "I3", "L3", "m4", "I4", "L4"))
    u1 = s.inp("u1")
    xs = s.coord("slider.x", "slider.u")
    tr = s.coord("rod.theta", "rod.w")
    tk = s.coord("rocker.theta", "rocker.w")
    tc = s.coord("crank.theta", "crank.w")
    pslider = sm.Matrix([xs, sm.Rational(8, 10)])  # on the guide y = 0.8 (no gravity: flat)
    s.particle("slider", pslider, m1)
    s.rigid("rod", pslider + L2 / 2 * e(tr), tr, m2, I2)
    s.rigid("rocker", L3 / 2 * e(tk), tk, m3, I3)
    pivot = sm.Matrix([0, sm.Rational(3, 10)])
    _, Ac, _ = s.rigid("crank", pivot, tc, m4, I4)  # mass centre at its pivot
    s.loads.append((Ac, u1 * s.N.z))
    loop = pslider + L2 * e(tr) - L3 * e(tk)  # rod.B at rocker.T
    pin = pivot + L4 * e(tc)  # crank.P on the rocker's slot line through the origin
    s.close(loop[0], loop[1], -sm.sin(tk) * pin[0] + sm.cos(tk) * pin[1])
    return s, ["crank.w"]


def three_rrr():
    s = Planar("three_rrr")
    m1, I1, m2, I2, m3, I3 = (s.param(n) for n in ("m1", "I1", "m2", "I2", "m3", "I3"))
    us = [s.inp(n) for n in ("u1", "u2", "u3")]
    r3 = sm.sqrt(3)
    base = [sm.Matrix([3, 0]), sm.Matrix([-sm.Rational(3, 2), 3 * r3 / 2]),
            sm.Matrix([-sm.Rational(3, 2), -3 * r3 / 2])]
    joint = [sm.Matrix([1, 0]), sm.Matrix([-sm.Rational(1, 2), r3 / 2]), sm.Matrix([-sm.Rational(1, 2), -r3 / 2])]
    legs = ["HA", "HB", "HC"]
    tp = [s.coord(f"{h}.proximal.theta", f"{h}.proximal.w") for h in legs]
    td = [s.coord(f"{h}.distal.theta", f"{h}.distal.w") for h in legs]
    x = s.coord("platform.x", "platform.u")
    y = s.coord("platform.y", "platform.v")
    th = s.coord("platform.theta", "platform.w")
    _, Ap, _ = s.rigid("platform", sm.Matrix([x, y]), th, m1, I1)
    rot = sm.Matrix([[sm.cos(th), -sm.sin(th)], [sm.sin(th), sm.cos(th)]])
    for k, h in enumerate(legs):
        _, Ak, _ = s.rigid(f"{h}_proximal", base[k], tp[k], m3, I3)  # mass centre at the pivot
        elbow = base[k] + 2 * e(tp[k])
        s.rigid(f"{h}_distal", elbow - e(td[k]), td[k], m2, I2)  # P (0,0), E (2,0), com (1,0)
        s.loads.append((Ak, us[k] * s.N.z))
        loop = elbow - 2 * e(td[k]) - (sm.Matrix([x, y]) + rot * joint[k])
        s.close(loop[0], loop[1])
    return s, ["platform.u", "platform.v", "platform.w"]


MODELS = {"four_bar": four_bar, "four_bar_abs": four_bar_abs, "slider_crank": slider_crank, "whitworth": whitworth, "three_rrr": three_rrr}


def codegen(s, M, F, outdir):
    name = f"sympy_{s.name}"
    o = M.shape[0]
    entries = [M[i, j] for i in range(o) for j in range(o)] + [F[i] for i in range(o)]
    temps, reduced = sm.cse(entries, symbols=sm.numbered_symbols("x"))
    pr = Printer()
    ops_sympy = 0
    ops_conv = {"adds": 0, "muls": 0, "divs": 0, "calls": 0}

    def names(tag, lst):  # declared extern first: a const global is internal in C++
        body = ", ".join(f'"{n}"' for n in lst) if lst else '""'
        return (f"extern const char* const {name}_{tag}[];\n"
                f"const char* const {name}_{tag}[] = {{{body}}};")

    def count(tag, n):
        return f"extern const int {name}_{tag};\nconst int {name}_{tag} = {n};"

    lines = [
        f"/* Generated by bench/sympy_planar.py (sympy {sm.__version__}, KanesMethod with",
        f"   dependent coordinates and speeds): {s.name}, M u' = F, {o} speeds. */",
        "#include <math.h>",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        count("nq", o),
        count("np", len(s.pnames)),
        count("nin", len(s.inames)),
        names("qnames", s.qnames),
        names("unames", s.unames),
        names("pnames", s.pnames),
        names("inames", s.inames),
        f"void {name}_mass_forcing(const double* q, const double* u, const double* p, const double* in,"
        " double* M, double* F) {",
        "  (void)q; (void)u; (void)p; (void)in;",
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
    if len(argv) != 3 or argv[1] not in MODELS:
        sys.stderr.write(__doc__)
        return 2
    outdir = argv[2]
    os.makedirs(outdir, exist_ok=True)
    t0 = time.perf_counter()
    s, independent = MODELS[argv[1]]()
    M, F = s.equations(independent)
    t1 = time.perf_counter()
    path, ntemps, ops_sympy, ops_conv = codegen(s, M, F, outdir)
    t2 = time.perf_counter()
    stats = {
        "model": s.name,
        "sympy": sm.__version__,
        "speeds": M.shape[0],
        "independent": independent,
        "derive_s": round(t1 - t0, 4),
        "codegen_s": round(t2 - t1, 4),
        "cse_temporaries": ntemps,
        "count_ops": ops_sympy,
        "ops_mbsc_conv": sum(ops_conv.values()),
        "ops_mbsc_conv_detail": ops_conv,
        "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
        "file": path,
    }
    with open(os.path.join(outdir, f"sympy_{s.name}.json"), "w") as f:
        json.dump(stats, f, indent=1)
    print(json.dumps(stats))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
