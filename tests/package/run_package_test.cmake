# SPDX-License-Identifier: GPL-2.0-or-later
# The package test (ctest entry `package`), run as `cmake -P` with
#   MBSC_BUILD_DIR, MBSC_SOURCE_DIR, CONFIG, GENERATOR, CXX, LAUNCHER (may be empty), PKG_CONFIG.
#
#  1. cmake --install the build into a fresh temporary prefix, then move that folder;
#  2. the installed package files name nothing of the build or source tree;
#  3. copy tests/package/app (and a shipped model) to a folder outside the source tree
#     whose path has a space, configure it with nothing but the prefix on
#     CMAKE_PREFIX_PATH (no package registries), build it and run it (the app checks
#     the generated code against textbook equations and an RK4 energy drift);
#  4. change a file the `swing` model includes, rebuild: the generated code and the
#     app's output must follow (generate --depfile and DEPFILE);
#  5. pkg-config: the prefix's mbsc-runtime.pc gives Cflags that compile a program
#     against the installed runtime headers.
# The temporary folder is removed when everything passed, and kept (and named) otherwise.
cmake_minimum_required(VERSION 3.18)

foreach(v MBSC_BUILD_DIR MBSC_SOURCE_DIR GENERATOR CXX PKG_CONFIG)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "run_package_test.cmake: -D${v}=... is required")
  endif()
endforeach()

# A fresh folder under the system's temporary folder.
set(tmp_base /tmp)
if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
  set(tmp_base "$ENV{TMPDIR}")
endif()
string(RANDOM LENGTH 10 ALPHABET 0123456789abcdefghijklmnopqrstuvwxyz suffix)
set(root "${tmp_base}/mbsc-package-test-${suffix}")
set(prefix "${root}/prefix")
set(app "${root}/user project")
set(build "${app}/build")
file(MAKE_DIRECTORY "${root}")

function(fail what)
  message(FATAL_ERROR "package test: ${what}\n(files kept in ${root})")
endfunction()

