#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Scaling check of mbsc on the planar N-link pendulum chain (bench/chain_model.py):
# for each N it generates the model, compiles it (g++ -O2), counts the instructions of
# one rhs call with callgrind (bench/chain_driver.cpp, `count mbsc`: 100 calls at 100
# random states after 100 warm-up calls) and measures the CPU time of `mbsc generate`.
# It then fits the growth exponents (least squares of log y on log N) and FAILS (exit 1)
# when
#   rhs instructions per call grow faster than N^RHS_MAX   (default 1.1), or
#   generation CPU time grows faster than N^GEN_MAX        (default 1.3).
# Not a ctest entry: a few minutes on 2 cores (valgrind and g++; the default file of
# N = 128, every function with mass_matrix formed from its factors, compiles in about
# 14 s of CPU; it took 183 s with the symbolic mass_matrix, `--mass-matrix symbolic`).
#
#   bash bench/check_scaling.sh                          (from the repository root)
#   MBSC_GEN_FLAGS="--solver sparse" bash bench/check_scaling.sh
#
# Environment: NS (default "16 32 64 128"); MBSC_GEN_FLAGS (extra flags of
# `mbsc generate`, e.g. "--solver sparse"); STATE (default minimal); MBSC (an mbsc
# binary; default: build one in build-bench/ like bench/run_chain.sh); RHS_MAX, GEN_MAX.
# Needs g++, cmake, /usr/bin/python3, GNU time and valgrind (installed with apt-get when
# missing and running as root). Scratch files: bench/work/scaling/ (ignored); the table
# is printed and written to bench/work/scaling/scaling.txt.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
NS=${NS:-"16 32 64 128"}
STATE=${STATE:-minimal}
MBSC_GEN_FLAGS=${MBSC_GEN_FLAGS:-}
RHS_MAX=${RHS_MAX:-1.1}
GEN_MAX=${GEN_MAX:-1.3}
PY=/usr/bin/python3
CXXFLAGS_BENCH="-std=c++17 -O2 -march=x86-64"
WORK=bench/work/scaling

log() { echo "[check_scaling $(date +%T)] $*" >&2; }

for pkg in time valgrind; do
  bin=/usr/bin/$pkg
  if [ ! -x "$bin" ]; then
    log "installing $pkg (Debian package '$pkg')"
    apt-get install -y "$pkg" >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y "$pkg" >/dev/null; }
  fi
done

if [ -z "${MBSC:-}" ]; then
  log "building mbsc (Release) in build-bench"
  cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
  cmake --build build-bench -j2 --target mbsc >/dev/null
  MBSC=build-bench/mbsc
fi
[ -x "$MBSC" ] || { echo "check_scaling: no mbsc binary at $MBSC" >&2; exit 1; }

rm -rf "$WORK"
mkdir -p "$WORK"
DATA=$WORK/data.txt   # N gen_cpu_s instr_per_call compile_s
: > "$DATA"

for n in $NS; do
  name=chain$n
  dir=$WORK/$n
  mkdir -p "$dir"
  $PY bench/chain_model.py "$n" "$dir/$name.mbs"
  log "N=$n generate ${MBSC_GEN_FLAGS:+($MBSC_GEN_FLAGS)}"
  # shellcheck disable=SC2086
  /usr/bin/time -f '%U %S' -o "$dir/gen_time.txt" "$MBSC" generate "$dir/$name.mbs" -o "$dir/gen" --state "$STATE" \
    $MBSC_GEN_FLAGS >"$dir/gen.log" 2>&1 || { echo "check_scaling: mbsc generate failed at N=$n, see $dir/gen.log" >&2; exit 1; }
  gen_cpu=$(tail -1 "$dir/gen_time.txt" | awk '{ printf "%.3f", $1 + $2 }')
  log "N=$n compile"
  /usr/bin/time -f '%e' -o "$dir/cc_time.txt" g++ $CXXFLAGS_BENCH -c "$dir/gen/$name/$name.cpp" -o "$dir/$name.o"
  cc=$(tail -1 "$dir/cc_time.txt")
  g++ $CXXFLAGS_BENCH -DCHAIN_N="$n" -DMBSC_HEADER="\"$name.hpp\"" -DNO_SYMPY -I "$dir/gen/$name" \
    bench/chain_driver.cpp "$dir/$name.o" -o "$dir/driver"
  log "N=$n callgrind"
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$dir/callgrind.out" \
    "$dir/driver" count mbsc >"$dir/count.txt" 2>"$dir/callgrind.log" ||
    { echo "check_scaling: callgrind failed at N=$n, see $dir/callgrind.log" >&2; exit 1; }
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$dir/callgrind.log")
  calls=$(sed -n 's/^count_calls=//p' "$dir/count.txt")
  ir=$(awk -v a="$total" -v b="$calls" 'BEGIN { printf "%.0f", a / b }')
  echo "$n $gen_cpu $ir $cc" >> "$DATA"
  log "N=$n: generation CPU $gen_cpu s, $ir instructions per rhs call, compile $cc s"
done

# Fit and verdict.
$PY - "$DATA" "$RHS_MAX" "$GEN_MAX" "$MBSC_GEN_FLAGS" "$WORK/scaling.txt" <<'EOF'
# SPDX-License-Identifier: GPL-2.0-or-later
import math, sys

rows = [line.split() for line in open(sys.argv[1]) if line.strip()]
rhs_max, gen_max, flags, out_path = float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]


def slope(xs, ys):
    """Least-squares slope of log y on log x (the growth exponent)."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(max(y, 1e-3)) for y in ys]  # GNU time's 10 ms resolution: never log(0)
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    sxx = sum((x - mx) ** 2 for x in lx)
    return sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / sxx


ns = [int(r[0]) for r in rows]
out = [f"mbsc generate flags: {flags or 'none'}", "", "| N | generation CPU (s) | instructions / rhs call | compile (s) |",
       "|---:|---:|---:|---:|"]
out += [f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} |" for r in rows]
if len(rows) < 2:
    print("\n".join(out) + "\ncheck_scaling: need at least two N to fit an exponent", file=sys.stderr)
    sys.exit(1)
e_rhs = slope(ns, [float(r[2]) for r in rows])
e_gen = slope(ns, [float(r[1]) for r in rows])
e_cc = slope(ns, [float(r[3]) for r in rows])
out.append("")
out.append(f"growth exponent of rhs instructions per call: {e_rhs:.2f} (target <= {rhs_max:g})")
out.append(f"growth exponent of generation CPU time:       {e_gen:.2f} (target <= {gen_max:g})")
out.append(f"growth exponent of compile time:              {e_cc:.2f} (not checked)")
fails = []
if e_rhs > rhs_max:
    fails.append(f"rhs instructions grow as N^{e_rhs:.2f} > N^{rhs_max:g}")
if e_gen > gen_max:
    fails.append(f"generation CPU time grows as N^{e_gen:.2f} > N^{gen_max:g}")
out.append("")
out.append("PASS" if not fails else "FAIL: " + "; ".join(fails))
text = "\n".join(out) + "\n"
open(out_path, "w").write(text)
print(text)
if fails:
    print("#" * 78 + "\ncheck_scaling: FAILED: " + "; ".join(fails) + "\n" + "#" * 78, file=sys.stderr)
    sys.exit(1)
EOF
