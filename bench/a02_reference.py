"""The error of an `mbsc run` of tests/data/chain/iftomm_a02.mbs against the chain's exact
one-degree-of-freedom motion. On its parallelogram branch the chain is one pendulum,
J theta'' = -K cos(theta), with J = (N + 1) m a^2 / 3 + N m a^2 (the cranks about their
pivots, the couplers translating) and K = g ((N + 1) m a / 2 + N m a); integrated here by
RK4 at 2.5e-5 s (its own error below 1e-12 rad over 20 s, checked against 5e-5 s).
  /usr/bin/python3 bench/a02_reference.py run.csv   ->  largest and final |theta - exact|
"""
import csv
import math
import sys

N, a, m, g = 40, 1.0, 1.0, 9.81
J = (N + 1) * m * a * a / 3 + N * m * a * a
K = g * ((N + 1) * m * a / 2 + N * m * a)


def rate(y):
    return (y[1], -K / J * math.cos(y[0]))


def rk4(y, h):
    k1 = rate(y)
    k2 = rate((y[0] + h / 2 * k1[0], y[1] + h / 2 * k1[1]))
    k3 = rate((y[0] + h / 2 * k2[0], y[1] + h / 2 * k2[1]))
    k4 = rate((y[0] + h * k3[0], y[1] + h * k3[1]))
    return tuple(y[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]) for i in range(2))


rows = list(csv.DictReader(open(sys.argv[1])))
y, t, h = (math.pi / 2, 1.0), 0.0, 2.5e-5
worst = final = 0.0
for row in rows:
    target = float(row["t"])
    while t < target - 1e-12:
        step = min(h, target - t)
        y = rk4(y, step)
        t += step
    final = abs(float(row["crank_angle"]) - y[0])
    worst = max(worst, final)
print(f"largest |theta - exact| {worst:.3g} rad, at t = {t:g}: {final:.3g} rad")
