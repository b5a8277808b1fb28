# Finds SuiteSparse's CHOLMOD (Debian: libsuitesparse-dev, which ships no CMake package in 5.x).
# Defines CHOLMOD_FOUND and the imported target CHOLMOD::CHOLMOD.
# With CHOLMOD_STATIC=ON (cmake/Portable.cmake) the target is the static archives of CHOLMOD and of
# everything it calls (AMD, CAMD, COLAMD, CCOLAMD, SuiteSparse_config, METIS, OpenBLAS with LAPACK).
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
if(CHOLMOD_STATIC)
  set(_cholmod_parts cholmod amd camd colamd ccolamd suitesparseconfig metis openblas)
  foreach(part IN LISTS _cholmod_parts)
    find_library(CHOLMOD_${part}_ARCHIVE lib${part}.a PATH_SUFFIXES openblas-pthread)
    list(APPEND _cholmod_archives CHOLMOD_${part}_ARCHIVE)
  endforeach()
  set(CHOLMOD_LIBRARY ${CHOLMOD_cholmod_ARCHIVE})
else()
  find_library(CHOLMOD_LIBRARY cholmod)
endif()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR
                                  ${_cholmod_archives})
if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
  if(CHOLMOD_STATIC)
    set(_deps)
    foreach(var IN LISTS _cholmod_archives)
      if(NOT var STREQUAL CHOLMOD_cholmod_ARCHIVE)
        list(APPEND _deps ${${var}})
      endif()
    endforeach()
    find_package(Threads REQUIRED)
    set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
      INTERFACE_LINK_LIBRARIES "${_deps};Threads::Threads;m;rt")
  endif()
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY)
