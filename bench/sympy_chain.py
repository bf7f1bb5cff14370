#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""The sympy peer of the chain benchmark: the planar N-link pendulum chain with
sympy.physics.mechanics (KanesMethod), then C code for its mass matrix and forcing.

Usage: /usr/bin/python3 bench/sympy_chain.py N OUTDIR

Generalized coordinates q_k = th_k (absolute rod angles from the downward vertical),
speeds u_k = q_k'; particle k of mass m sits at the end of rod k (length l), gravity
-g*N.y. Writes
  OUTDIR/sympy_chainN.c     void sympy_chainN_mass(const double* q, const double* u,
                                                   const double* p, double* M)   (N*N, row-major)
                            void sympy_chainN_forcing(const double* q, const double* u,
                                                      const double* p, double* F) (N)
                            void sympy_chainN_mass_forcing(q, u, p, double* M, double* F)
                              (both at once, sharing the CSE temporaries: what the
                              benchmark driver calls)
                            with p = {m, l, g} and M u' = F;
  OUTDIR/sympy_chainN.json  timings and operation counts (also printed on stdout).

Times are measured inside the process (sympy's import is not counted):
  derive_s   building the model, KanesMethod.kanes_equations, mass_matrix and forcing;
  codegen_s  sympy.cse over all N*N + N entries together (default options), printing
             with a C99CodePrinter subclass, writing the file.
Operation counts of the printed (CSE'd) code of sympy_chainN_mass_forcing, every
temporary once plus every output:
  count_ops        sympy.count_ops(visual=False), summed: sympy's own convention
                   (x**2 is one POW, a - b one SUB, -a one NEG, 1/x one DIV);
  ops_mbsc_conv    mbsc's convention (src/ir/print_cpp.cpp), counted on the same
                   expressions: an n-term sum is n-1 adds (subtractions included,
                   negation free), an n-factor product n-1 muls (a coefficient of
                   magnitude 1 is free, any other one is a factor), denominators
                   go to one division, x**k for k = 2..4 is k-1 muls (x**-k adds a
                   division), every sin/cos/sqrt/pow call is one call. The Cholesky
                   solve that the benchmark driver adds to get u' is NOT included
                   here (the harness adds n^3/6 + n^2 flops, mbsc's formula).
"""
import json
import os
import resource
import sys
import time

import sympy as sm
import sympy.physics.mechanics as me
from sympy.printing.c import C99CodePrinter


class Printer(C99CodePrinter):
    """C99 printer that writes small integer powers as products, as mbsc does
    (gcc -O2 only rewrites pow(x, 2) itself, not pow(x, 3))."""

    def _print_Pow(self, expr):
        b, e = expr.base, expr.exp
        if e.is_Integer and 2 <= abs(int(e)) <= 4:
            k = abs(int(e))
            base = self.parenthesize(b, 100)  # always wrap non-atoms
            prod = "*".join([base] * k)
            return prod if e > 0 else "1.0/(" + prod + ")"
        return super()._print_Pow(expr)


def mbsc_convention_ops(expr):
    """Operation count of one expression with mbsc's printing conventions."""
    adds = muls = divs = calls = 0

    def visit(e):
        nonlocal adds, muls, divs, calls
        if e.is_Atom:
            return
        if e.is_Add:
            adds += len(e.args) - 1
            for a in e.args:
                visit(a)
            return
        if e.is_Mul:
            num = den = 0
            for f in e.args:
                if f.is_Number:
                    if abs(f) != 1:
                        num += 1
                    continue
                if f.is_Pow and f.exp.is_Integer and int(f.exp) < 0:
                    k = -int(f.exp)
                    den += k if k <= 4 else 1
                    if k > 4:
                        calls += 1
                    visit(f.base)
                    continue
                if f.is_Pow and f.exp.is_Integer and 2 <= int(f.exp) <= 4:
                    num += int(f.exp)
                    visit(f.base)
                    continue
                num += 1
                visit(f)
            muls += max(num, 1) - 1
            if den:
                muls += den - 1
                divs += 1
            return
        if e.is_Pow:
            ex = e.exp
            if ex.is_Integer and 2 <= abs(int(ex)) <= 4:
                muls += abs(int(ex)) - 1
                if ex < 0:
                    divs += 1
            elif ex == -1:
                divs += 1
            elif ex == sm.S.Half:
                calls += 1
            elif ex == -sm.S.Half:
                calls += 1
                divs += 1
            else:
                calls += 1
            visit(e.base)
            if not ex.is_Number:
                visit(ex)
            return
        if isinstance(e, sm.Function):
            calls += 1
            for a in e.args:
                visit(a)
            return
        raise ValueError(f"unexpected node {type(e)}: {e}")

    visit(expr)
    return {"adds": adds, "muls": muls, "divs": divs, "calls": calls}


def derive(n):
    q = me.dynamicsymbols(f"q1:{n + 1}")
    u = me.dynamicsymbols(f"u1:{n + 1}")
    m, l, g = sm.symbols("m l g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    particles, loads, kd = [], [], []
    prev = O
    for k in range(n):
        A = N.orientnew(f"A{k + 1}", "Axis", [q[k], N.z])
        A.set_ang_vel(N, u[k] * N.z)
        P = prev.locatenew(f"P{k + 1}", -l * A.y)  # l*(sin q, -cos q) in N
        P.v2pt_theory(prev, N, A)
        particles.append(me.Particle(f"pa{k + 1}", P, m))
        loads.append((P, -m * g * N.y))
        kd.append(q[k].diff() - u[k])
        prev = P
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(particles, loads)
    M = kane.mass_matrix
    F = kane.forcing
    # plain symbols named as the C arrays they become
    sub = {}
    for k in range(n):
        sub[q[k]] = sm.Symbol(f"q[{k}]")
        sub[u[k]] = sm.Symbol(f"u[{k}]")
    sub[m] = sm.Symbol("p[0]")
    sub[l] = sm.Symbol("p[1]")
    sub[g] = sm.Symbol("p[2]")
    M = M.xreplace(sub)
    F = F.xreplace(sub)
    return M, F


def codegen(n, M, F, outdir):
    name = f"sympy_chain{n}"
    entries = [M[i, j] for i in range(n) for j in range(n)] + [F[i] for i in range(n)]
    temps, reduced = sm.cse(entries, symbols=sm.numbered_symbols("x"))
    pr = Printer()
    nM = n * n
    # a temporary is emitted in the functions that need it (mass, forcing, or both)
    deps = {}
    tnames = [s for s, _ in temps]
    tset = set(tnames)
    for s, e in temps:
        deps[s] = {d for d in e.free_symbols if d in tset}

    def needed(exprs):
        need = set()
        stack = [d for e in exprs for d in e.free_symbols if d in tset]
        while stack:
            s = stack.pop()
            if s in need:
                continue
            need.add(s)
            stack.extend(deps[s])
        return need

    parts = {"mass": ([(e, f"M[{i}]") for i, e in enumerate(reduced[:nM])], "double* M"),
             "forcing": ([(e, f"F[{i}]") for i, e in enumerate(reduced[nM:])], "double* F"),
             "mass_forcing": ([(e, f"M[{i}]") for i, e in enumerate(reduced[:nM])] +
                              [(e, f"F[{i}]") for i, e in enumerate(reduced[nM:])], "double* M, double* F")}
    ops_sympy = 0
    ops_conv = {"adds": 0, "muls": 0, "divs": 0, "calls": 0}
    lines = [
        f"/* Generated by bench/sympy_chain.py (sympy {sm.__version__}, KanesMethod):",
        f"   planar {n}-link pendulum chain, p = {{m, l, g}}, M u' = F. */",
        "#include <math.h>",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
    ]
    for fn, (outs, args) in parts.items():
        need = needed([e for e, _ in outs])
        combined = fn == "mass_forcing"  # the counts are those of this one (M and F together)
        lines.append(f"void {name}_{fn}(const double* q, const double* u, const double* p, {args}) {{")
        lines.append("  (void)q; (void)u; (void)p;")
        for s, e in temps:
            if s in need:
                lines.append(f"  const double {s} = {pr.doprint(e)};")
                if combined:
                    ops_sympy += sm.count_ops(e, visual=False)
                    for k, v in mbsc_convention_ops(e).items():
                        ops_conv[k] += v
        for e, dest in outs:
            lines.append(f"  {dest} = {pr.doprint(e)};")
            if combined:
                ops_sympy += sm.count_ops(e, visual=False)
                for k, v in mbsc_convention_ops(e).items():
                    ops_conv[k] += v
        lines.append("}")
    lines += ["#ifdef __cplusplus", "}", "#endif", ""]
    path = os.path.join(outdir, f"{name}.c")
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return path, len(temps), int(ops_sympy), ops_conv


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    n = int(argv[1])
    outdir = argv[2]
    os.makedirs(outdir, exist_ok=True)
    t0 = time.perf_counter()
    M, F = derive(n)
    t1 = time.perf_counter()
    path, ntemps, ops_sympy, ops_conv = codegen(n, M, F, outdir)
    t2 = time.perf_counter()
    stats = {
        "n": n,
        "sympy": sm.__version__,
        "derive_s": round(t1 - t0, 4),
        "codegen_s": round(t2 - t1, 4),
        "total_s": round(t2 - t0, 4),
        "cse_temporaries": ntemps,
        "count_ops": ops_sympy,
        "ops_mbsc_conv": sum(ops_conv.values()),
        "ops_mbsc_conv_detail": ops_conv,
        "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
        "file": path,
    }
    with open(os.path.join(outdir, f"sympy_chain{n}.json"), "w") as f:
        json.dump(stats, f, indent=1)
    print(json.dumps(stats))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
