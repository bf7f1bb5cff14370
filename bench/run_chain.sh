#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Planar N-link pendulum chain: mbsc against sympy.physics.mechanics (KanesMethod),
# N = 2 4 8 16 32 64, measured in the same run. The single entry point:
#
#   bash bench/run_chain.sh   (from the repository root; ~8 min on 2 cores)
#
# The SD/FAST figures in docs/benchmarks.md were measured outside this repository
# (see "How the SD/FAST figures were measured" there); no script here builds SD/FAST.
#
# Environment: NS="2 4 8" to run other sizes; STATE=minimal (default: mbsc's state is
# (angles, rates) like sympy's) or STATE=full (all 6N coordinates and speeds); SYMPY_TIMEOUT (default 300 s);
# SYMPY_MAX_N (default 64: larger N skip sympy); MBSC_TIMEOUT (default 900 s, generation);
# MBSC_GEN_FLAGS (extra flags of `mbsc generate`, e.g. "--solver sparse");
# MBSC_BIN: an mbsc binary to measure instead of building one in build-bench/ (before/after
# comparisons); OUT_NAME: the result files' name instead of chain / chain_full.
# CALLGRIND=0 skips the instruction counts.
# Needs g++, cmake, the build dependencies of mbsc, /usr/bin/python3 with sympy
# (Debian python3-sympy), GNU time and valgrind (Debian packages `time` and `valgrind`;
# these three are installed with apt-get when missing and running as root).
#
# Per N and tool: generation wall and CPU time and peak memory, compile time and peak
# memory (g++ -O2), instructions per rhs call (callgrind, the primary and
# load-independent metric), ns per rhs call, and the accuracy the figures were measured
# at: each tool's accelerations against a long-double closed-form reference and against
# mbsc's, at 100 random states (bench/chain_driver.cpp). A difference above ACC_LIMIT
# (default 1e-10) fails the run (exit 1) after the tables are written.
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
OUT=${OUT_NAME:-$OUT}   # OUT_NAME=chain_small: other result files (a partial run keeps the committed ones)
SYMPY_TIMEOUT=${SYMPY_TIMEOUT:-300}
SYMPY_MAX_N=${SYMPY_MAX_N:-64}
MBSC_TIMEOUT=${MBSC_TIMEOUT:-900}
MBSC_GEN_FLAGS=${MBSC_GEN_FLAGS:-}
CALLGRIND=${CALLGRIND:-1}
ACC_LIMIT=${ACC_LIMIT:-1e-10}
PY=/usr/bin/python3
CXXFLAGS_BENCH="-std=c++17 -O2 -march=x86-64"
WORK=bench/work
RES=bench/results
BUILD=build-bench
MBSC=${MBSC_BIN:-$BUILD/mbsc}   # MBSC_BIN=path: measure that binary (before/after a change), nothing built

log() { echo "[run_chain $(date +%T)] $*" >&2; }
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }

# --- tools -----------------------------------------------------------------------------
if [ ! -x /usr/bin/time ]; then
  log "installing GNU time (Debian package 'time')"
  apt-get install -y time >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y time >/dev/null; }
fi
if [ "$CALLGRIND" = 1 ] && ! command -v valgrind >/dev/null; then
  log "installing valgrind (Debian package 'valgrind')"
  apt-get install -y valgrind >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y valgrind >/dev/null; }
fi
if ! $PY -c 'import sympy' 2>/dev/null; then
  log "installing sympy (Debian package 'python3-sympy')"
  apt-get install -y python3-sympy >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y python3-sympy >/dev/null; } || true
fi
$PY -c 'import sympy' 2>/dev/null || { echo "run_chain: $PY has no sympy (apt-get install python3-sympy)" >&2; exit 1; }

if [ -z "${MBSC_BIN:-}" ]; then
  log "building mbsc (Release) in $BUILD"
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
  cmake --build "$BUILD" -j2 --target mbsc >/dev/null
fi

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
  echo "valgrind: $(valgrind --version 2>/dev/null || echo none) (callgrind, instructions of 100 rhs calls after 100 warm-up calls)"
  echo "flags: g++ $CXXFLAGS_BENCH -c (generated code and driver)"
  echo "mbsc state: --state $STATE; extra generate flags: ${MBSC_GEN_FLAGS:-none}"
  echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
} > "$RES/${OUT}_env.txt"
cat "$RES/${OUT}_env.txt" >&2

CSV=$RES/$OUT.csv
# max_rel_diff: against sympy for mbsc, against mbsc for sympy; ref_rel_diff:
# against the long-double reference (bench/chain_driver.cpp).
echo "n,tool,status,gen_s,peak_rss_mib,rhs_ops,count_ops_sympy,compile_s,ns_per_call,ns_min,ns_max,max_rel_diff,derive_s,codegen_s,gen_cpu_s,compile_rss_mib,instr_per_call,ref_rel_diff" > "$CSV"

