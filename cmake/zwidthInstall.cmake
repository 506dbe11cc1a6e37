# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

# Use from another project (docs/firmware.md):
#   find_package(zwidth 0.1 CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE zwidth::core)     # double
#   target_link_libraries(app PRIVATE zwidth::core_f)   # float (ZW_REAL_FLOAT comes along)
# or pkg-config zwidth / zwidth_f.  The same names work after add_subdirectory(zwidth).
# The host-only simulation (sim.h) is zwidth::sim / zwidth::sim_f (CMake only).
# Not installed: the shared libraries (Python reference tests only), the host programs.

set_target_properties(zwidth_d PROPERTIES EXPORT_NAME core)
set_target_properties(zwidth_f PROPERTIES EXPORT_NAME core_f)
set_target_properties(zwidth_sim_d PROPERTIES EXPORT_NAME sim)
set_target_properties(zwidth_sim_f PROPERTIES EXPORT_NAME sim_f)
add_library(zwidth::core ALIAS zwidth_d)
add_library(zwidth::core_f ALIAS zwidth_f)
add_library(zwidth::sim ALIAS zwidth_sim_d)
add_library(zwidth::sim_f ALIAS zwidth_sim_f)

if(NOT ZW_INSTALL)
  return()
endif()

include(CMakePackageConfigHelpers)
set(ZW_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/zwidth)

install(TARGETS zwidth_d zwidth_f zwidth_sim_d zwidth_sim_f
  EXPORT zwidthTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/csrc/include/zwidth
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
install(EXPORT zwidthTargets NAMESPACE zwidth:: DESTINATION ${ZW_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/zwidthConfig.cmake.in
  ${PROJECT_BINARY_DIR}/zwidthConfig.cmake INSTALL_DESTINATION ${ZW_CMAKE_DIR})
# 0.x: a minor release may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/zwidthConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/zwidthConfig.cmake ${PROJECT_BINARY_DIR}/zwidthConfigVersion.cmake
  DESTINATION ${ZW_CMAKE_DIR})

# pkg-config: relocatable (prefix found from the .pc file's own directory), so
# cmake --install --prefix and copying the installed tree both work.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(ZW_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH _zw_up "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
  string(REGEX REPLACE "/$" "" _zw_up "${_zw_up}")
  set(ZW_PC_PREFIX "\${pcfiledir}/${_zw_up}")
endif()
foreach(_zw_pc IN ITEMS "zwidth;zwidth_d;;double" "zwidth_f;zwidth_f; -DZW_REAL_FLOAT;float")
  list(GET _zw_pc 0 ZW_PC_NAME)
  list(GET _zw_pc 1 ZW_PC_LIB)
  list(GET _zw_pc 2 ZW_PC_DEFINE)
  list(GET _zw_pc 3 ZW_PC_PRECISION)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/zwidth.pc.in ${PROJECT_BINARY_DIR}/${ZW_PC_NAME}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${ZW_PC_NAME}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()
