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
function(mbsc_test_model target)
  cmake_parse_arguments(ARG "" "MODEL;NAME" "" ${ARGN})
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
