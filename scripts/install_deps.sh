#!/usr/bin/env bash
# Installs the Debian packages mbsc needs to build and test (root, or sudo available).
# `install_deps.sh sanitize` adds clang with its sanitizer and libFuzzer runtimes and
# LLVM's linker (lld-14: links the sanitized test programs about four times faster) and
# llvm-symbolizer (llvm-14: file and line in the reports of a failed sanitizer run);
# `install_deps.sh test` adds pdflatex (texlive-latex-base without its recommends: 16
# packages, under a minute), which the test of `print --standalone` compiles with.
set -euo pipefail
# libtinyxml2-dev: the XML reader of `mbsc import` (URDF robots).
# python3-numpy: the test of `generate --python` (tests/cli/python_module_test.cpp) runs the module.
pkgs=(g++ cmake make pkg-config libginac-dev libcln-dev libeigen3-dev libfmt-dev libcli11-dev catch2 python3-numpy libtinyxml2-dev)
# gnuplot-nox: the plots of `mbsc run --plot` and `mbsc bench --plot`.
# libsundials-dev: the integrators bdf, adams, ark-dirk, ark-erk of `mbsc run` (optional at
# configure time). Its hard dependencies bring MPI, PETSc, hypre and Trilinos development
# packages: 135 packages, 68 MB to download, 310 MB installed on top of the build group
# (without recommends; with them 3 more).
# libopenmpi-dev, openmpi-bin: `mbsc sweep` across the ranks of mpirun (optional at configure
# time; libsundials-dev brings the first already).
lean=(gnuplot-nox libsundials-dev libopenmpi-dev openmpi-bin)  # installed without their recommends
if [ "${1:-}" = sanitize ]; then pkgs+=(clang-14 libclang-rt-14-dev lld-14 llvm-14); fi
if [ "${1:-}" = test ]; then lean+=(texlive-latex-base); fi
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=() missing_lean=()
for p in "${pkgs[@]}"; do installed "$p" || missing+=("$p"); done
for p in "${lean[@]}"; do installed "$p" || missing_lean+=("$p"); done
if [ $(( ${#missing[@]} + ${#missing_lean[@]} )) -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "installing: ${missing[*]} ${missing_lean[*]}"
  $SUDO apt-get update -qq
  if [ ${#missing[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
  if [ ${#missing_lean[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing_lean[@]}" >/dev/null
  fi
fi
