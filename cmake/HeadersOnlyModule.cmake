# A Python extension module from headers only (no interpreter of that version needed, so one
# Debian 11 chroot builds for 3.11, 3.13 and 3.14): BDINTERP_PYTHON_INCLUDE_DIR (Python.h),
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
