#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Planar N-link pendulum chain: mbsc against sympy.physics.mechanics (KanesMethod),
# N = 2 4 8 16 32 64, measured in the same run. The single entry point:
#
#   bash bench/run_chain.sh            (from the repository root; ~10 min on 2 cores)
#
# Environment: NS="2 4 8" to run other sizes; STATE=minimal (default: mbsc's state is
# (angles, rates) like sympy's) or STATE=full (all 6N coordinates and speeds); SYMPY_TIMEOUT (default 300 s);
# MBSC_TIMEOUT (default 900 s). Needs g++, cmake, the build dependencies of mbsc,
# /usr/bin/python3 with sympy (Debian python3-sympy) and GNU time (Debian package
# `time`, installed with apt-get when missing and running as root).
#
# Writes bench/results/chain.csv (one row per N and tool), bench/results/chain.md (the
# tables, also printed) and bench/results/chain_env.txt (machine, date, versions), or
# chain_full.* with STATE=full;
# scratch files go to bench/work/ (ignored).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
NS=${NS:-"2 4 8 16 32 64"}
STATE=${STATE:-minimal}
OUT=chain; [ "$STATE" = full ] && OUT=chain_full   # result files: bench/results/$OUT.{csv,md}, ${OUT}_env.txt
SYMPY_TIMEOUT=${SYMPY_TIMEOUT:-300}
MBSC_TIMEOUT=${MBSC_TIMEOUT:-900}
PY=/usr/bin/python3
CXXFLAGS_BENCH="-std=c++17 -O2 -march=x86-64"
WORK=bench/work
RES=bench/results
BUILD=build-bench
MBSC=$BUILD/mbsc

log() { echo "[run_chain $(date +%T)] $*" >&2; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }

# --- tools -----------------------------------------------------------------------------
if [ ! -x /usr/bin/time ]; then
  log "installing GNU time (Debian package 'time')"
  apt-get install -y time >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y time >/dev/null; }
fi
$PY -c 'import sympy' 2>/dev/null || { echo "run_chain: $PY has no sympy (apt-get install python3-sympy)" >&2; exit 1; }

log "building mbsc (Release) in $BUILD"
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
cmake --build "$BUILD" -j2 --target mbsc >/dev/null

rm -rf "$WORK"
mkdir -p "$WORK" "$RES"

# --- environment -----------------------------------------------------------------------
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "nproc: $(nproc)"
  echo "cpu: $(lscpu | grep 'Model name' | sed 's/Model name: *//')"
  echo "memory: $(free -h | awk '/^Mem:/ {print $2}')"
  echo "kernel: $(uname -r)"
  echo "g++: $(g++ --version | head -1)"
  echo "mbsc: $($MBSC --version 2>&1 | head -1), sources hash $(find src include templates cmake CMakeLists.txt -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum | cut -c1-16) (sha256 of the sha256s of src/ include/ templates/ cmake/ CMakeLists.txt when built; others may edit them)"
  echo "sympy: $($PY -c 'import sympy; print(sympy.__version__)') (python $($PY -c 'import platform; print(platform.python_version())'))"
  echo "flags: g++ $CXXFLAGS_BENCH -c (generated code and driver)"
  echo "mbsc state: --state $STATE"
  echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
} > "$RES/${OUT}_env.txt"
cat "$RES/${OUT}_env.txt" >&2

CSV=$RES/$OUT.csv
echo "n,tool,status,gen_s,peak_rss_mib,rhs_ops,count_ops_sympy,compile_s,ns_per_call,ns_min,ns_max,max_rel_diff,derive_s,codegen_s" > "$CSV"

