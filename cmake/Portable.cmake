# The portable build of the compiled Python module (BDINTERP_PORTABLE=ON; scripts/build-portable.sh
# runs it in Debian 11 for glibc 2.31). libstdc++ and libgcc are linked in statically with their
# symbols hidden (--exclude-libs), so the module needs no newer C++ runtime than the host's.
# CHOLMOD (with AMD, CAMD, COLAMD, CCOLAMD, SuiteSparse_config and its METIS copy) is built from
# source (cmake/CHOLMODFromSource.cmake) and linked in with its symbols hidden: shared, its calls
# went to any other CHOLMOD in the process (Debian's Blender 5.2 loads SuiteSparse 7's), and
# Debian's static archives are not position-independent. What it loads (BLAS/LAPACK, libgfortran,
# libquadmath, libgomp) stays shared: scripts/bundle_libs.py copies those next to the module under
# private names (RUNPATH $ORIGIN), as auditwheel does.

# Links `target` (a MODULE library) with the static C++ runtime.
function(bdinterp_portable_link target)
  target_link_options(${target} PRIVATE -static-libstdc++ -static-libgcc
                      -Wl,--exclude-libs,ALL -Wl,--as-needed -s)
endfunction()
