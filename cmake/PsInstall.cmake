# `cmake --install <build> [--prefix <dir>]`: photoscene as a library, the way OpenCV is used.
#
#   <prefix>/include/photoscene/...                       public headers of every module
#   <prefix>/lib/libps_<module>.a                          one static library per module
#   <prefix>/lib/cmake/photoscene/photosceneConfig.cmake   find_package(photoscene COMPONENTS ...)
#   <prefix>/bin/photoscene                                the command
#   <prefix>/share/photoscene/graphs/*.json                the material-graph library
#   <prefix>/share/photoscene/viewer/                      report.html's bundled three.js viewer
#
# Each module is the imported target photoscene::<module>, with its module dependencies and the
# third-party packages it links (photosceneConfig.cmake finds them with find_dependency). Run-time
# data is found next to the running program (<bin>/../share/photoscene), then in the build's
# source tree, then under the configured CMAKE_INSTALL_PREFIX (ps::findDataFolder in core);
# tests/downstream builds and runs a project against an installed tree.
include(CMakePackageConfigHelpers)

function(ps_install_package)
  set(cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/photoscene)
  get_property(PS_INSTALLED_MODULES GLOBAL PROPERTY PS_MODULES)
  if(TARGET photoscene)
    install(TARGETS photoscene RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT photoscene_bin)
  endif()
  install(EXPORT photosceneTargets NAMESPACE photoscene:: DESTINATION ${cmake_dir}
          FILE photosceneTargets.cmake COMPONENT photoscene_dev)
  configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/photosceneConfig.cmake.in
    ${CMAKE_BINARY_DIR}/cmake/photosceneConfig.cmake INSTALL_DESTINATION ${cmake_dir}
    PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_DATADIR)
  # 0.x: a minor release may change the API
  write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/photosceneConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${CMAKE_BINARY_DIR}/cmake/photosceneConfig.cmake
                ${CMAKE_BINARY_DIR}/cmake/photosceneConfigVersion.cmake
          DESTINATION ${cmake_dir} COMPONENT photoscene_dev)
endfunction()