sympy_stop=""   # set to the N that did not finish; larger N are not attempted
for n in $NS; do
  name=chain$n
  dir=$WORK/$n
  mkdir -p "$dir"
  $PY bench/chain_model.py "$n" "$dir/$name.mbs"

  # --- mbsc: generate ---
  log "N=$n mbsc generate"
  t0=$(now)
  set +e
  timeout "$MBSC_TIMEOUT" /usr/bin/time -f '%M' -o "$dir/mbsc_mem.txt" "$MBSC" generate "$dir/$name.mbs" -o "$dir/gen" --state "$STATE" >"$dir/mbsc_gen.log" 2>&1
  rc=$?
  set -e
  t1=$(now)
  if [ $rc -ne 0 ]; then
    log "N=$n mbsc generate failed (rc $rc), see $dir/mbsc_gen.log"
    status="failed rc=$rc"; [ $rc -eq 124 ] && status="did not finish in ${MBSC_TIMEOUT} s"
    echo "$n,mbsc,$status,,,,,,,,,,," >> "$CSV"
    mbsc_ok=""
  else
    mbsc_ok=1
    m_gen=$(elapsed "$t0" "$t1")
    m_mem=$(awk '{ printf "%.1f", $1 / 1024 }' "$dir/mbsc_mem.txt" | tail -1)
    cpp=$dir/gen/$name/$name.cpp
    m_ops=$(sed -n 's|^//   rhs: .* total \([0-9]*\)$|\1|p' "$cpp")
    if [ "$n" -le 16 ]; then  # cross-check the banner with `mbsc print --stats` (it derives again)
      s_ops=$("$MBSC" print "$dir/$name.mbs" --stats --state "$STATE" | awk '$1 == "rhs" { print $NF }')
      [ "$s_ops" = "$m_ops" ] || { echo "run_chain: rhs ops differ: banner $m_ops, --stats $s_ops" >&2; exit 1; }
    fi
    log "N=$n mbsc compile"
    t0=$(now)
    g++ $CXXFLAGS_BENCH -c "$cpp" -o "$dir/$name.o"
    t1=$(now)
    m_cc=$(elapsed "$t0" "$t1")
  fi

  # --- sympy: derive + codegen ---
  s_status=""
  if [ -n "$sympy_stop" ]; then
    s_status="not attempted (N=$sympy_stop did not finish)"
  else
    log "N=$n sympy derive + codegen (timeout $SYMPY_TIMEOUT s)"
    set +e
    timeout "$SYMPY_TIMEOUT" $PY bench/sympy_chain.py "$n" "$dir/sympy" >"$dir/sympy.log" 2>&1
    rc=$?
    set -e
    if [ $rc -eq 124 ]; then
      s_status="did not finish in $((SYMPY_TIMEOUT / 60)) min"
      sympy_stop=$n
    elif [ $rc -ne 0 ]; then
      s_status="failed rc=$rc"
      log "N=$n sympy failed, see $dir/sympy.log"
    else
      s_status=ok
      read -r s_der s_cg s_ops_conv s_ops_raw s_mem < <($PY -c '
import json, sys
d = json.load(open(sys.argv[1]))
print(d["derive_s"], d["codegen_s"], d["ops_mbsc_conv"], d["count_ops"], round(d["maxrss_kb"] / 1024, 1))' "$dir/sympy/sympy_$name.json")
      lu=$(awk -v n="$n" 'BEGIN { printf "%d", n * n * n / 6.0 + n * n + 0.5 }')  # the Cholesky solve both use: n^3/6 + n^2 k, k = 1
      s_ops=$((s_ops_conv + lu))
      s_raw=$((s_ops_raw + lu))
      s_gen=$(awk -v a="$s_der" -v b="$s_cg" 'BEGIN { printf "%.3f", a + b }')
      log "N=$n sympy compile"
      t0=$(now)
      g++ $CXXFLAGS_BENCH -x c++ -c "$dir/sympy/sympy_$name.c" -o "$dir/sympy_$name.o"
      t1=$(now)
      s_cc=$(elapsed "$t0" "$t1")
    fi
  fi

  # --- driver: agreement and speed ---
  diff="" ; m_ns="" ; s_ns=""
  if [ -n "$mbsc_ok" ]; then
    objs="$dir/$name.o"
    defs="-DCHAIN_N=$n -DMBSC_HEADER=\"$name.hpp\""
    if [ "$s_status" = ok ]; then objs="$objs $dir/sympy_$name.o"; else defs="$defs -DNO_SYMPY"; fi
    log "N=$n driver (check at 100 states, then timing)"
    # shellcheck disable=SC2086
    g++ $CXXFLAGS_BENCH $defs -I "$dir/gen/$name" bench/chain_driver.cpp $objs -o "$dir/driver"
    "$dir/driver" > "$dir/driver.txt"
    val() { sed -n "s/^$1=//p" "$dir/driver.txt"; }
    diff=$(val max_rel_diff)
    m_ns=$(val mbsc_ns)
    echo "$n,mbsc,ok,$m_gen,$m_mem,$m_ops,,$m_cc,$m_ns,$(val mbsc_ns_min),$(val mbsc_ns_max),$diff,," >> "$CSV"
    if [ "$s_status" = ok ]; then
      echo "$n,sympy,ok,$s_gen,$s_mem,$s_ops,$s_raw,$s_cc,$(val sympy_ns),$(val sympy_ns_min),$(val sympy_ns_max),$diff,$s_der,$s_cg" >> "$CSV"
    fi
  fi
  if [ "$s_status" != ok ]; then
    echo "$n,sympy,$s_status,,,,,,,,,,," >> "$CSV"
  elif [ -z "$mbsc_ok" ]; then  # no driver without mbsc's code: no speed, no agreement
    echo "$n,sympy,ok,$s_gen,$s_mem,$s_ops,$s_raw,$s_cc,,,,,$s_der,$s_cg" >> "$CSV"
  fi
done
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$RES/${OUT}_env.txt"

# --- tables ----------------------------------------------------------------------------
$PY - "$CSV" "$RES/$OUT.md" <<'EOF'
# SPDX-License-Identifier: GPL-2.0-or-later
import csv, sys

rows = list(csv.DictReader(open(sys.argv[1])))
out = []
out.append("| N | tool | generation (s) | peak memory (MiB) | rhs ops | compile (s) | ns / rhs call | max rel. diff vs other tool |")
out.append("|---:|---|---:|---:|---:|---:|---:|---:|")
for r in rows:
    if r["status"] != "ok":
        out.append(f"| {r['n']} | {r['tool']} | {r['status']} | | | | | |")
        continue
    if not r["ns_per_call"]:
        out.append(f"| {r['n']} | {r['tool']} | {float(r['gen_s']):.3g} | {r['peak_rss_mib']} | {r['rhs_ops']} | "
                   f"{float(r['compile_s']):.3g} | n/a | n/a |")
        continue
    diff = r["max_rel_diff"] or "n/a"
    out.append(f"| {r['n']} | {r['tool']} | {float(r['gen_s']):.3g} | {r['peak_rss_mib']} | {r['rhs_ops']} | "
               f"{float(r['compile_s']):.3g} | {float(r['ns_per_call']):.4g} | {diff} |")
out.append("")
out.append("Ratios mbsc / sympy (same run; < 1 means mbsc is smaller or faster):")
out.append("")
out.append("| N | generation | peak memory | rhs ops | compile | ns / rhs call |")
out.append("|---:|---:|---:|---:|---:|---:|")
by = {(r["n"], r["tool"]): r for r in rows}
for n in dict.fromkeys(r["n"] for r in rows):
    a, b = by.get((n, "mbsc")), by.get((n, "sympy"))
    if not a or not b or not a["ns_per_call"] or not b["ns_per_call"]:
        out.append(f"| {n} | n/a | n/a | n/a | n/a | n/a |")
        continue
    cells = [f"{float(a[k]) / float(b[k]):.3g}" for k in ("gen_s", "peak_rss_mib", "rhs_ops", "compile_s", "ns_per_call")]
    out.append(f"| {n} | " + " | ".join(cells) + " |")
text = "\n".join(out) + "\n"
open(sys.argv[2], "w").write(text)
print(text)
EOF
log "done: $CSV, $RES/$OUT.md"
