#!/usr/bin/env bash
# Installs what is missing, builds the compiler and the example app, then runs the
# main job on shipped models: simulate the Whitworth quick-return mechanism (a closed
# loop) with `mbsc run` and plot it; check the double pendulum, generate its C++,
# print its mass matrix and simulate it with the generated code compiled into an app.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF >/dev/null
cmake --build build -j"$(nproc)" --target mbsc simulate_double_pendulum
mkdir -p build/demo
./build/mbsc run models/whitworth.mbs --t-end 16 -o build/demo/whitworth.csv --plot build/demo/whitworth.svg
./build/mbsc check models/double_pendulum.mbs
./build/mbsc generate models/double_pendulum.mbs -o build/demo
./build/mbsc print models/double_pendulum.mbs --what M
./build/apps/simulate_double_pendulum
