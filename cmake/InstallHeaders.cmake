# Installs the public headers of bdinterp: every cpp/include/bdinterp/*.h except the internal ones
# (and nothing under detail/). An internal header that a public one still includes stays installed
# (with a message), so the installed package always compiles; the list shrinks as the includes go.
set(BDINTERP_INTERNAL_HEADERS lobachevsky.h triangle.h parallel.h)

function(bdinterp_install_public_headers dir)
  file(GLOB all RELATIVE ${dir} ${dir}/*.h)
  set(public ${all})
  list(REMOVE_ITEM public ${BDINTERP_INTERNAL_HEADERS})
  set(queue ${public})
  while(queue)  # the closure of the public headers' includes
    list(POP_FRONT queue header)
    file(STRINGS ${dir}/${header} includes REGEX "^#include \"bdinterp/[^/\"]+\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^#include \"bdinterp/([^\"]+)\".*" "\\1" inc "${line}")
      if(NOT inc IN_LIST public)
        message(STATUS "bdinterp: internal header ${inc} installed (included by ${header})")
        list(APPEND public ${inc})
        list(APPEND queue ${inc})
      endif()
    endforeach()
  endwhile()
  list(TRANSFORM public PREPEND ${dir}/)
  install(FILES ${public} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bdinterp)
endfunction()
