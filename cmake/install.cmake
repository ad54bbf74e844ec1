# `cmake --install`: the libraries (kernels embedded, so no source tree is needed at run time),
# their headers and a CMake package: find_package(offsetmap CONFIG) gives offsetmap::offsetmap
# (the pass; OpenCL only) and, when it was built, offsetmap::evaluation (needs OpenImageIO).
include(CMakePackageConfigHelpers)

set(OFFSETMAP_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/offsetmap")
set(OFFSETMAP_INSTALL_TARGETS offsetmap)
if(OFFSETMAP_BUILD_EVALUATION)
    list(APPEND OFFSETMAP_INSTALL_TARGETS offsetmap_reference offsetmap_evaluation)
endif()
install(TARGETS ${OFFSETMAP_INSTALL_TARGETS} EXPORT offsetmapTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Each installed library's own headers, and no others: the core's always (offsetmap/shared.h, the
# structs host and kernels share, among them), the lab's with the lab.
# The renderer is not installed, so neither are its headers.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/core/include/offsetmap"
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(OFFSETMAP_BUILD_EVALUATION)
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/reference/include/offsetmap"
        "${PROJECT_SOURCE_DIR}/evaluation/include/offsetmap" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
install(EXPORT offsetmapTargets NAMESPACE offsetmap:: DESTINATION ${OFFSETMAP_CMAKE_DIR})

set(OFFSETMAP_HAS_EVALUATION ${OFFSETMAP_BUILD_EVALUATION})
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/offsetmapConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/offsetmapConfig.cmake" INSTALL_DESTINATION ${OFFSETMAP_CMAKE_DIR})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/offsetmapConfigVersion.cmake"
    COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/offsetmapConfig.cmake"
    "${PROJECT_BINARY_DIR}/offsetmapConfigVersion.cmake" DESTINATION ${OFFSETMAP_CMAKE_DIR})

# The command-line program with what it finds beside itself (<prefix>/share/offsetmap/).
if(OFFSETMAP_BUILD_CLI)
    install(TARGETS offsetmap_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/data" DESTINATION ${CMAKE_INSTALL_DATADIR}/offsetmap)
    install(FILES "${PROJECT_SOURCE_DIR}/tools/bench/plot_sweep.py"
        "${PROJECT_SOURCE_DIR}/tools/bench/plot_failure.py"
        "${PROJECT_SOURCE_DIR}/tools/bench/plot_temporal.py"
        "${PROJECT_SOURCE_DIR}/tools/bench/plot_bench.py"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/offsetmap/tools/bench)
endif()
