#!/usr/bin/env bash
# The sanitizer job: builds mbsc and the whole test suite with clang's AddressSanitizer
# and UndefinedBehaviorSanitizer (plus libFuzzer's coverage instrumentation), runs the
# suite, then fuzzes the model front end for FUZZ_SECONDS (default 60) with the same
# build. Any sanitizer report, test failure or fuzzer finding fails the job.
# Installs what is missing (clang-14 and its runtimes, libclang-rt-14-dev: the compiler
# and the libFuzzer runtime must be of one version). Used by .ci/run; see
# docs/robustness.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh sanitize
BUILD=${BUILD:-build-sanitize}
# lld links the fifty-odd sanitized programs about four times faster than the default
# linker (unit_tests: 2.7 s of CPU instead of 10.4 s); the code is the same.
# -O0: the sanitizers see the most, and clang compiles GiNaC-heavy code twice as fast
# as at -O1. Line tables only, for readable stack traces at little cost.
FLAGS="-O0 -gline-tables-only -fno-omit-frame-pointer -fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all"
CHECKS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:quarantine_size_mb=64
# symbolize=0 while building and testing: the same checks, but a report names its frames
# as binary+offset, and `symbolized` below adds the function, file and line when a step
# fails. Symbolizing is costly even when nothing is wrong: the leak check at the exit of
# every process matches CLN's suppressed allocation (below) frame by frame, which starts
# llvm-symbolizer on the 100 MB binary; that doubled the time of each short mbsc run
# (the model generations of the build, the hundreds of runs of the `cli`, `robustness`
# and `run_command` entries).
export ASAN_OPTIONS=$CHECKS:symbolize=0
# CLN allocates a small table once and never frees it: that library's one-time
# allocation is suppressed, nothing else (tests/lsan.supp).
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The heaviest numeric checks at their small scale (tests/unit/test_scale.hpp): the
# sparse elimination against 32-digit references at one probe point instead of two and
# random trees up to 20 bodies instead of 40, the same code paths; the Release run of
# the test command runs the full sizes.
export MBSC_TEST_SCALE=small
CC=clang-14 CXX=clang++-14 cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Sanitize -DMBSC_BUILD_TESTS=ON -DMBSC_SLOW_TESTS=ON -DMBSC_BUILD_APPS=OFF -DMBSC_MPI=OFF -DMBSC_PRINT_TESTS=OFF \
  -DMBSC_FUZZ=ON -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined -fuse-ld=lld" >/dev/null
# symbolized LOG COMMAND...: runs COMMAND, its output also kept in LOG; when it fails,
# prints the sanitizer reports of LOG again with function, file and line.
symbolized() {
  local log=$1 status=0
  shift
  "$@" 2>&1 | tee "$log" || status=$?
  if [ "$status" -ne 0 ]; then
    echo "sanitize.sh: the output above again, its stack frames symbolized:"
    LLVM_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer asan_symbolize-14 -d < "$log" || true
    exit "$status"
  fi
}
# The build precompiles the big headers (cmake/precompiled_headers.cmake: no compiler
# launcher here), and the ctest run below starts its entries in the order of their ASan
# seconds (mbsc_sanitize_cost in tests/CMakeLists.txt); docs/robustness.md, "CI time".
symbolized "$BUILD/build.log" cmake --build "$BUILD" -j"$(nproc)"
# Not built here: the example apps and the printer's program (MBSC_PRINT_TESTS=OFF), whose
# only entry, `print`, is left to the Release run as below.
# Left to the Release run of the test command (keeps this job inside CI's half hour):
# the LaTeX entry (over three minutes in pdflatex under ASan, the same print code as the
# `cli` entry's print commands), the printer's entry (every shipped model printed and read
# back, 76 s under ASan), the 1000-period pendulum (the same generated code and
# integrator as pendulum_periods_test, which runs here) and the 40-window rank-loss chain
# (over five minutes under ASan; the same rank-loss code as rank_loss_test, which runs here),
# the bicycle linearized with v and g symbolic (minutes of GiNaC elimination under ASan;
# the same symbolic code as the pendulum and parallelogram cases of `linearize`, which run
# here) and the tadpole tricycle's sweep (its model compiled in over a minute in Release;
# the same linearize and eig code as the `linearize` entry's bicycle, which runs here; its
# finite-difference entry, linear_tricycle_test, is not even built here), front_end_scale
# (big models inside a time budget: a check of how the front end's time grows, which the
# sanitizers' overhead blurs, 170 s under ASan; the same front-end code runs here on every
# model of the `cli` and `robustness` entries), and the determinism entries (the same
# commands in ten processes each, 90 s of one core in Release: GiNaC's run-dependent
# order is the same under the sanitizers, and the commands themselves run here in `cli`,
# `golden` and `linearize`), and run_shipped (every shipped model generated, compiled and
# simulated by `mbsc run`: its time is g++ building and running the generated code, which
# the sanitizers do not instrument; the same models' generation runs here in `golden`,
# and `mbsc run` itself in `run_command`), and urdf_robots (four real robots imported and
# checked: TALOS's check derives every function of a 50-joint humanoid, 20 s in Release and
# minutes at -O0 under ASan; the import code runs here on the small URDFs of the `cli` entry
# and in the URDF fuzz target), and tutorial (docs/tutorial.md's commands as written: its
# time is g++ compiling the tutorial's models and app, which the sanitizers do not
# instrument; the same commands run here in `run_command`, `linearize` and `cli`).
symbolized "$BUILD/ctest.log" ctest --test-dir "$BUILD" --output-on-failure --no-tests=error -j"$(nproc)" \
  -E '^(latex|print|pendulum_1000_periods_test|rank_loss_chain40_test|linearize_symbolic_bicycle|linearize_tricycle|front_end_scale|determinism|determinism_tricycle|run_shipped|urdf_robots|tutorial)$'
# The fuzzer symbolizes as it goes (its reports are rare and come with the input).
ASAN_OPTIONS=$CHECKS FUZZ_SECONDS=${FUZZ_SECONDS:-60} BUILD="$BUILD" bash scripts/fuzz.sh
