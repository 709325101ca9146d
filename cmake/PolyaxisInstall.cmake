# `cmake --install`: the CLI and the CAD importer (bin), libpolyaxis.so and the public headers, and
# a CMake package (find_package(polyaxis) -> polyaxis::polyaxis). The Python package installs from
# python/CMakeLists.txt.
include(CMakePackageConfigHelpers)

install(TARGETS polyaxis polyaxis-cad-import RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(NOT TARGET polyaxis_lib)
  return()  # no libpolyaxis without position-independent code: the CLI alone
endif()
install(TARGETS polyaxis_lib EXPORT polyaxisTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/polyaxis DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/machines ${PROJECT_SOURCE_DIR}/examples/processes
        DESTINATION ${CMAKE_INSTALL_DATADIR}/polyaxis)

set(polyaxis_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/polyaxis)
install(EXPORT polyaxisTargets NAMESPACE polyaxis:: DESTINATION ${polyaxis_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/polyaxisConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/polyaxisConfig.cmake INSTALL_DESTINATION ${polyaxis_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/polyaxisConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/polyaxisConfig.cmake ${PROJECT_BINARY_DIR}/polyaxisConfigVersion.cmake
        DESTINATION ${polyaxis_cmake_dir})