# timed CMD...: runs it under GNU time; sets t_wall, t_cpu (user + sys) and t_rss_mib.
timed() {
  local f rc=0; f=$(mktemp)
  /usr/bin/time -f '%e %U %S %M' -o "$f" "$@" || rc=$?
  read -r t_wall u s m < <(tail -1 "$f")
  rm -f "$f"
  t_cpu=$(awk -v u="$u" -v s="$s" 'BEGIN { printf "%.3f", u + s }')
  t_rss_mib=$(awk -v m="$m" 'BEGIN { printf "%.1f", m / 1024 }')
  return $rc
}

# instructions DIR TOOL: callgrind's instructions per rhs call of TOOL in DIR/driver.
instructions() {
  [ "$CALLGRIND" = 1 ] || return 0
  local d=$1 t=$2
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$d/callgrind.$t" \
    "$d/driver" count "$t" >"$d/count_$t.txt" 2>"$d/callgrind_$t.log" ||
    { echo "run_chain: callgrind of $t failed, see $d/callgrind_$t.log" >&2; exit 1; }
  local total calls
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$d/callgrind_$t.log")
  calls=$(sed -n 's/^count_calls=//p' "$d/count_$t.txt")
  awk -v a="$total" -v b="$calls" 'BEGIN { if (b > 0 && a > 0) printf "%.0f", a / b }'
}

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
  # shellcheck disable=SC2086
  timed timeout "$MBSC_TIMEOUT" "$MBSC" generate "$dir/$name.mbs" -o "$dir/gen" --state "$STATE" $MBSC_GEN_FLAGS >"$dir/mbsc_gen.log" 2>&1
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
    m_mem=$t_rss_mib
    m_cpu=$t_cpu
    cpp=$dir/gen/$name/$name.cpp
    m_ops=$(sed -n 's|^//   rhs: .* total \([0-9]*\)$|\1|p' "$cpp")
    if [ "$n" -le 16 ]; then  # cross-check the banner with `mbsc print --stats` (it derives again)
      # shellcheck disable=SC2086
      s_ops=$("$MBSC" print "$dir/$name.mbs" --stats --state "$STATE" $MBSC_GEN_FLAGS | awk '$1 == "rhs" { print $NF }')
      [ "$s_ops" = "$m_ops" ] || { echo "run_chain: rhs ops differ: banner $m_ops, --stats $s_ops" >&2; exit 1; }
    fi
    log "N=$n mbsc compile"
    timed g++ $CXXFLAGS_BENCH -c "$cpp" -o "$dir/$name.o"
    m_cc=$t_wall
    m_ccmem=$t_rss_mib
  fi

  # --- sympy: derive + codegen ---
  s_status=""
  if [ -n "$sympy_stop" ]; then
    s_status="not attempted (N=$sympy_stop did not finish)"
  elif [ "$n" -gt "$SYMPY_MAX_N" ]; then
    s_status="not attempted (N > SYMPY_MAX_N=$SYMPY_MAX_N)"
  else
    log "N=$n sympy derive + codegen (timeout $SYMPY_TIMEOUT s)"
    set +e
    timed timeout "$SYMPY_TIMEOUT" $PY bench/sympy_chain.py "$n" "$dir/sympy" >"$dir/sympy.log" 2>&1
    rc=$?
    set -e
    s_cpu=$t_cpu
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
      timed g++ $CXXFLAGS_BENCH -x c++ -c "$dir/sympy/sympy_$name.c" -o "$dir/sympy_$name.o"
      s_cc=$t_wall
      s_ccmem=$t_rss_mib
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
    log "N=$n callgrind (instructions per rhs call)"
    m_ir=$(instructions "$dir" mbsc)
    echo "$n,mbsc,ok,$m_gen,$m_mem,$m_ops,,$m_cc,$m_ns,$(val mbsc_ns_min),$(val mbsc_ns_max),$diff,,,$m_cpu,$m_ccmem,$m_ir,$(val mbsc_ref_diff)" >> "$CSV"
    if [ "$s_status" = ok ]; then
      s_ir=$(instructions "$dir" sympy)
      echo "$n,sympy,ok,$s_gen,$s_mem,$s_ops,$s_raw,$s_cc,$(val sympy_ns),$(val sympy_ns_min),$(val sympy_ns_max),$diff,$s_der,$s_cg,$s_cpu,$s_ccmem,$s_ir,$(val sympy_ref_diff)" >> "$CSV"
    fi
  fi
  # no driver without mbsc's code: no speed, no agreement
  if [ "$s_status" != ok ]; then
    echo "$n,sympy,$s_status,,,,,,,,,,,,,,," >> "$CSV"
  elif [ -z "$mbsc_ok" ]; then
    echo "$n,sympy,ok,$s_gen,$s_mem,$s_ops,$s_raw,$s_cc,,,,,$s_der,$s_cg,$s_cpu,$s_ccmem,," >> "$CSV"
  fi
