#include "bdinterp/distortion.h"
#include "bindings.h"

namespace bdinterp::bindings {

void bind_distortion(py::module_& m) {
  m.def("conformal_distortion", &conformal_distortion, py::arg("source"), py::arg("result"),
        py::arg("faces"), "Per-face K = sigma_max / sigma_min of the affine map source -> result.");
  m.def("flipped_faces", &flipped_faces, py::arg("source"), py::arg("result"), py::arg("faces"),
        "Number of faces whose orientation in result is opposite to (or collapsed from) the source's.");
  m.def("area_ratio", &area_ratio, py::arg("source"), py::arg("result"), py::arg("faces"),
        "Per-face signed area ratio result / source (negative: flipped).");
}

}  // namespace bdinterp::bindings
