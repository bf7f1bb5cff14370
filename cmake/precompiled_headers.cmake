# SPDX-License-Identifier: GPL-2.0-or-later
# Precompiled headers: the big third-party headers (Catch2, GiNaC, Eigen, fmt) parsed once
# per target instead of once per translation unit. Only build time changes: every source
# still includes what it uses, and the flags are the target's own.
#
# CI builds from a clean clone without a compiler cache, twice (scripts/test.sh with g++,
# scripts/sanitize.sh with clang), and header parsing was a large share of those builds
# (docs/robustness.md, "CI time"). What pays differs by compiler (measured there): clang
# loads a precompiled header lazily, so GiNaC, Eigen and fmt precompiled for mbsc_core
# save about a fifth of each GiNaC-heavy source's CPU time; g++ maps its whole image
# (143 MB for those three) into every unit, which costs as much as parsing them, so with
# g++ only the tests' Catch2 header (and the standard headers with it) is precompiled.
#
# A compiler cache (ccache) refuses units that use a precompiled header unless told to
# be sloppy about it, so with a compiler launcher set the default is off: a developer's
# cached rebuilds stay cached.
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(_mbsc_pch_default OFF)
else()
  set(_mbsc_pch_default ON)
endif()
option(MBSC_PCH "precompile the third-party headers (faster clean builds; off with a compiler launcher)"
       ${_mbsc_pch_default})

# mbsc_precompile(<target> [ANY <header>...] [CLANG <header>...]): the target's sources see
# these headers first; ANY with every compiler, CLANG with clang only (see above).
function(mbsc_precompile target)
  cmake_parse_arguments(ARG "" "" "ANY;CLANG" ${ARGN})
  set(headers ${ARG_ANY})
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    list(APPEND headers ${ARG_CLANG})
  endif()
  if(MBSC_PCH AND headers)
    target_precompile_headers(${target} PRIVATE ${headers})
  endif()
endfunction()

# mbsc_precompile_like(<target> <holder>): reuse the holder target's precompiled header
# (built once for many one-file test programs). The holder must have the same compile
# flags and a subset of the target's definitions: clang refuses a header precompiled with
# a macro the unit lacks or defines differently, and -Winvalid-pch -Werror makes g++ do so.
function(mbsc_precompile_like target holder)
  if(MBSC_PCH)
    target_precompile_headers(${target} REUSE_FROM ${holder})
  endif()
endfunction()
