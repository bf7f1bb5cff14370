# SPDX-License-Identifier: GPL-2.0-or-later
# mbsc_add_model(<target> MODEL <file.mbs> [NAME name] [STATE full|minimal]
#                [FORMULATION complement|multipliers] [OUTPUTS fn...] [FREEZE name=value...])
#
# Runs the mbsc compiler at build time and adds the generated C++ to <target>.
# Without NAME, the model's name (its `model NAME` statement) must equal the file's
# stem; NAME renames the generated namespace and files (e.g. a frozen variant).
# The generated header is included as "<name>/<name>.hpp".
function(mbsc_add_model target)
  cmake_parse_arguments(ARG "" "MODEL;NAME;STATE;FORMULATION" "OUTPUTS;FREEZE" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbsc_add_model: MODEL is required")
  endif()
  get_filename_component(model_path ${ARG_MODEL} ABSOLUTE)
  get_filename_component(name ${ARG_MODEL} NAME_WE)
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/mbsc_generated)
  # --force: this folder in the build tree is mbsc's by construction (older builds may
  # have written it without the marker); --quiet: no progress line in build logs.
  set(args generate ${model_path} -o ${out_dir} --force --quiet)
  if(ARG_NAME)
    set(name ${ARG_NAME})
    list(APPEND args --name ${name})
  endif()
  if(ARG_STATE)
    list(APPEND args --state ${ARG_STATE})
  endif()
  if(ARG_FORMULATION)
    list(APPEND args --formulation ${ARG_FORMULATION})
  endif()
  if(ARG_OUTPUTS)
    string(REPLACE ";" "," outs "${ARG_OUTPUTS}")
    list(APPEND args --outputs ${outs})
  endif()
  foreach(f ${ARG_FREEZE})
    list(APPEND args --freeze ${f})
  endforeach()
  if(TARGET mbsc)
    set(compiler $<TARGET_FILE:mbsc>)
  else()
    find_program(MBSC_EXECUTABLE mbsc REQUIRED)
    set(compiler ${MBSC_EXECUTABLE})
  endif()
  # One generation rule per output folder and name, shared by every target using it
  # (a custom target serialises it, so parallel builds never run it twice).
  string(MD5 key "${out_dir}/${name}")
  set(gen_target mbsc_gen_${name}_${key})
  if(NOT TARGET ${gen_target})
    add_custom_command(
      OUTPUT ${out_dir}/${name}/${name}.cpp ${out_dir}/${name}/${name}.hpp
      COMMAND ${compiler} ${args}
      DEPENDS ${model_path} ${compiler}
      COMMENT "mbsc: generating equations of ${name}"
      VERBATIM)
    add_custom_target(${gen_target} DEPENDS ${out_dir}/${name}/${name}.cpp ${out_dir}/${name}/${name}.hpp)
  endif()
  add_dependencies(${target} ${gen_target})
  set_source_files_properties(${out_dir}/${name}/${name}.cpp PROPERTIES GENERATED TRUE)
  target_sources(${target} PRIVATE ${out_dir}/${name}/${name}.cpp)
  target_include_directories(${target} PRIVATE ${out_dir})
endfunction()
