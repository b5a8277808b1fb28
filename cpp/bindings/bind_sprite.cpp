// bdinterp._core.mesh_from_alpha: the sprite mesher (bdinterp.mesh_from_image wraps it).
#include "bindings.h"

#ifdef BDINTERP_SPRITE
#include "bdinterp/sprite_mesh.h"

namespace bdinterp::bindings {

void bind_sprite(py::module_& m) {
  m.def(
      "mesh_from_alpha",
      [](const Eigen::Ref<const AlphaImage>& alpha, double threshold, double spacing, double detail,
         double padding, double min_angle, double min_area) {
        SpriteMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = mesh_from_alpha(alpha, {threshold, spacing, detail, padding, min_angle, min_area});
        }
        py::dict out;
        out["vertices"] = mesh.vertices;
        out["faces"] = mesh.faces;
        out["uvs"] = mesh.uvs;
        out["spacing"] = mesh.spacing;
        out["outline_vertices"] = mesh.outline_vertices;
        out["islands"] = mesh.islands;
        out["holes"] = mesh.holes;
        out["dropped_islands"] = mesh.dropped_islands;
        out["dropped_holes"] = mesh.dropped_holes;
        out["area"] = mesh.area;
        return out;
      },
      py::arg("alpha").noconvert(), py::arg("threshold"), py::arg("spacing"), py::arg("detail"),
      py::arg("padding"), py::arg("min_angle"), py::arg("min_area"),
      "Mesh of alpha >= threshold of a row-major float32 (h, w) alpha (row 0 the top); a dict.");
}

}  // namespace bdinterp::bindings
#endif
