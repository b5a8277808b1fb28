// Internal: the BLAS routines a CHOLMOD built from source calls (blas_forward.c), for the thread
// controls of that BLAS (parallel/runtimes.cpp). Only in builds that define BDINTERP_FORWARDED_BLAS.
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

// The routine `name` (Fortran name, e.g. "dgemm_") that CHOLMOD's calls reach, or NULL.
void *bdinterp_blas_routine(const char *name);

#ifdef __cplusplus
}
#endif
