/* The BLAS calls of a CHOLMOD built from source, made to the BLAS this module links. CHOLMOD is
 * compiled with BLAS64_SUFFIX=bdi (it calls dgemmbdi_, ...); these hidden functions forward each to
 * the routine of the module's own dependencies. By its plain name a call would bind to the first
 * definition in the process, e.g. the reference BLAS Debian's Blender links (docs/PLATFORMS.md).
 * Every argument of a Fortran BLAS routine is a pointer: each is forwarded by its pointer count. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "linalg/blas_forward.h"

typedef void *P;

/* The routines CHOLMOD calls: real and complex, single and double (nm -u of its objects). */
#define ROUTINES(X)                                                                          \
  X(sgemm, 13) X(dgemm, 13) X(cgemm, 13) X(zgemm, 13) X(sgemv, 11) X(dgemv, 11) X(cgemv, 11) \
  X(zgemv, 11) X(strsm, 11) X(dtrsm, 11) X(ctrsm, 11) X(ztrsm, 11) X(strsv, 8) X(dtrsv, 8)   \
  X(ctrsv, 8) X(ztrsv, 8) X(ssyrk, 10) X(dsyrk, 10) X(cherk, 10) X(zherk, 10) X(spotrf, 5)   \
  X(dpotrf, 5) X(cpotrf, 5) X(zpotrf, 5)

enum {
#define INDEX(name, n) I_##name,
  ROUTINES(INDEX)
#undef INDEX
  ROUTINE_COUNT
};
static const char *const names[ROUTINE_COUNT] = {
#define NAME(name, n) #name "_",
    ROUTINES(NAME)
#undef NAME
};
static void *routines[ROUTINE_COUNT];
static pthread_once_t resolved = PTHREAD_ONCE_INIT;

/* dlsym with the module's own handle searches the module and then its dependencies (its local
 * scope), never the rest of the process; a program linked with this code (the tests) is searched
 * through the global scope, which starts with its own dependencies. */
static void resolve(void) {
  Dl_info self;
  void *handle = NULL;
  if (dladdr((void *)&resolve, &self) && self.dli_fname) handle = dlopen(self.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
  for (int k = 0; k < ROUTINE_COUNT; ++k) {
    routines[k] = handle ? dlsym(handle, names[k]) : NULL;
    if (!routines[k]) routines[k] = dlsym(RTLD_DEFAULT, names[k]);
  }
}

void *bdinterp_blas_routine(const char *name) {
  pthread_once(&resolved, resolve);
  for (int k = 0; k < ROUTINE_COUNT; ++k)
    if (!strcmp(names[k], name)) return routines[k];
  return NULL;
}

static void *routine(int k) {
  pthread_once(&resolved, resolve);
  if (!routines[k]) {  /* the module was linked with this BLAS: it cannot be missing */
    fprintf(stderr, "bdinterp: the BLAS routine %s is missing from the module's libraries\n", names[k]);
    abort();
  }
  return routines[k];
}

#define ARGS5 P a, P b, P c, P d, P e
#define PASS5 a, b, c, d, e
#define ARGS8 ARGS5, P f, P g, P h
#define PASS8 PASS5, f, g, h
#define ARGS10 ARGS8, P i, P j
#define PASS10 PASS8, i, j
#define ARGS11 ARGS10, P l
#define PASS11 PASS10, l
#define ARGS13 ARGS11, P m, P n
#define PASS13 PASS11, m, n
#define FORWARD(name, n)                                      \
  void name##bdi_(ARGS##n) {                                  \
    ((void (*)(ARGS##n))routine(I_##name))(PASS##n);          \
  }
ROUTINES(FORWARD)
