// The thread controls of the libraries CHOLMOD calls: the OpenMP runtime (Debian's libcholmod links
// libgomp) and the BLAS of its supernodal factorisations (OpenBLAS). bdinterp needs neither itself,
// so they are looked up at run time, in the library each call of CHOLMOD's really binds to.
#ifdef _WIN32
#include "parallel/windows.h"
// After windows.h: psapi.h needs its types.
#include <psapi.h>
#else
#include <dlfcn.h>
#endif

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include "parallel/parallel.h"
#ifdef BDINTERP_FORWARDED_BLAS
#include "linalg/blas_forward.h"
#endif

namespace bdinterp::parallel {
namespace {

// The library that this code's (and so CHOLMOD's) references to `symbol` bind to, or nullptr.
// dlsym(RTLD_DEFAULT) from here searches the global scope and then this object's own dependencies:
// the order the loader resolved CHOLMOD's references in, so the shipped modules' privately named
// copies (libgomp-bdi.so.1, scripts/bundle_libs.py) are found too, which a lookup by soname missed.
struct Library {
  void* handle = nullptr;
  std::string file;
};
#ifdef _WIN32
// Windows has no global symbol scope: the first module of the process (in load order) that exports
// `symbol`. A CHOLMOD linked statically (make test-windows) calls no DLL for it: nothing is found.
Library library_of(const char* symbol) {
  std::vector<HMODULE> modules(256);
  DWORD bytes = 0;
  if (!EnumProcessModules(GetCurrentProcess(), modules.data(), static_cast<DWORD>(modules.size() * sizeof(HMODULE)), &bytes))
    return {};
  modules.resize(std::min<size_t>(modules.size(), bytes / sizeof(HMODULE)));
  for (HMODULE m : modules) {
    char file[MAX_PATH];
    if (GetProcAddress(m, symbol) && GetModuleFileNameA(m, file, MAX_PATH)) return {m, file};
  }
  return {};
}

void* address_in(const Library& lib, const char* name) {
  return reinterpret_cast<void*>(GetProcAddress(static_cast<HMODULE>(lib.handle), name));
}
#else
// The library that holds the function at `f`.
Library library_at(void* f) {
  Dl_info info{};
  if (!f || !dladdr(f, &info) || !info.dli_fname) return {};
  void* h = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);  // already loaded: no new library
  return h ? Library{h, info.dli_fname} : Library{};
}

Library library_of(const char* symbol) {
#ifdef BDINTERP_FORWARDED_BLAS
  // CHOLMOD's BLAS calls go through linalg/blas_forward.c, to the module's own BLAS.
  if (void* f = bdinterp_blas_routine(symbol)) return library_at(f);
#endif
  return library_at(dlsym(RTLD_DEFAULT, symbol));
}

void* address_in(const Library& lib, const char* name) { return dlsym(lib.handle, name); }
#endif

template <class Fn>
Fn symbol_in(const Library& lib, const char* name) {
  return lib.handle ? reinterpret_cast<Fn>(address_in(lib, name)) : nullptr;
}

// A runtime's integer setting: its setter and getter in the library that `called` binds to.
struct Control {
  Library lib;
  void (*set)(int) = nullptr;
  int (*get)() = nullptr;
  Control(const char* called, const char* setter, const char* getter)
      : lib(library_of(called)), set(symbol_in<void (*)(int)>(lib, setter)), get(symbol_in<int (*)()>(lib, getter)) {}
  bool usable() const { return set && get; }
};

// OpenMP: CHOLMOD runs parallel regions of a fixed 4 threads inside supernodal factorisations
// (CHOLMOD_OMP_NUM_THREADS), whatever bdinterp's own threading: on two busy cores those regions wait
// for threads that are not scheduled. OpenMP's dynamic adjustment, set for the calling thread only
// (a per-thread setting), lets libgomp shrink such a team to the idle cores.
const Control& openmp() {
  static const Control c("GOMP_parallel", "omp_set_dynamic", "omp_get_dynamic");
  return c;
}

// OpenBLAS: its number of threads is one process-wide setting.
const Control& openblas() {
  static const Control c("dgemm_", "openblas_set_num_threads", "openblas_get_num_threads");
  return c;
}

// SingleThreadedBlas objects alive in the process, and the thread count before the first.
std::mutex blas_mutex;
int blas_holders = 0;
int blas_saved = 1;

}  // namespace

int detail::swap_omp_dynamic(int value) {
  const Control& omp = openmp();
  if (!omp.usable()) return -1;
  const int old = omp.get();
  omp.set(value);
  return old;
}

Runtimes runtimes() {
  Runtimes r;
  r.blas = openblas().lib.file;
  r.blas_threads = openblas().usable();
  if (openmp().usable()) r.openmp = openmp().lib.file;
  return r;
}

SingleThreadedBlas::SingleThreadedBlas(bool active) : active_(active && openblas().usable()) {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (blas_holders++ > 0) return;
  blas_saved = openblas().get();
  if (blas_saved != 1) openblas().set(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (--blas_holders == 0 && blas_saved != 1) openblas().set(blas_saved);
}

}  // namespace bdinterp::parallel
