# MUMPS (double real, MPI build) as Debian ships it: libmumps-dev (PORD and MUMPS's own AMD/AMF/QAMD orderings)
# and, preferred when installed, libmumps-ptscotch-dev (the same MPI build linked with SCOTCH and PT-SCOTCH).
# Debian ships no CMake config for either. Defines MUMPS::DMUMPS (headers, libraries, MPI::MPI_C or MPI::MPI_CXX) and
# MUMPS_WITH_SCOTCH (ON for the ptscotch flavour; compile definition DB_MUMPS_SCOTCH=1 on the target).
# MPI's C library through whichever language the including project enabled (a C++-only consumer of the installed
# package has no C compiler enabled, and FindMPI's C component needs one).
get_property(_mumps_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
if("C" IN_LIST _mumps_languages)
  set(_mumps_mpi_lang C)
else()
  set(_mumps_mpi_lang CXX)
endif()
find_package(MPI QUIET COMPONENTS ${_mumps_mpi_lang})
find_path(MUMPS_INCLUDE_DIR dmumps_c.h)

find_library(MUMPS_DMUMPS_PTSCOTCH dmumps_ptscotch)
find_library(MUMPS_COMMON_PTSCOTCH mumps_common_ptscotch)
find_library(MUMPS_PORD_PTSCOTCH pord_ptscotch)
find_library(MUMPS_DMUMPS_PLAIN dmumps)
find_library(MUMPS_COMMON_PLAIN mumps_common)
find_library(MUMPS_PORD_PLAIN pord)

if(MUMPS_DMUMPS_PTSCOTCH AND MUMPS_COMMON_PTSCOTCH AND MUMPS_PORD_PTSCOTCH)
  set(MUMPS_LIBRARIES ${MUMPS_DMUMPS_PTSCOTCH} ${MUMPS_COMMON_PTSCOTCH} ${MUMPS_PORD_PTSCOTCH})
  set(MUMPS_WITH_SCOTCH ON)
elseif(MUMPS_DMUMPS_PLAIN AND MUMPS_COMMON_PLAIN)
  set(MUMPS_LIBRARIES ${MUMPS_DMUMPS_PLAIN} ${MUMPS_COMMON_PLAIN})
  if(MUMPS_PORD_PLAIN)
    list(APPEND MUMPS_LIBRARIES ${MUMPS_PORD_PLAIN})
  endif()
  set(MUMPS_WITH_SCOTCH OFF)
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(MUMPS REQUIRED_VARS MUMPS_INCLUDE_DIR MUMPS_LIBRARIES MPI_${_mumps_mpi_lang}_FOUND)

if(MUMPS_FOUND AND NOT TARGET MUMPS::DMUMPS)
  add_library(MUMPS::DMUMPS INTERFACE IMPORTED)
  set_target_properties(MUMPS::DMUMPS PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${MUMPS_LIBRARIES};MPI::MPI_${_mumps_mpi_lang}"
    # mpi.h from C++ would pull in the deprecated C++ bindings (and need libmpi_cxx); only the C API is used.
    INTERFACE_COMPILE_DEFINITIONS "OMPI_SKIP_MPICXX=1;MPICH_SKIP_MPICXX=1")
  if(MUMPS_WITH_SCOTCH)
    set_property(TARGET MUMPS::DMUMPS APPEND PROPERTY INTERFACE_COMPILE_DEFINITIONS DB_MUMPS_SCOTCH=1)
  endif()
endif()
mark_as_advanced(MUMPS_INCLUDE_DIR MUMPS_DMUMPS_PTSCOTCH MUMPS_COMMON_PTSCOTCH MUMPS_PORD_PTSCOTCH
  MUMPS_DMUMPS_PLAIN MUMPS_COMMON_PLAIN MUMPS_PORD_PLAIN)
