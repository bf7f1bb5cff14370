#!/usr/bin/env bash
# Sparse outputs (issue 11): size and g++ -O2 compile time of the generated chain of 40
# parallelogram four-bars (81 bodies, 242 constraints), whose Jacobians are 242 x 243
# with 804 entries that are not identically zero. The figures of docs/benchmarks.md,
# "Sparse outputs". Writes bench/results/sparse_outputs.txt.
#   bash bench/run_sparse_outputs.sh                 # this tree's Release build
#   MBSC=/path/to/old/mbsc bash bench/run_sparse_outputs.sh   # another compiler (before/after)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${MBSC:-}" ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)" --target mbsc >/dev/null
  MBSC=./build/mbsc
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out="bench/results/sparse_outputs.txt"
"$MBSC" generate models/parallelogram_chain.mbs --freeze N=40 --name pchain40 -o "$tmp" -q
src="$tmp/pchain40/pchain40.cpp"
# Lines of one function: from `int NAME(` to the closing brace at column 0.
lines_of() { awk -v f="int $1(" 'index($0, f) == 1 {on = 1} on {n++} on && /^}/ {on = 0} END {print n + 0}' "$src"; }
/usr/bin/time -f "%U %M" -o "$tmp/time" g++ -std=c++17 -O2 -c "$src" -o "$tmp/pchain40.o"
t=$(tail -1 "$tmp/time")
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(g++ --version | head -1), mbsc $MBSC"
  echo "pchain40.cpp lines | $(wc -l < "$src")"
  echo "pchain40.cpp bytes | $(wc -c < "$src")"
  echo "constraint_jacobian lines | $(lines_of constraint_jacobian)"
  echo "position_jacobian lines | $(lines_of position_jacobian)"
  echo "g++ -O2 user seconds | ${t% *}"
  echo "g++ -O2 peak resident KiB | ${t#* }"
} | tee "$out"
