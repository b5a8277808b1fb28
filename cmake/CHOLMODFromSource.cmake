# CHOLMOD from a SuiteSparse 7 source tree (-DBDINTERP_SUITESPARSE_SOURCE=DIR, e.g. Debian's
# suitesparse_7.10.1+dfsg.orig.tar.xz unpacked): static, position-independent SuiteSparse_config,
# AMD, CAMD, COLAMD, CCOLAMD and CHOLMOD (with the METIS copy CHOLMOD carries under names of its
# own), compiled with the file lists of SuiteSparse's own CMake, which needs CMake 3.22 (Debian 11
# has 3.18). Its symbols are hidden, so a module that links it keeps its calls when the process
# holds another CHOLMOD (Debian's Blender 5.2 loads SuiteSparse 7's through Ceres).
# Supernodal factors need a BLAS and LAPACK: used where found (BDINTERP_CHOLMOD_BLAS=ON), else
# CHOLMOD is simplicial only. OpenMP likewise. Defines CHOLMOD::CHOLMOD as FindCHOLMOD.cmake does.
enable_language(C)
set(_ss "${BDINTERP_SUITESPARSE_SOURCE}")
if(NOT EXISTS "${_ss}/CHOLMOD/Include/cholmod.h" OR NOT EXISTS "${_ss}/SuiteSparse_config/SuiteSparse_config.h")
  message(FATAL_ERROR "BDINTERP_SUITESPARSE_SOURCE=${_ss} is not a SuiteSparse 7 source tree")
endif()
option(BDINTERP_CHOLMOD_BLAS "CHOLMOD from source: supernodal factors with the BLAS found" ON)

set(_parts Check Cholesky Utility MatrixOps Modify Partition)
set(_defs "")
if(BDINTERP_CHOLMOD_BLAS)
  find_package(BLAS)
  find_package(LAPACK)
endif()
if(BDINTERP_CHOLMOD_BLAS AND BLAS_FOUND AND LAPACK_FOUND)
  list(APPEND _parts Supernodal)
  set(BDINTERP_CHOLMOD_SUPERNODAL ON)
else()
  set(BDINTERP_CHOLMOD_SUPERNODAL OFF)
  list(APPEND _defs NSUPERNODAL)
endif()

set(_sources "${_ss}/SuiteSparse_config/SuiteSparse_config.c")
foreach(_lib AMD CAMD COLAMD CCOLAMD)
  file(GLOB _s "${_ss}/${_lib}/Source/*.c")
  list(APPEND _sources ${_s})
endforeach()
set(_private_includes "${_ss}/CHOLMOD" "${_ss}/CHOLMOD/SuiteSparse_metis/GKlib"
    "${_ss}/CHOLMOD/SuiteSparse_metis/libmetis" "${_ss}/CHOLMOD/SuiteSparse_metis/include")
foreach(_part ${_parts})
  file(GLOB _s "${_ss}/CHOLMOD/${_part}/cholmod_*.c")
  list(APPEND _sources ${_s})
  list(APPEND _private_includes "${_ss}/CHOLMOD/${_part}")
endforeach()

add_library(bdinterp_cholmod STATIC ${_sources})
set_target_properties(bdinterp_cholmod PROPERTIES C_STANDARD 11 C_STANDARD_REQUIRED ON
                      POSITION_INDEPENDENT_CODE ON C_VISIBILITY_PRESET hidden)
target_include_directories(bdinterp_cholmod SYSTEM PUBLIC
  "${_ss}/SuiteSparse_config" "${_ss}/CHOLMOD/Include" "${_ss}/AMD/Include" "${_ss}/CAMD/Include"
  "${_ss}/COLAMD/Include" "${_ss}/CCOLAMD/Include")
target_include_directories(bdinterp_cholmod PRIVATE ${_private_includes})
# Upstream builds its sources with their warnings; they are not this project's to fix.
target_compile_options(bdinterp_cholmod PRIVATE -w)
target_compile_definitions(bdinterp_cholmod PRIVATE ${_defs})
find_package(OpenMP COMPONENTS C)
if(OpenMP_C_FOUND)
  target_link_libraries(bdinterp_cholmod PRIVATE OpenMP::OpenMP_C)
endif()
if("Supernodal" IN_LIST _parts AND UNIX AND NOT APPLE)
  # Its BLAS calls renamed (dgemm_ -> dgemmbdi_) and forwarded to the BLAS linked here, looked up
  # in the module's own dependencies (cpp/src/linalg/blas_forward.c): by their plain names they
  # would bind to whatever BLAS the host process loaded first. The BLAS stays a dependency of the
  # module though nothing calls it by name.
  find_package(Threads REQUIRED)
  target_sources(bdinterp_cholmod PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/cpp/src/linalg/blas_forward.c")
  target_include_directories(bdinterp_cholmod PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}/cpp/src")
  target_compile_definitions(bdinterp_cholmod PRIVATE BLAS64_SUFFIX=bdi INTERFACE BDINTERP_FORWARDED_BLAS)
  target_link_libraries(bdinterp_cholmod PRIVATE -Wl,--no-as-needed ${LAPACK_LIBRARIES} ${BLAS_LIBRARIES}
                        -Wl,--as-needed ${CMAKE_DL_LIBS} Threads::Threads)
elseif("Supernodal" IN_LIST _parts)
  target_link_libraries(bdinterp_cholmod PRIVATE ${LAPACK_LIBRARIES} ${BLAS_LIBRARIES})
endif()
if(NOT WIN32)
  target_link_libraries(bdinterp_cholmod PRIVATE m)
endif()
add_library(CHOLMOD::CHOLMOD ALIAS bdinterp_cholmod)
message(STATUS "CHOLMOD from ${_ss}: static, hidden; supernodal: ${BDINTERP_CHOLMOD_SUPERNODAL}, OpenMP: ${OpenMP_C_FOUND}")
