# Finds OpenSubdiv's CPU library and headers as Debian 12's libosd-dev ships them.
# Debian's OpenSubdivConfig.cmake names a static libosdCPU.a the package does not ship, so
# find_package(OpenSubdiv) fails there; this module looks for the files instead.
# Defines the imported target quadcage::opensubdiv.
find_path(OpenSubdiv_INCLUDE_DIR opensubdiv/far/topologyRefiner.h)
find_library(OpenSubdiv_CPU_LIBRARY NAMES osdCPU)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdivDebian DEFAULT_MSG OpenSubdiv_CPU_LIBRARY OpenSubdiv_INCLUDE_DIR)
if(OpenSubdivDebian_FOUND AND NOT TARGET quadcage::opensubdiv)
  add_library(quadcage::opensubdiv UNKNOWN IMPORTED)
  set_target_properties(quadcage::opensubdiv PROPERTIES
    IMPORTED_LOCATION "${OpenSubdiv_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenSubdiv_INCLUDE_DIR}")
endif()
mark_as_advanced(OpenSubdiv_INCLUDE_DIR OpenSubdiv_CPU_LIBRARY)
