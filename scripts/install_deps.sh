#!/usr/bin/env bash
# Installs the Debian packages mbsc needs to build and test (root, or sudo available).
# `install_deps.sh sanitize` adds clang with its sanitizer and libFuzzer runtimes.
set -euo pipefail
# python3-numpy: the test of `generate --python` (tests/cli/python_module_test.cpp) runs the module.
pkgs=(g++ cmake make pkg-config libginac-dev libcln-dev libeigen3-dev libfmt-dev libcli11-dev catch2 python3-numpy)
if [ "${1:-}" = sanitize ]; then pkgs+=(clang-14 libclang-rt-14-dev); fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
