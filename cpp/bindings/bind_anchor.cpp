// Anchor and AnchorPath as classes: Python builds the C++ objects directly (no flattening into
// keyword arguments and rebuilding here).
#include "bdinterp/anchor.h"
#include "bindings.h"

namespace bdinterp::bindings {

void bind_anchor(py::module_& m) {
  py::class_<AnchorPath>(m, "AnchorPath",
                         "Trajectory of the anchor: at time t[k] it is at position[k] (plane "
                         "coordinates) and turned by angle[k] radians relative to the source.")
      .def(py::init([](std::vector<double> t, Positions position, std::vector<double> angle) {
             return AnchorPath{std::move(t), std::move(position), std::move(angle)};
           }),
           py::arg("t"), py::arg("position"), py::arg("angle"))
      .def_readwrite("t", &AnchorPath::t)
      .def_readwrite("position", &AnchorPath::position)
      .def_readwrite("angle", &AnchorPath::angle);

  py::class_<Anchor> anchor(m, "Anchor", "What stays put: the centroid, a vertex, or a path.");
  py::enum_<Anchor::Mode>(anchor, "Mode")
      .value("Centroid", Anchor::Mode::Centroid)
      .value("Vertex", Anchor::Mode::Vertex)
      .value("Path", Anchor::Mode::Path);
  anchor.def(py::init<>())
      .def_static("centroid", &Anchor::centroid,
                  "Blend the area-weighted centroid and the mean rotation (the default).")
      .def_static("at_vertex", &Anchor::at_vertex, py::arg("vertex"),
                  "Blend this vertex's position and its faces' orientation (the paper's mode).")
      .def_static("along", &Anchor::along, py::arg("path"), py::arg("vertex") = -1,
                  "The centroid (vertex = -1) or the vertex follows the path (two shapes only).")
      .def_readonly("mode", &Anchor::mode)
      .def_readonly("vertex", &Anchor::vertex)
      .def_readonly("path", &Anchor::path);
}

}  // namespace bdinterp::bindings
