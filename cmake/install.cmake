# `cmake --install`: the dba program, the library as the imported target
# dba::dba (dba_core: the modules' static libraries, dba::common, dba::io, ...)
# with its public headers, and the CMake package
# (dbaConfig.cmake, dbaConfigVersion.cmake, dbaTargets.cmake) under
# lib/cmake/dba, so that find_package(dba) + target_link_libraries(x dba::dba)
# builds against an installed dba. The Python module installs itself
# (python/CMakeLists.txt).
include(CMakePackageConfigHelpers)

set(DBA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/dba)

install(TARGETS dba RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
set(DBA_MODULE_TARGETS "")
foreach(m ${DBA_MODULES})
  list(APPEND DBA_MODULE_TARGETS dba_${m})
endforeach()
install(TARGETS dba_core dba_headers ${DBA_MODULE_TARGETS} EXPORT dbaTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# Every header of the library but the test helpers and a module's internal
# ones (*_internal.h), in their directories (include/dba/lm/bundle_adjust.h, ...).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/dba DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h"
  PATTERN "*_internal.h" EXCLUDE
  PATTERN "testing" EXCLUDE)
install(EXPORT dbaTargets NAMESPACE dba:: DESTINATION ${DBA_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/dbaConfig.cmake.in
  ${PROJECT_BINARY_DIR}/dbaConfig.cmake
  INSTALL_DESTINATION ${DBA_INSTALL_CMAKEDIR})
# 0.x: only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dbaConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dbaConfig.cmake ${PROJECT_BINARY_DIR}/dbaConfigVersion.cmake
  DESTINATION ${DBA_INSTALL_CMAKEDIR})