# Runs a command; fails the test with its output when it fails. OUTPUT_VAR (optional)
# receives stdout.
function(run what)
  cmake_parse_arguments(R "" "OUTPUT_VAR" "COMMAND" ${ARGN})
  execute_process(COMMAND ${R_COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    fail("${what} failed (${rc}):\n${out}\n${err}")
  endif()
  if(R_OUTPUT_VAR)
    set(${R_OUTPUT_VAR} "${out}" PARENT_SCOPE)
  endif()
endfunction()

# Nothing from the environment may point the project at another mbsc.
unset(ENV{CMAKE_PREFIX_PATH})
unset(ENV{mbsc_DIR})
unset(ENV{mbsc_ROOT})
unset(ENV{MBSC_ROOT})
unset(ENV{PKG_CONFIG_PATH})

# 1. Install.
set(config_args "")
if(CONFIG)
  set(config_args --config ${CONFIG})
endif()
run("cmake --install" COMMAND ${CMAKE_COMMAND} --install ${MBSC_BUILD_DIR} --prefix ${root}/installed ${config_args})
# ... and moved: nothing in it may depend on where it was installed.
file(RENAME "${root}/installed" "${prefix}")
foreach(f bin/mbsc include/mbsc/runtime/rk4.hpp include/mbsc/runtime/assemble.hpp
          include/mbsc/runtime/least_squares.hpp include/mbsc/runtime/partition_selector.hpp
          include/mbsc/runtime/simulate.hpp include/mbsc/runtime/projection.hpp include/mbsc/runtime/make_stepper.hpp
          include/mbsc/fmi/fmi2_functions.h include/mbsc/fmi/fmi3_exports.hpp include/mbsc/fmi/fmu_instance.hpp)
  if(NOT EXISTS "${prefix}/${f}")
    fail("the install has no ${f}")
  endif()
endforeach()
file(GLOB_RECURSE config_files "${prefix}/*/cmake/mbsc/*")
file(GLOB_RECURSE pc_files "${prefix}/*/pkgconfig/mbsc-runtime.pc")
if(NOT config_files OR NOT pc_files)
  fail("the install has no lib/cmake/mbsc or no pkgconfig/mbsc-runtime.pc")
endif()

# 2. Relocatable: the package files find everything relative to themselves.
foreach(f IN LISTS config_files pc_files)
  file(READ "${f}" text)
  foreach(tree "${MBSC_BUILD_DIR}" "${MBSC_SOURCE_DIR}" "${root}/installed")
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      fail("${f} names ${tree}: the installed package must depend neither on the build or source tree nor on where it was installed")
    endif()
  endforeach()
endforeach()

# 3. The user's project, outside the source tree.
file(COPY "${MBSC_SOURCE_DIR}/tests/package/app/" DESTINATION "${app}")
file(COPY "${MBSC_SOURCE_DIR}/models/double_pendulum.mbs" DESTINATION "${app}/models")
set(configure_args -S ${app} -B ${build} -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
if(LAUNCHER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
run("configuring the user's project" COMMAND ${CMAKE_COMMAND} ${configure_args})
file(STRINGS "${build}/CMakeCache.txt" found REGEX "^mbsc_DIR:")
get_filename_component(real_prefix "${prefix}" REALPATH)
if(NOT found MATCHES "^mbsc_DIR:PATH=(.*)$")
  fail("the user's project did not record where it found mbsc")
endif()
get_filename_component(found_dir "${CMAKE_MATCH_1}" REALPATH)
string(FIND "${found_dir}" "${real_prefix}/" at)
if(NOT at EQUAL 0)
  fail("find_package(mbsc) found ${found_dir}, not the package in ${prefix}")
endif()
run("building the user's project" COMMAND ${CMAKE_COMMAND} --build ${build} --parallel 2)
run("running the user's app" COMMAND ${build}/pendulum_app OUTPUT_VAR out)
message(STATUS "${out}")
if(NOT out MATCHES "double_pendulum: ok" OR NOT out MATCHES "swing: ok, l = 0.75\n")
  fail("unexpected output of the app:\n${out}")
endif()

# 4. A change in an included file regenerates the model that includes it.
set(generated "${build}/mbsc_generated/swing/swing.hpp")
file(READ "${generated}" before)
file(READ "${app}/models/swing data.mbs" data)
string(REPLACE "l = 0.75" "l = 1.25" data "${data}")
file(WRITE "${app}/models/swing data.mbs" "${data}")
run("rebuilding after the included file changed" COMMAND ${CMAKE_COMMAND} --build ${build} --parallel 2)
file(READ "${generated}" after)
if(after STREQUAL before)
  fail("${generated} did not change when the file its model includes changed")
endif()
run("running the rebuilt app" COMMAND ${build}/pendulum_app OUTPUT_VAR out)
if(NOT out MATCHES "swing: ok, l = 1.25\n")
  fail("the rebuilt app does not use the changed included file:\n${out}")
endif()

# 5. pkg-config, for builds without CMake: only the prefix's own .pc files are seen.
get_filename_component(pc_dir "${pc_files}" DIRECTORY)
set(ENV{PKG_CONFIG_LIBDIR} "${pc_dir}")
run("pkg-config --cflags mbsc-runtime" COMMAND ${PKG_CONFIG} --cflags mbsc-runtime OUTPUT_VAR cflags)
string(STRIP "${cflags}" cflags)
separate_arguments(cflags UNIX_COMMAND "${cflags}")
set(include_dir "")
foreach(flag IN LISTS cflags)
  if(flag MATCHES "^-I(.+)$")
    get_filename_component(include_dir "${CMAKE_MATCH_1}" REALPATH)
  endif()
endforeach()
if(NOT include_dir STREQUAL "${real_prefix}/include")
  fail("pkg-config --cflags mbsc-runtime gives '${cflags}', not the prefix's include folder")
endif()
# A program compiled with those flags alone: RK4 on y' = -y over [0, 1].
file(WRITE "${root}/pc_check.cpp" [=[
#include <cmath>
#include <cstdio>
#include <vector>
#include "mbsc/runtime/rk4.hpp"
int main() {
  std::vector<double> y{1.0};
  auto f = [](double, const double* s, double* d) { d[0] = -s[0]; return 0; };
  mbsc::runtime::rk4_integrate(f, 0.0, 1.0, 100, y, [](double, const std::vector<double>&) {});
  const double err = std::abs(y[0] - std::exp(-1.0));
  std::printf("rk4 error %.1e\n", err);
  return err < 1e-9 ? 0 : 1;
}
]=])
run("compiling with pkg-config's flags" COMMAND ${CXX} -std=c++17 ${cflags} "${root}/pc_check.cpp" -o "${root}/pc_check")
run("running the program built with pkg-config's flags" COMMAND "${root}/pc_check")

file(REMOVE_RECURSE "${root}")
message(STATUS "package test: passed")
