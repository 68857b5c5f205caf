# Install rules and the CMake package (included from the top-level CMakeLists.txt).
#
#   cmake --install build --prefix PREFIX
#
# installs PREFIX/include/quadcage/**, the static module libraries (PREFIX/lib), the quadcage
# executable (PREFIX/bin), the QuadriFlow peer script (PREFIX/share/quadcage) and the package
# PREFIX/lib/cmake/quadcage: quadcageConfig.cmake, quadcageConfigVersion.cmake, the exported targets
# quadcage::{core,subdiv,layout,accel,fit,render,bench} and quadcage::quadcage, the optional
# quadcage::cad in an export set of its own (quadcageCadTargets.cmake, loaded only where OpenCASCADE
# is found, so a consumer of quadcage::quadcage never needs OpenCASCADE), and
# FindOpenSubdivDebian.cmake. Every installed path is relative to PREFIX: the tree can be moved.
include(CMakePackageConfigHelpers)

set(QUADCAGE_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/quadcage"
    CACHE STRING "Where the CMake package of quadcage is installed, relative to the prefix")

install(TARGETS
    quadcage_core quadcage_subdiv quadcage_layout quadcage_accel quadcage_fit quadcage_render
    quadcage_bench quadcage_quadcage
  EXPORT quadcageTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
install(TARGETS quadcage_cad
  EXPORT quadcageCadTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
install(TARGETS quadcage RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/quadcage" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
  FILES_MATCHING PATTERN "*.h")
install(FILES "${PROJECT_SOURCE_DIR}/tools/bench/quadriflow.py" DESTINATION "${CMAKE_INSTALL_DATADIR}/quadcage")

install(EXPORT quadcageTargets NAMESPACE quadcage:: DESTINATION "${QUADCAGE_INSTALL_CMAKEDIR}")
install(EXPORT quadcageCadTargets NAMESPACE quadcage:: DESTINATION "${QUADCAGE_INSTALL_CMAKEDIR}")
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/quadcageConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/quadcageConfig.cmake"
  INSTALL_DESTINATION "${QUADCAGE_INSTALL_CMAKEDIR}")
# 0.x: a minor release may change the API, so 0.1 accepts 0.1.* only.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/quadcageConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMinorVersion)
install(FILES
    "${PROJECT_BINARY_DIR}/quadcageConfig.cmake"
    "${PROJECT_BINARY_DIR}/quadcageConfigVersion.cmake"
    "${PROJECT_SOURCE_DIR}/cmake/FindOpenSubdivDebian.cmake"
    "${PROJECT_SOURCE_DIR}/cmake/CeresGenericBlas.cmake"
  DESTINATION "${QUADCAGE_INSTALL_CMAKEDIR}")
