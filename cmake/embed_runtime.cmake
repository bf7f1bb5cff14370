# Writes OUT: a C++ file defining mbsc::fmu::runtime_files(), the text of every header
# under ROOT/mbsc/runtime and ROOT/mbsc/fmi (what an exported FMU's sources/ carry, so
# that its glue compiles wherever mbsc is installed), and mbsc::fmu::licence_text(), the
# file LICENSE (the FMU's documentation/licenses/).
file(GLOB files ${ROOT}/mbsc/runtime/*.hpp ${ROOT}/mbsc/fmi/*.hpp ${ROOT}/mbsc/fmi/*.h)
list(SORT files)
set(body "// Generated from include/mbsc/runtime and include/mbsc/fmi by cmake/embed_runtime.cmake. Do not edit.\n")
set(body "${body}#include <string>\n#include <utility>\n#include <vector>\nnamespace mbsc::fmu {\n")
set(body "${body}const std::vector<std::pair<std::string, std::string>>& runtime_files() {\n")
set(body "${body}  static const std::vector<std::pair<std::string, std::string>> files = {\n")
foreach(f ${files})
  file(RELATIVE_PATH rel ${ROOT} ${f})
  file(READ ${f} content)
  set(body "${body}    {\"${rel}\", R\"mbsc_rt(${content})mbsc_rt\"},\n")
endforeach()
file(READ ${LICENSE} licence)
set(body "${body}  };\n  return files;\n}\n")
set(body "${body}const std::string& licence_text() {\n  static const std::string text = R\"mbsc_rt(${licence})mbsc_rt\";\n  return text;\n}\n")
set(body "${body}}  // namespace mbsc::fmu\n")
file(WRITE ${OUT}.tmp "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUT}.tmp ${OUT})
