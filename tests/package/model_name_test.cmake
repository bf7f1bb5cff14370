# SPDX-License-Identifier: GPL-2.0-or-later
# ctest entry `package_model_name` (cmake -P, -DMBSC_SOURCE_DIR=...): how mbsc_add_model
# reads a model's name at configure time (cmake/mbsc.cmake, _mbsc_model_name), on files
# written here, against the names mbsc itself reads (docs/language_syntax.md).
cmake_minimum_required(VERSION 3.18)
include(${MBSC_SOURCE_DIR}/cmake/mbsc.cmake)

string(RANDOM LENGTH 10 ALPHABET 0123456789abcdefghijklmnopqrstuvwxyz suffix)
set(dir "/tmp/mbsc-model-name-test-${suffix}")
if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
  set(dir "$ENV{TMPDIR}/mbsc-model-name-test-${suffix}")
endif()
file(MAKE_DIRECTORY "${dir}")
string(ASCII 239 187 191 bom)

set(failures 0)
function(expect file_text want)
  file(WRITE "${dir}/m.mbs" "${file_text}")
  _mbsc_model_name("${dir}/m.mbs" got)
  if(NOT got STREQUAL "${want}")
    message(SEND_ERROR "model name of [[${file_text}]]: got '${got}', expected '${want}'")
  endif()
endfunction()

expect("model swing\n" swing)
expect("# A model of a crane: model trolley is in the comment\n\n   model   gantry_2   # trailing\nparameter m\n"
       gantry_2)
expect("${bom}model with_bom\n" with_bom)
expect("parameter a = 1; model after_semicolon\n" after_semicolon)
expect("\tmodel\ttabbed\r\n" tabbed)
# No `model` statement in the file itself (it comes from an include): "", and
# mbsc_add_model falls back to the file's stem.
expect("include \"header.mbs\"\nparameter modelling = 1\n" "")
expect("parameter remodel = 2\n" "")

file(REMOVE_RECURSE "${dir}")
