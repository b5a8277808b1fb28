// The Interpolator, constructed from an Anchor and an options object (both bound as classes).
#include <mutex>

#include "bdinterp/interpolator.h"
#include "bindings.h"

namespace bdinterp::bindings {
namespace {

// InterpolatorOptions plus the thread count, which today's Interpolator takes through set_threads
// (the "core" branch moves it into InterpolatorOptions; then this wrapper goes).
struct Options {
  InterpolatorOptions core;
  int threads = 0;
};

void bind_options(py::module_& m) {
  py::class_<Options>(m, "InterpolatorOptions",
                      "Options of an Interpolator; every field has the library's default.")
      .def(py::init<>())
      .def_property(
          "base", [](const Options& o) { return o.core.base; },
          [](Options& o, int v) { o.core.base = v; }, "the shape the maps start from")
      .def_property(
          "tolerance", [](const Options& o) { return o.core.flatten.tolerance; },
          [](Options& o, double v) { o.core.flatten.tolerance = v; },
          "stop when max |2 pi - angle sum| <= tolerance (radians)")
      .def_property(
          "max_iterations", [](const Options& o) { return o.core.flatten.max_iterations; },
          [](Options& o, int v) { o.core.flatten.max_iterations = v; },
          "Newton steps before SolverError")
      .def_property(
          "reuse_factorization", [](const Options& o) { return o.core.flatten.reuse_factorization; },
          [](Options& o, bool v) { o.core.flatten.reuse_factorization = v; },
          "allow chord steps with an earlier factorisation")
      .def_readwrite("threads", &Options::threads,
                     "workers of frames() and threads of one frame (0 = one per core, 1 = sequential)");
}

// The Interpolator with the per-object lock its C++ class does not have yet: the GIL is released
// first and the lock taken afterwards, so a thread waiting for the lock never holds the GIL and
// cannot deadlock with one that needs it.
struct Guarded {
  std::unique_ptr<Interpolator> impl;
  std::mutex mutex;
  template <typename F>
  auto locked(F&& f) {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex);
    return f(*impl);
  }
};

}  // namespace

void bind_interpolator(py::module_& m) {
  bind_options(m);
  py::class_<Guarded>(m, "Interpolator")
      .def(py::init([](const std::vector<Positions>& shapes, const Faces& faces, const Anchor& anchor,
                       const Options& options) {
             py::gil_scoped_release release;
             auto g = std::make_unique<Guarded>();
             g->impl = std::make_unique<Interpolator>(shapes, faces, anchor, options.core);
             g->impl->set_threads(options.threads);
             return g;
           }),
           py::arg("shapes"), py::arg("faces"), py::arg("anchor") = Anchor::centroid(),
           py::arg("options") = Options{})
      .def("at", [](Guarded& g, double t) { return g.locked([&](Interpolator& I) { return I.at(t); }); },
           py::arg("t"))
      .def("blend",
           [](Guarded& g, const Eigen::VectorXd& w) {
             return g.locked([&](Interpolator& I) { return I.blend(w); });
           },
           py::arg("weights"))
      .def("frames_into",
           [](Guarded& g, const std::vector<double>& ts, Eigen::Ref<Positions> out) {
             g.locked([&](Interpolator& I) { I.frames(ts, out); return 0; });
           },
           py::arg("ts"), py::arg("out").noconvert(),
           "Writes frame j into rows [j n, (j+1) n) of out, a C-contiguous float64 (len(ts) n, 2) array.")
      .def_property_readonly(
          "stats", [](Guarded& g) { return g.locked([](Interpolator& I) { return I.last_stats(); }); },
          "FrameStats of the last at()/blend(), or of all frames of the last frames_into().")
      .def("forget", [](Guarded& g) { g.locked([](Interpolator& I) { I.forget(); return 0; }); },
           "Drops cached solutions and factorisations: the next frame is computed cold.")
      .def("floor_seconds",
           [](Guarded& g, int repeats) {
             return g.locked([&](Interpolator& I) { return I.floor_seconds(repeats); });
           },
           py::arg("repeats") = 5,
           "Median seconds of one Cholesky factorisation + solve of the interior cotan Laplacian.")
      .def_property_readonly("threads", [](const Guarded& g) { return g.impl->threads(); })
      .def_property_readonly("num_vertices", [](const Guarded& g) { return g.impl->num_vertices(); })
      .def_property_readonly("num_shapes", [](const Guarded& g) { return g.impl->num_shapes(); });
}

}  // namespace bdinterp::bindings
