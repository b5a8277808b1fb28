# The portable build of the compiled Python module (BDINTERP_PORTABLE=ON; scripts/build-portable.sh
# runs it in Debian 11 for glibc 2.31). The module must load next to Blender's own numpy/OpenBLAS on a
# machine without SuiteSparse: CHOLMOD, METIS, OpenBLAS (its LAPACK), the Fortran runtime, libstdc++
# and libgcc are linked in statically and their symbols hidden (--exclude-libs), so the module's
# NEEDED list is the manylinux set and nothing it carries can interpose on another library.
set(CMAKE_DISABLE_FIND_PACKAGE_OpenMP ON)  # no libgomp to ship; frames still run on threads
set(CHOLMOD_STATIC ON)                     # cmake/FindCHOLMOD.cmake: the .a archives and their deps

# Links `target` (a MODULE library) self-contained.
function(bdinterp_portable_link target)
  foreach(rt libgfortran.a libquadmath.a)
    execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=${rt}
                    OUTPUT_VARIABLE path OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT IS_ABSOLUTE "${path}")
      message(FATAL_ERROR "BDINTERP_PORTABLE: ${rt} not found (Debian: gfortran)")
    endif()
    list(APPEND runtime ${path})
  endforeach()
  target_link_libraries(${target} PRIVATE ${runtime} m)
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
  # What pybind11_add_module does: hidden visibility, no symbol of Python itself linked (the
  # interpreter provides them).
  set_target_properties(${name} PROPERTIES PREFIX "" SUFFIX ${BDINTERP_PYTHON_EXT_SUFFIX}
                        CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${name} PRIVATE -Wl,--unresolved-symbols=ignore-in-object-files)
endfunction()
