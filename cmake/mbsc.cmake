# SPDX-License-Identifier: GPL-2.0-or-later
# mbsc_add_model(<target> MODEL <file.mbs> [NAME name] [STATE full|minimal]
#                [FORMULATION complement|multipliers] [SOLVER auto|dense|sparse]
#                [MASS_MATRIX auto|symbolic|factors] [OUTPUTS fn...] [FREEZE name=value...]
#                [LINEAR_PARTS] [DERIVATIVES])
#
# Runs the mbsc compiler at build time and adds the generated C++ to <target>.
# The generated header is included as "<name>/<name>.hpp", namespace mbsc_gen::<name>.
#
# <name> is NAME when given (it renames the generated namespace and files, e.g. for a
# frozen variant); otherwise the model's own name, read at configure time from the first
# `model NAME` statement of the file (comments skipped), whatever the file is called. A
# file without one (its `model` statement comes from an include) falls back to the
# file's stem. The name is passed on as --name, so the files always match what the build
# expects; CMake re-reads it when the model file changes.
#
# The model is regenerated when it, or any file it includes (at any depth), changes:
# mbsc writes a depfile (generate --depfile) that add_custom_command(DEPFILE) reads
# (CMake 3.20 or later with Makefiles, any version with Ninja). Older CMake with
# Makefiles regenerates on changes of the model file only.
#
# The compiler is, in this order: the target mbsc::mbsc (imported by
# find_package(mbsc), or the alias in mbsc's own build), a target named mbsc, or an
# mbsc program on the PATH (MBSC_EXECUTABLE).

# The depfile holds the paths mbsc was given (absolute here); with NEW, Ninja reads
# them the same way whatever the folder of the calling CMakeLists.txt. The function
# below keeps the policy settings in effect where it is defined.
if(POLICY CMP0116)
  cmake_policy(SET CMP0116 NEW)
endif()

# The model's name as its first `model NAME` statement gives it, or "" when the file
# has none.
function(_mbsc_model_name path out_var)
  file(READ "${path}" text)
  string(ASCII 239 187 191 bom)  # a UTF-8 byte-order mark, which mbsc skips too
  string(FIND "${text}" "${bom}" at)
  if(at EQUAL 0)
    string(SUBSTRING "${text}" 3 -1 text)
  endif()
  string(REGEX REPLACE "#[^\n]*" "" text "${text}")
  if(text MATCHES "(^|[ \t\r\n;{}])model[ \t]+([A-Za-z_][A-Za-z0-9_]*)")
    set(${out_var} "${CMAKE_MATCH_2}" PARENT_SCOPE)
  else()
    set(${out_var} "" PARENT_SCOPE)
  endif()
endfunction()

function(mbsc_add_model target)
  cmake_parse_arguments(ARG "LINEAR_PARTS;DERIVATIVES" "MODEL;NAME;STATE;FORMULATION;SOLVER;MASS_MATRIX" "OUTPUTS;FREEZE;BATCH" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbsc_add_model: MODEL is required")
  endif()
  get_filename_component(model_path "${ARG_MODEL}" ABSOLUTE)
  if(NOT EXISTS "${model_path}")
    message(FATAL_ERROR "mbsc_add_model: model file '${model_path}' does not exist")
  endif()
  if(ARG_NAME)
    set(name ${ARG_NAME})
  else()
    _mbsc_model_name("${model_path}" name)
    if(name STREQUAL "")
      get_filename_component(name "${model_path}" NAME_WE)
    endif()
    # A renamed model renames the generated files: read it again when the file changes.
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${model_path}")
  endif()
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/mbsc_generated)
  set(depfile ${out_dir}/${name}.d)
  # --force: this folder in the build tree is mbsc's by construction (older builds may
  # have written it without the marker); --quiet: nothing in build logs on success (no progress line, no summary).
  set(args generate ${model_path} -o ${out_dir} --name ${name} --force --quiet)
  if(ARG_STATE)
    list(APPEND args --state ${ARG_STATE})
  endif()
  if(ARG_FORMULATION)
    list(APPEND args --formulation ${ARG_FORMULATION})
  endif()
  if(ARG_SOLVER)
    list(APPEND args --solver ${ARG_SOLVER})
  endif()
  if(ARG_MASS_MATRIX)
    list(APPEND args --mass-matrix ${ARG_MASS_MATRIX})
  endif()
  if(ARG_LINEAR_PARTS)
    list(APPEND args --linear-parts)
  endif()
  if(ARG_DERIVATIVES)
    list(APPEND args --derivatives)
  endif()
  if(ARG_OUTPUTS)
    string(REPLACE ";" "," outs "${ARG_OUTPUTS}")
    list(APPEND args --outputs ${outs})
  endif()
  if(ARG_BATCH)  # generate --batch: the functions with batched entry points (docs/batched.md)
    string(REPLACE ";" "," batch "${ARG_BATCH}")
    list(APPEND args --batch ${batch})
  endif()
  foreach(f ${ARG_FREEZE})
    list(APPEND args --freeze ${f})
  endforeach()
  if(TARGET mbsc::mbsc)
    set(compiler $<TARGET_FILE:mbsc::mbsc>)
  elseif(TARGET mbsc)
    set(compiler $<TARGET_FILE:mbsc>)
  else()
    find_program(MBSC_EXECUTABLE mbsc REQUIRED)
    set(compiler ${MBSC_EXECUTABLE})
  endif()
  set(depfile_args "")
  if(CMAKE_GENERATOR MATCHES "Ninja" OR CMAKE_VERSION VERSION_GREATER_EQUAL 3.21 OR
     (CMAKE_VERSION VERSION_GREATER_EQUAL 3.20 AND CMAKE_GENERATOR MATCHES "Makefiles"))
    list(APPEND args --depfile ${depfile})
    set(depfile_args DEPFILE ${depfile})
  endif()
  # One generation rule per output folder and name, shared by every target using it
  # (a custom target serialises it, so parallel builds never run it twice).
  string(MD5 key "${out_dir}/${name}")
  set(gen_target mbsc_gen_${name}_${key})
  if(NOT TARGET ${gen_target})
    # The outputs in the order mbsc names them in the depfile (Ninja wants the first).
    add_custom_command(
      OUTPUT ${out_dir}/${name}/${name}.hpp ${out_dir}/${name}/${name}.cpp
      COMMAND ${compiler} ${args}
      DEPENDS ${model_path} ${compiler}
      ${depfile_args}
      COMMENT "mbsc: generating equations of ${name}"
      VERBATIM)
    add_custom_target(${gen_target} DEPENDS ${out_dir}/${name}/${name}.hpp ${out_dir}/${name}/${name}.cpp)
  endif()
  add_dependencies(${target} ${gen_target})
  set_source_files_properties(${out_dir}/${name}/${name}.cpp PROPERTIES GENERATED TRUE)
  target_sources(${target} PRIVATE ${out_dir}/${name}/${name}.cpp)
  target_include_directories(${target} PRIVATE ${out_dir})
  # The generated code is C++17 (inline constexpr tables).
  target_compile_features(${target} PRIVATE cxx_std_17)
endfunction()
