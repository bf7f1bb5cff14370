#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Fit the growth exponent of check/generate CPU time in the model size and fail loudly.

Usage: /usr/bin/python3 bench/fit_front_end_scaling.py bench/results/front_end_scaling.csv

For each (family, command), the slope of log(cpu time) against log(N) by least squares
over the points that took at least MIN_SECONDS (below that the process start and the
clock's resolution dominate). Exit 1 when a run failed or any slope exceeds the limit
(MBSC_SCALING_LIMIT, default 1.3), printing which; exit 0 otherwise.
"""
import csv
import math
import os
import sys

MIN_SECONDS = 0.05


def slope(points):
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def main():
    limit = float(os.environ.get("MBSC_SCALING_LIMIT", "1.3"))
    series, failed = {}, []
    with open(sys.argv[1], newline="") as f:
        for row in csv.DictReader(f):
            key = (row["family"], row["command"])
            if row["exit"] != "0":
                failed.append(f"{key[0]} {key[1]} N={row['n']} exited {row['exit']}")
                continue
            series.setdefault(key, []).append((int(row["n"]), float(row["cpu_s"])))
    over = []
    print(f"{'family':22} {'command':9} {'points':>6} {'largest N':>9} {'cpu s':>8} {'exponent':>8}")
    for (family, command), pts in sorted(series.items()):
        timed = [(n, t) for n, t in pts if t >= MIN_SECONDS]
        big_n, big_t = max(pts)
        if len(timed) < 2:
            print(f"{family:22} {command:9} {len(timed):6} {big_n:9} {big_t:8.3f} {'(fast)':>8}")
            continue
        k = slope(timed)
        print(f"{family:22} {command:9} {len(timed):6} {big_n:9} {big_t:8.3f} {k:8.2f}")
        if k > limit:
            over.append(f"{family} {command}: time grows as N^{k:.2f} (limit N^{limit})")
    for line in failed + over:
        print(f"FAIL: {line}", file=sys.stderr)
    if failed or over:
        print(f"FAIL: {len(failed) + len(over)} scaling check(s) failed", file=sys.stderr)
        return 1
    print(f"ok: every fitted exponent is at most {limit}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
