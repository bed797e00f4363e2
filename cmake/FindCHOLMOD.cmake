# Debian's libsuitesparse-dev (5.x) ships headers in /usr/include/suitesparse and no CMake config.
# Defines SuiteSparse::CHOLMOD (with METIS, libmetis-dev), SuiteSparse::UMFPACK and SuiteSparse::SPQR (the latter two when found).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
find_library(AMD_LIBRARY amd)
find_library(CAMD_LIBRARY camd)
find_library(COLAMD_LIBRARY colamd)
find_library(CCOLAMD_LIBRARY ccolamd)
find_library(UMFPACK_LIBRARY umfpack)
find_library(SPQR_LIBRARY spqr)
find_library(METIS_LIBRARY NAMES metis libmetis.so.5)
find_path(METIS_INCLUDE_DIR metis.h)  # libmetis-dev: the METIS orderings call METIS directly too

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY
  SUITESPARSE_CONFIG_LIBRARY AMD_LIBRARY COLAMD_LIBRARY METIS_LIBRARY METIS_INCLUDE_DIR)

if(CHOLMOD_FOUND AND NOT TARGET SuiteSparse::CHOLMOD)
  add_library(SuiteSparse::CHOLMOD INTERFACE IMPORTED)
  set_target_properties(SuiteSparse::CHOLMOD PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR};${METIS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${CHOLMOD_LIBRARY};${AMD_LIBRARY};${CAMD_LIBRARY};${COLAMD_LIBRARY};${CCOLAMD_LIBRARY};${SUITESPARSE_CONFIG_LIBRARY}")
  if(UMFPACK_LIBRARY)
    add_library(SuiteSparse::UMFPACK INTERFACE IMPORTED)
    set_target_properties(SuiteSparse::UMFPACK PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}" INTERFACE_LINK_LIBRARIES "${UMFPACK_LIBRARY}")
  endif()
  if(SPQR_LIBRARY)
    add_library(SuiteSparse::SPQR INTERFACE IMPORTED)
    set_target_properties(SuiteSparse::SPQR PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}" INTERFACE_LINK_LIBRARIES "${SPQR_LIBRARY}")
  endif()
  set_property(TARGET SuiteSparse::CHOLMOD APPEND PROPERTY INTERFACE_LINK_LIBRARIES "${METIS_LIBRARY}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY AMD_LIBRARY CAMD_LIBRARY
  COLAMD_LIBRARY CCOLAMD_LIBRARY UMFPACK_LIBRARY SPQR_LIBRARY METIS_LIBRARY METIS_INCLUDE_DIR)
