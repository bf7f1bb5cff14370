#!/usr/bin/env bash
# Installs what is missing, builds everything and runs the whole test suite, the long
# tests (label slow) included.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh test
# Tests ON explicitly: a build folder configured by scripts/demo.sh has them off.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=ON -DMBSC_SLOW_TESTS=ON >/dev/null
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure --no-tests=error -j"$(nproc)"
