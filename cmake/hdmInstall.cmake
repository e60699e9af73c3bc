# Install rules and the CMake package (`find_package(hdm)`), included by the top-level
# CMakeLists.txt. `cmake --install build --prefix P` puts:
#   P/include/hdm/...            the public headers (not detail/: no public header includes it)
#   P/lib/libhdm_*.a             the static libraries
#   P/bin/hdm, P/bin/hdm-studio  the programs (when built)
#   P/lib/cmake/hdm/             hdmConfig.cmake, hdmConfigVersion.cmake and one targets file per
#                                component, so that a consumer of hdm::core needs Eigen only.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(HDM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/hdm)

# component: CMake target. Each component is its own export set (hdm-<component>-targets.cmake):
# the config loads only the components asked for and the third-party packages they need.
set(hdm_components core bake analysis repair pipeline reference io render harness bridge hdm)
set(hdm_target_core hdm_core)
set(hdm_target_bake hdm_bake)
set(hdm_target_analysis hdm_analysis)
set(hdm_target_repair hdm_repair)
set(hdm_target_pipeline hdm_pipeline)
set(hdm_target_reference hdm_reference)
set(hdm_target_io hdm_io)
set(hdm_target_render hdm_render)
set(hdm_target_harness hdm_harness)
set(hdm_target_bridge hdm_bridge)
set(hdm_target_hdm hdm)

foreach(component IN LISTS hdm_components)
  set(target ${hdm_target_${component}})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${component})
  install(TARGETS ${target} EXPORT hdm-${component}
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT hdm-${component} NAMESPACE hdm:: FILE hdm-${component}-targets.cmake
          DESTINATION ${HDM_INSTALL_CMAKEDIR})
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/hdm DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h" PATTERN "detail" EXCLUDE)

if(TARGET hdm_cli)
  install(TARGETS hdm_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET hdm_studio)
  install(TARGETS hdm_studio RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})  # `hdm studio` runs it from beside hdm
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/scripts/ DESTINATION ${CMAKE_INSTALL_DATADIR}/hdm/scripts)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hdmConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/cmake/hdmConfig.cmake
                              INSTALL_DESTINATION ${HDM_INSTALL_CMAKEDIR})
# 0.x: a minor release may break the API, so 0.1 accepts 0.1.z only; from 1.0 on, SameMajorVersion.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/hdmConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/hdmConfig.cmake ${PROJECT_BINARY_DIR}/cmake/hdmConfigVersion.cmake
        DESTINATION ${HDM_INSTALL_CMAKEDIR})
