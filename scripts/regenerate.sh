#!/usr/bin/env bash
# Regenerates generated/ from models/ with the freshly built compiler. Review the diff.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc
for m in models/*.mbs; do ./build/mbsc generate "$m" -o generated; done
git status --short generated
