// bdinterp._core.mesh_from_alpha, SpriteMeshOptions and SpriteMesh: the sprite mesher
// (bdinterp.mesh_from_image wraps it). The options' defaults and the mesh's fields are the C++
// structs' own, so Python has no second copy of them.
#include "bindings.h"

#ifdef BDINTERP_SPRITE
#include "bdinterp/sprite_mesh.h"

namespace bdinterp::bindings {

void bind_sprite(py::module_& m) {
  py::class_<SpriteMeshOptions>(m, "SpriteMeshOptions", "The sprite mesher's options, with their defaults.")
      .def(py::init<>())
      .def_readwrite("threshold", &SpriteMeshOptions::threshold, "alpha >= threshold is the sprite; in (0, 1]")
      .def_readwrite("spacing", &SpriteMeshOptions::spacing,
                     "the longest edge in pixels; 0: the sprite's larger side / spacing_divisions")
      .def_readwrite("spacing_divisions", &SpriteMeshOptions::spacing_divisions,
                     ">= 1; used when spacing is 0 (the spacing is at least 2 pixels)")
      .def_readwrite("detail", &SpriteMeshOptions::detail,
                     "how far (pixels) the simplified outline may stray from the traced one")
      .def_readwrite("padding", &SpriteMeshOptions::padding, "how far (pixels) the outline grows outwards")
      .def_readwrite("min_angle", &SpriteMeshOptions::min_angle, "degrees, in (0, 30]")
      .def_readwrite("min_area", &SpriteMeshOptions::min_area,
                     "islands and holes smaller than this (pixels^2) are dropped");
  py::class_<SpriteMesh>(m, "SpriteMesh",
                         "A sprite's triangle mesh: vertices (n, 2) in pixels (x right, y up, origin at the "
                         "image's bottom-left corner), faces (m, 3) counter-clockwise, uvs (n, 2).")
      .def_readonly("vertices", &SpriteMesh::vertices)
      .def_readonly("faces", &SpriteMesh::faces)
      .def_readonly("uvs", &SpriteMesh::uvs, "vertices / (width, height)")
      .def_readonly("spacing", &SpriteMesh::spacing, "the edge bound used")
      .def_readonly("outline_vertices", &SpriteMesh::outline_vertices, "of the simplified, grown outline")
      .def_readonly("islands", &SpriteMesh::islands)
      .def_readonly("holes", &SpriteMesh::holes)
      .def_readonly("dropped_islands", &SpriteMesh::dropped_islands, "smaller than min_area")
      .def_readonly("dropped_holes", &SpriteMesh::dropped_holes, "smaller than min_area or closed by the padding")
      .def_readonly("area", &SpriteMesh::area, "of the mesh, pixels^2")
      .def_property_readonly(
          "size", [](const SpriteMesh& s) { return py::make_tuple(s.width, s.height); }, "the image's (width, height)")
      .def("__repr__", [](const SpriteMesh& s) {
        return "<SpriteMesh " + std::to_string(s.vertices.rows()) + " vertices, " + std::to_string(s.faces.rows()) +
               " faces, spacing " + std::to_string(s.spacing) + ">";
      });
  m.def(
      "mesh_from_alpha",
      [](const Eigen::Ref<const AlphaImage>& alpha, const SpriteMeshOptions& options) {
        py::gil_scoped_release release;
        return mesh_from_alpha(alpha, options);
      },
      py::arg("alpha").noconvert(), py::arg("options"),
      "Mesh of alpha >= threshold of a row-major float32 (h, w) alpha (row 0 the top).");
}

}  // namespace bdinterp::bindings
#endif
