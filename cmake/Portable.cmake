# The portable build of the compiled Python module (BDINTERP_PORTABLE=ON; scripts/build-portable.sh
# runs it in Debian 11 for glibc 2.31). libstdc++ and libgcc are linked in statically with their
# symbols hidden (--exclude-libs), so the module needs no newer C++ runtime than the host's.
# CHOLMOD and what it loads (AMD, CAMD, COLAMD, CCOLAMD, SuiteSparse_config, METIS, BLAS/LAPACK,
# libgfortran, libquadmath, libgomp) are linked shared: Debian's static SuiteSparse archives are not
# position-independent (measured: 6897 absolute relocations in libcholmod.a; ld refuses them in a
# shared object), so scripts/bundle_libs.py copies the shared ones next to the module under
# private names (RUNPATH $ORIGIN), as auditwheel does.
set(CMAKE_DISABLE_FIND_PACKAGE_OpenMP ON)  # bdinterp's own loops: no OpenMP, frames still threaded

# Links `target` (a MODULE library) with the static C++ runtime.
function(bdinterp_portable_link target)
  target_link_options(${target} PRIVATE -static-libstdc++ -static-libgcc
                      -Wl,--exclude-libs,ALL -Wl,--as-needed -s)
endfunction()

# A Python extension module from headers only (no interpreter of that version needed, so one
# Debian 11 chroot builds for 3.11 and 3.13): BDINTERP_PYTHON_INCLUDE_DIR (Python.h),
# BDINTERP_PYBIND11_INCLUDE_DIR (pybind11/pybind11.h), BDINTERP_PYTHON_EXT_SUFFIX
# (e.g. .cpython-313-x86_64-linux-gnu.so).
function(bdinterp_headers_only_module name)
  foreach(var BDINTERP_PYBIND11_INCLUDE_DIR BDINTERP_PYTHON_EXT_SUFFIX)
    if(NOT ${var})
      message(FATAL_ERROR "BDINTERP_PYTHON_INCLUDE_DIR needs ${var} too")
    endif()
  endforeach()
  add_library(${name} MODULE ${ARGN})
  target_include_directories(${name} SYSTEM PRIVATE ${BDINTERP_PYTHON_INCLUDE_DIR}
                             ${BDINTERP_PYBIND11_INCLUDE_DIR})
  # What pybind11_add_module does: hidden visibility, Python's own symbols left to the interpreter.
  set_target_properties(${name} PROPERTIES PREFIX "" SUFFIX ${BDINTERP_PYTHON_EXT_SUFFIX}
                        CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
endfunction()
