# The portable build of the compiled Python module (BDINTERP_PORTABLE=ON; scripts/build-portable.sh
# runs it in Debian 11 for glibc 2.31). libstdc++ and libgcc are linked in statically with their
# symbols hidden (--exclude-libs), so the module needs no newer C++ runtime than the host's.
# CHOLMOD and what it loads (AMD, CAMD, COLAMD, CCOLAMD, SuiteSparse_config, METIS, BLAS/LAPACK,
# libgfortran, libquadmath, libgomp) are linked shared: Debian's static SuiteSparse archives are not
# position-independent (measured: 6897 absolute relocations in libcholmod.a; ld refuses them in a
# shared object), so scripts/bundle_libs.py copies the shared ones next to the module under
# private names (RUNPATH $ORIGIN), as auditwheel does.

# Links `target` (a MODULE library) with the static C++ runtime.
function(bdinterp_portable_link target)
  target_link_options(${target} PRIVATE -static-libstdc++ -static-libgcc
                      -Wl,--exclude-libs,ALL -Wl,--as-needed -s)
endfunction()
