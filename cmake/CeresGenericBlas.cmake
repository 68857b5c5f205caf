# Debian 12's Ceres package names its build machine's BLAS in its link interface: ATLAS's
# libf77blas.so and libatlas.so, beside the generic libblas.so/liblapack.so. A program linked with
# them resolves dgemm_/dsyrk_ to ATLAS's generic kernels first, whatever Debian's alternatives
# choose for libblas.so.3, so CHOLMOD's supernodal factorisation (most of the fit's solve) never
# reaches OpenBLAS. Dropping the two keeps the generic libblas/liblapack: the implementation is
# then the one the alternatives select (OpenBLAS once tools/install_deps.sh has run).
# CHOLMOD's own BLAS comes from CMake's FindBLAS, which prefers ATLAS too: set BLA_VENDOR to
# Generic before find_package(Ceres), and include this file after it.
if(TARGET Ceres::ceres)
  get_target_property(_quadcage_ceres_libs Ceres::ceres INTERFACE_LINK_LIBRARIES)
  if(_quadcage_ceres_libs)
    list(FILTER _quadcage_ceres_libs EXCLUDE REGEX "/lib(f77blas|atlas)\\.so$")
    set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${_quadcage_ceres_libs}")
  endif()
  unset(_quadcage_ceres_libs)
endif()
