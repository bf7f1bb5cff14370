#!/usr/bin/env bash
# Time and memory of check/generate on the big or hostile inputs of the robustness issue
# (docs/robustness.md), with the Release build: the figures in docs/benchmarks.md,
# "Front end: big and hostile inputs". Writes bench/results/front_end.txt. The growth
# with model size (and its fitted exponents) is bench/run_front_end_scaling.sh's.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# 10 000 parameters; N free particles; a 60 000-term sum.
{ echo "model many_parameters"; for i in $(seq 0 9999); do echo "parameter p$i = $i.5"; done
  echo "body b : particle2d { mass p9999 }"; } > "$tmp/params.mbs"
for n in 300 1000; do
  printf 'model free%s\nparameter m = 1, g = 9.81\ngravity (0, -g)\nfor i = 1 to %s { body b[i] : particle2d { mass m } }\n' \
    "$n" "$n" > "$tmp/free$n.mbs"
done
{ printf 'model long_sum\nparameter a = 1'; for i in $(seq 1 59999); do printf '+1'; done
  printf '\nbody b : particle2d { mass a }\n'; } > "$tmp/sum.mbs"
out="bench/results/front_end.txt"
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), commit $(git rev-parse --short HEAD)"
  echo "# case | seconds (wall) | peak resident KiB | exit code"
  run() {  # label, then the mbsc arguments
    local label=$1; shift
    local rc=0
    /usr/bin/time -f "%e %M" -o "$tmp/time" ./build/mbsc "$@" -q >/dev/null 2>&1 || rc=$?
    local t; t=$(tail -1 "$tmp/time")  # after a "Command exited ..." line on failure
    echo "$label | ${t% *} | ${t#* } | $rc"
  }
  run "check 10000 parameters" check "$tmp/params.mbs"
  run "check 60000-term sum" check "$tmp/sum.mbs"
  run "check 300 free particles" check "$tmp/free300.mbs"
  run "check 1000 free particles" check "$tmp/free1000.mbs"
  run "generate 1000 free particles" generate "$tmp/free1000.mbs" -o "$tmp/out"
  run "generate parallelogram chain N=150, --budget 10" generate models/parallelogram_chain.mbs \
    --freeze N=150 --budget 10 -o "$tmp/out2"
  run "check parallelogram chain N=1000, --budget 10 (stops)" check models/parallelogram_chain.mbs \
    --freeze N=1000 --budget 10
} | tee "$out"
