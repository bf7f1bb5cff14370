#!/usr/bin/env bash
# Fuzzes the model front end (lexer, loops, parser, model builder; small models also
# derived and generated) with libFuzzer for FUZZ_SECONDS (default 60) on FUZZ_JOBS
# workers (default 1), from a corpus seeded with every model in models/ and tests/data/;
# then the reader of command-line expressions (--set, --init, --input, --let,
# --prescribe) for FUZZ_OPTION_SECONDS (default a third of FUZZ_SECONDS), from a corpus
# seeded with tests/fuzz/option_seeds.txt, one expression a line; then `mbsc import` of
# URDF files for FUZZ_URDF_SECONDS (default a third of FUZZ_SECONDS), from a corpus seeded
# with tests/data/urdf.
# FUZZ_SEED fixes libFuzzer's random seed (CI does, so that its short run is repeatable).
# Expects the build of scripts/sanitize.sh (BUILD, default build-sanitize); builds it
# when missing. A crash, leak, sanitizer report or timeout fails the run, leaving the
# input that caused it in $BUILD/fuzz-findings/. Long campaigns: docs/robustness.md.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-sanitize}
SECONDS_TO_RUN=${FUZZ_SECONDS:-60}
JOBS=${FUZZ_JOBS:-1}
SEED=${FUZZ_SEED:-0}
OPTION_SECONDS=${FUZZ_OPTION_SECONDS:-$(( ${SECONDS_TO_RUN:-0} / 3 ))}
URDF_SECONDS=${FUZZ_URDF_SECONDS:-$(( ${SECONDS_TO_RUN:-0} / 3 ))}
for v in "$SECONDS_TO_RUN" "$JOBS" "$SEED" "$OPTION_SECONDS" "$URDF_SECONDS"; do
  case "$v" in '' | *[!0-9]*) echo "fuzz.sh: FUZZ_SECONDS, FUZZ_JOBS and FUZZ_SEED must be whole numbers" >&2; exit 2 ;; esac
done
if [ ! -x "$BUILD/tests/fuzz/model_fuzzer" ] || [ ! -x "$BUILD/tests/fuzz/option_fuzzer" ] ||
   [ ! -x "$BUILD/tests/fuzz/urdf_fuzzer" ]; then
  FUZZ_SECONDS=0 BUILD="$BUILD" bash scripts/sanitize.sh
fi
# A small quarantine: ASan's default (256 MiB of freed memory kept aside) lets the
# resident size of a long run creep towards libFuzzer's -rss_limit_mb.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:quarantine_size_mb=64}
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
[ "$SECONDS_TO_RUN" -gt 0 ] || exit 0
root=$PWD
cd "$BUILD"
mkdir -p fuzz-corpus fuzz-findings option-corpus
# Seeds: every model file of the repository (the corpus is kept: it grows from run to run).
find "$root/models" "$root/tests/data" -name '*.mbs' -size -16k -exec cp -n {} fuzz-corpus/ \;
args=(-dict="$root/tests/fuzz/mbs.dict" -max_len=16384 -timeout=20 -rss_limit_mb=4096
      -max_total_time="$SECONDS_TO_RUN" -artifact_prefix=fuzz-findings/ -print_final_stats=1)
# Several workers share the corpus; each logs to fuzz-<n>.log in the build folder.
if [ "$JOBS" -gt 1 ]; then args+=(-jobs="$JOBS" -workers="$JOBS"); fi
if [ "$SEED" -gt 0 ]; then args+=(-seed="$SEED"); fi
./tests/fuzz/model_fuzzer "${args[@]}" fuzz-corpus
[ "$OPTION_SECONDS" -gt 0 ] || exit 0
# The option reader's seeds: one file per line of tests/fuzz/option_seeds.txt.
n=0
while IFS= read -r line; do
  n=$((n + 1))
  printf '%s' "$line" > "option-corpus/seed-$n"
done < "$root/tests/fuzz/option_seeds.txt"
option_args=(-dict="$root/tests/fuzz/mbs.dict" -max_len=4096 -timeout=20 -rss_limit_mb=4096
             -max_total_time="$OPTION_SECONDS" -artifact_prefix=fuzz-findings/option- -print_final_stats=1)
if [ "$JOBS" -gt 1 ]; then option_args+=(-jobs="$JOBS" -workers="$JOBS"); fi
if [ "$SEED" -gt 0 ]; then option_args+=(-seed="$SEED"); fi
./tests/fuzz/option_fuzzer "${option_args[@]}" option-corpus
[ "$URDF_SECONDS" -gt 0 ] || exit 0
mkdir -p urdf-corpus
cp -n "$root"/tests/data/urdf/*.urdf urdf-corpus/
urdf_args=(-dict="$root/tests/fuzz/urdf.dict" -max_len=16384 -timeout=20 -rss_limit_mb=4096
           -max_total_time="$URDF_SECONDS" -artifact_prefix=fuzz-findings/urdf- -print_final_stats=1)
if [ "$JOBS" -gt 1 ]; then urdf_args+=(-jobs="$JOBS" -workers="$JOBS"); fi
if [ "$SEED" -gt 0 ]; then urdf_args+=(-seed="$SEED"); fi
./tests/fuzz/urdf_fuzzer "${urdf_args[@]}" urdf-corpus
