# SPDX-License-Identifier: GPL-2.0-or-later
# `cmake --install`: the mbsc program, the header-only runtime, and the package files
# that let another project use them:
#
#   find_package(mbsc CONFIG REQUIRED)    -> mbsc::mbsc, mbsc::runtime, mbsc_add_model()
#   pkg-config --cflags mbsc-runtime      -> the runtime headers, for other build tools
#
# Every installed file finds the others relative to itself, so the tree may be
# installed under any prefix (cmake --install build --prefix DIR) and moved later.
include(CMakePackageConfigHelpers)

set(MBSC_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/mbsc)

install(TARGETS mbsc EXPORT mbscTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS mbsc_runtime EXPORT mbscTargets)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/include/mbsc/runtime DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mbsc
        FILES_MATCHING PATTERN "*.hpp")
# The FMI functions of exported FMUs (also inside each FMU's sources/), for importers and
# for building an FMU's sources by hand.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/include/mbsc/fmi DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mbsc
        FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp")
install(EXPORT mbscTargets NAMESPACE mbsc:: DESTINATION ${MBSC_CMAKE_DIR})

configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/mbscConfig.cmake.in ${CMAKE_BINARY_DIR}/mbscConfig.cmake
                              INSTALL_DESTINATION ${MBSC_CMAKE_DIR} NO_SET_AND_CHECK_MACRO)
# 0.x: a minor version may change the generated ABI, so only the same major.minor fits.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/mbscConfigVersion.cmake VERSION ${PROJECT_VERSION}
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/mbscConfig.cmake ${CMAKE_BINARY_DIR}/mbscConfigVersion.cmake
              ${CMAKE_SOURCE_DIR}/cmake/mbsc.cmake DESTINATION ${MBSC_CMAKE_DIR})

# pkg-config: header-only, so it goes with the architecture-independent files; the
# include folder is found from the .pc file's own place (${pcfiledir}).
set(MBSC_PC_DIR ${CMAKE_INSTALL_DATADIR}/pkgconfig)
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(MBSC_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  file(RELATIVE_PATH rel "/prefix/${MBSC_PC_DIR}" "/prefix/${CMAKE_INSTALL_INCLUDEDIR}")
  set(MBSC_PC_INCLUDEDIR "\${pcfiledir}/${rel}")
endif()
configure_file(${CMAKE_SOURCE_DIR}/cmake/mbsc-runtime.pc.in ${CMAKE_BINARY_DIR}/mbsc-runtime.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/mbsc-runtime.pc DESTINATION ${MBSC_PC_DIR})
