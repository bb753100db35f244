# FindCHOLMOD: SuiteSparse's CHOLMOD (Debian libsuitesparse-dev, which ships no CMake config) as the
# imported target CHOLMOD::CHOLMOD, for Eigen's CholmodSupport module.
#   CHOLMOD_INCLUDE_DIR  the directory of cholmod.h (Debian: /usr/include/suitesparse)
#   CHOLMOD_LIBRARY      libcholmod; its own dependencies (AMD, COLAMD, METIS, BLAS, LAPACK) come
#                        with the shared library
# Only the shared library is looked for: the static one would need every dependency named here.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY NAMES cholmod)
find_library(SUITESPARSE_CONFIG_LIBRARY NAMES suitesparseconfig)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY CHOLMOD_INCLUDE_DIR)
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY)

if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SUITESPARSE_CONFIG_LIBRARY}")
endif()
