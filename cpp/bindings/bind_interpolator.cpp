#include <optional>

#include "bdinterp/interpolator.h"
#include "bindings.h"

namespace bdinterp::bindings {
namespace {

Anchor make_anchor(int vertex, const std::optional<std::vector<double>>& path_t,
                   const std::optional<Positions>& path_positions,
                   const std::optional<std::vector<double>>& path_angles) {
  if (path_t) {
    if (!path_positions || !path_angles)
      throw InvalidInput("anchor path needs t, positions and angles");
    return Anchor::along(AnchorPath{*path_t, *path_positions, *path_angles}, vertex);
  }
  return vertex >= 0 ? Anchor::at_vertex(vertex) : Anchor::centroid();
}

py::dict stats_dict(const FrameStats& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["residual"] = s.residual;
  d["broken_triangles"] = s.broken_triangles;
  d["max_broken_triangles"] = s.max_broken_triangles;
  d["flatness"] = s.flatness;
  d["pieces"] = s.pieces;
  d["factorizations"] = s.factorizations;
  d["chord_steps"] = s.chord_steps;
  d["seconds"] = s.seconds;
  d["hole_closure"] = s.hole_closure;  // list, one entry per hole
  return d;
}

}  // namespace

void bind_interpolator(py::module_& m) {
  py::class_<Interpolator>(m, "Interpolator")
      .def(py::init([](const std::vector<Positions>& shapes, const Faces& faces, int anchor_vertex,
                       const std::optional<std::vector<double>>& path_t,
                       const std::optional<Positions>& path_positions,
                       const std::optional<std::vector<double>>& path_angles, int base,
                       double tolerance, int max_iterations) {
             InterpolatorOptions opt;
             opt.base = base;
             opt.flatten.tolerance = tolerance;
             opt.flatten.max_iterations = max_iterations;
             const Anchor a = make_anchor(anchor_vertex, path_t, path_positions, path_angles);
             py::gil_scoped_release release;
             return std::make_unique<Interpolator>(shapes, faces, a, opt);
           }),
           py::arg("shapes"), py::arg("faces"), py::arg("anchor_vertex") = -1,
           py::arg("path_t") = py::none(), py::arg("path_positions") = py::none(),
           py::arg("path_angles") = py::none(), py::arg("base") = 0, py::arg("tolerance") = 1e-10,
           py::arg("max_iterations") = 50)
      .def("at", &Interpolator::at, py::arg("t"), py::call_guard<py::gil_scoped_release>())
      .def("blend", &Interpolator::blend, py::arg("weights"),
           py::call_guard<py::gil_scoped_release>())
      .def("frames_into", &Interpolator::frames, py::arg("ts"), py::arg("out").noconvert(),
           py::call_guard<py::gil_scoped_release>(),
           "Writes frame j into rows [j n, (j+1) n) of out, a C-contiguous float64 (len(ts) n, 2) array.")
      .def_property_readonly("stats", [](const Interpolator& I) { return stats_dict(I.last_stats()); })
      .def("folded_faces", &Interpolator::folded_faces, py::arg("shape"),
           "Faces of input `shape` folded (reversed) relative to the base shape.")
      .def("forget", &Interpolator::forget,
           "Drops cached solutions and factorisations: the next frame is computed cold.")
      .def("floor_seconds", &Interpolator::floor_seconds, py::arg("repeats") = 5,
           py::call_guard<py::gil_scoped_release>(),
           "Median seconds of one Cholesky factorisation + solve of the interior cotan Laplacian.")
      .def_property("threads", &Interpolator::threads, &Interpolator::set_threads,
                    "Worker threads of frames_into (0 = all cores, 1 = sequential).")
      .def_property_readonly("num_vertices", &Interpolator::num_vertices)
      .def_property_readonly("num_shapes", &Interpolator::num_shapes);
}

}  // namespace bdinterp::bindings
