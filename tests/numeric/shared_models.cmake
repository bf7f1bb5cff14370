# SPDX-License-Identifier: GPL-2.0-or-later
# mbsc_test_model(<target> <mbsc_add_model arguments>): mbsc_add_model for the numeric
# tests, with each generated model compiled once however many test programs use it.
#
# mbsc_add_model adds the generated .cpp to the calling target, so a model shared by
# eight tests (four_bar) was compiled eight times: 269 compiles of 157 generated files,
# the Whipple bicycle's 430 KB sources three times each, in the Release build and again
# in the sanitizer build (CI time, scripts/sanitize.sh). Here the model goes into an
# OBJECT library of its own, built with the numeric tests' warnings (-Wall -Wextra
# -Werror) and the build's flags (the sanitizers' included), and each test links it.
# The tests see the same code, compiled the same way: only the copies are gone.
#
# The generated files are named after the model (NAME, or the model's own name), and
# mbsc_add_model already shares one generation rule per name in a folder: two uses of
# a name must therefore mean the same model and options, which is checked here.
#
# The models are compiled without optimization (-O0 after the build's own flags), unless
# OPTIMIZED is given: a generated rhs is straight-line code, and g++'s register allocator
# takes most of an -O2/-O3 compile of it (the tadpole tricycle's 1 MB linear parts: 48 s
# at -O3, 2.4 s at -O0), while the tests call it a few thousand times at most. The
# arithmetic is the same IEEE double arithmetic at every level (x86-64 has no fused
# multiply-add without -march, so nothing is contracted). OPTIMIZED keeps the build's
# flags for a model whose test runs long on it, and for the optimized builds' warnings.
function(mbsc_test_model target)
  cmake_parse_arguments(ARG "OPTIMIZED" "MODEL;NAME" "" ${ARGN})
  list(REMOVE_ITEM ARGN OPTIMIZED)
  get_filename_component(model_path "${ARG_MODEL}" ABSOLUTE)
  if(ARG_NAME)
    set(name ${ARG_NAME})
  else()
    _mbsc_model_name("${model_path}" name)
    if(name STREQUAL "")
      get_filename_component(name "${model_path}" NAME_WE)
    endif()
  endif()
  set(lib mbsc_test_model_${name})
  if(NOT TARGET ${lib})
    add_library(${lib} OBJECT)
    mbsc_add_model(${lib} ${ARGN})
    target_compile_options(${lib} PRIVATE -Wall -Wextra -Werror)
    if(NOT ARG_OPTIMIZED)
      target_compile_options(${lib} PRIVATE -O0)
    endif()
    target_include_directories(${lib} INTERFACE ${CMAKE_CURRENT_BINARY_DIR}/mbsc_generated)
    set_property(GLOBAL PROPERTY mbsc_test_model_args_${name} "${ARGN}")
  else()
    get_property(first GLOBAL PROPERTY mbsc_test_model_args_${name})
    if(NOT first STREQUAL "${ARGN}")
      message(FATAL_ERROR "mbsc_test_model: '${name}' is used with two different sets of options "
                          "(${first} / ${ARGN}): give one of them another NAME")
    endif()
  endif()
  target_link_libraries(${target} PRIVATE ${lib})
endfunction()