done
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$RES/${OUT}_env.txt"

# --- tables ----------------------------------------------------------------------------
set +e
$PY - "$CSV" "$RES/$OUT.md" "$ACC_LIMIT" <<'EOF'
# SPDX-License-Identifier: GPL-2.0-or-later
import csv, math, sys

rows = list(csv.DictReader(open(sys.argv[1])))
limit = float(sys.argv[3])
names = {"mbsc": "mbsc", "sympy": "sympy"}


def num(r, k):
    try:
        return float(r[k])
    except (KeyError, TypeError, ValueError):
        return None


def fmt(v, spec):
    return "n/a" if v is None else format(v, spec)


out = []
out.append("| N | tool | generation CPU (s) | peak memory (MiB) | compile (s) | compile memory (MiB) | "
           "instructions / rhs call | ns / rhs call | rel. diff vs reference | rel. diff vs mbsc (mbsc: vs sympy) |")
out.append("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for r in rows:
    tool = names.get(r["tool"], r["tool"])
    if r["status"] != "ok":
        out.append(f"| {r['n']} | {tool} | {r['status']} | | | | | | | |")
        continue
    cpu = num(r, 'gen_cpu_s')
    cpu = "< 0.01" if cpu == 0 else fmt(cpu, '.3g')  # GNU time's resolution
    out.append(f"| {r['n']} | {tool} | {cpu} | {r['peak_rss_mib'] or 'n/a'} | "
               f"{fmt(num(r, 'compile_s'), '.3g')} | {r['compile_rss_mib'] or 'n/a'} | "
               f"{fmt(num(r, 'instr_per_call'), '.0f')} | {fmt(num(r, 'ns_per_call'), '.4g')} | "
               f"{r['ref_rel_diff'] or 'n/a'} | {r['max_rel_diff'] or 'n/a'} |")
out.append("")
out.append("Ratios mbsc / peer (same run; < 1 means mbsc is smaller or faster; instr. = callgrind "
           "instructions per rhs call):")
out.append("")
out.append("| N | instr. / sympy | ns / sympy |")
out.append("|---:|---:|---:|")
by = {(r["n"], r["tool"]): r for r in rows if r["status"] == "ok"}


def ratio(a, b, k):
    x, y = (num(a, k) if a else None), (num(b, k) if b else None)
    return None if x is None or y is None or y == 0 else x / y


for n in dict.fromkeys(r["n"] for r in rows):
    m, s = by.get((n, "mbsc")), by.get((n, "sympy"))
    cells = [ratio(m, s, "instr_per_call"), ratio(m, s, "ns_per_call")]
    out.append(f"| {n} | " + " | ".join(fmt(c, ".3g") for c in cells) + " |")

# growth exponents: least squares of log(y) on log(N) over N >= 16
out.append("")
out.append("Growth exponents (least squares on log-log over N >= 16; the issue's target for the "
           "rhs is <= 1.1):")
out.append("")
out.append("| tool | instructions / rhs call | generation CPU | compile |")
out.append("|---|---:|---:|---:|")


def slope(pts):
    pts = [(math.log(x), math.log(y)) for x, y in pts if y and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else None


for tool in ("mbsc", "sympy"):
    rs = [r for r in rows if r["tool"] == tool and r["status"] == "ok" and int(r["n"]) >= 16]
    if not rs:
        continue
    cells = [slope([(int(r["n"]), num(r, k)) for r in rs]) for k in ("instr_per_call", "gen_cpu_s", "compile_s")]
    out.append(f"| {names[tool]} | " + " | ".join(fmt(c, ".2f") for c in cells) + " |")

bad = []
for r in rows:
    for k in ("ref_rel_diff", "max_rel_diff"):
        v = num(r, k)
        if r["status"] == "ok" and v is not None and not (v <= limit):
            bad.append(f"N={r['n']} {r['tool']} {k}={r[k]}")
out.append("")
out.append(f"Accuracy: every rel. diff above <= {limit:g}: " + ("yes" if not bad else "NO: " + "; ".join(bad)))
text = "\n".join(out) + "\n"
open(sys.argv[2], "w").write(text)
print(text)
sys.exit(3 if bad else 0)
EOF
rc=$?
set -e
log "done: $CSV, $RES/$OUT.md"
if [ $rc -eq 3 ]; then
  echo "run_chain: FAILED: a tool's accelerations differ by more than ACC_LIMIT=$ACC_LIMIT (see the table)" >&2
  exit 1
fi
[ $rc -eq 0 ] || { echo "run_chain: the table script failed (rc $rc)" >&2; exit 1; }
