# SPDX-License-Identifier: GPL-2.0-or-later
# The Python side of tests/cli/python_module_test.cpp's derivative case: the module of a
# model generated with --derivatives returns rhs_jacobian as (J_x, J_u) and
# inverse_dynamics_jacobian as (du/dx, du/dzdot), matrices of the documented shapes,
# equal to central differences of rhs and inverse_dynamics at a random state.
# Prints "checked N values" and exits 0, or prints what differs and exits 1.
#   usage: check_python_derivatives.py MODULE_DIR NAME
import importlib
import sys

import numpy as np

sys.path.insert(0, sys.argv[1])
mod = importlib.import_module(sys.argv[2])
model = mod.Model()
rng = np.random.default_rng(5)
x = rng.uniform(-0.8, 0.8, mod.kNx)
u = rng.uniform(-0.8, 0.8, mod.kNin)
zdot = rng.uniform(-0.8, 0.8, mod.kNdof)
failures, checked = [], 0


def central(f, v, j, h=1e-6):
    up, down = v.copy(), v.copy()
    up[j] += h
    down[j] -= h
    return (f(up) - f(down)) / (2 * h)


def compare(name, got, shape, columns):
    global checked
    if got.shape != shape:
        failures.append("%s: shape %s, expected %s" % (name, got.shape, shape))
        return
    for j, column in enumerate(columns):
        for i in range(shape[0]):
            checked += 1
            if abs(got[i, j] - column[i]) > 1e-6 * max(1.0, abs(column[i])):
                failures.append("%s[%d, %d]: %r, differences give %r" % (name, i, j, got[i, j], column[i]))


jx, ju = model.rhs_jacobian(0.0, x, u)
compare("J_x", jx, (mod.kNx, mod.kNx), [central(lambda v: model.rhs(0.0, v, u), x, j) for j in range(mod.kNx)])
compare("J_u", ju, (mod.kNx, mod.kNin), [central(lambda v: model.rhs(0.0, x, v), u, j) for j in range(mod.kNin)])
kx, kz = model.inverse_dynamics_jacobian(0.0, x, zdot)
compare("du/dx", kx, (mod.kNin, mod.kNx),
        [central(lambda v: model.inverse_dynamics(0.0, v, zdot), x, j) for j in range(mod.kNx)])
compare("du/dzdot", kz, (mod.kNin, mod.kNdof),
        [central(lambda v: model.inverse_dynamics(0.0, x, v), zdot, j) for j in range(mod.kNdof)])
for f in failures:
    print(f)
print("checked %d values" % checked)
sys.exit(1 if failures else 0)
