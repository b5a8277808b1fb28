#include "bdinterp/baselines.h"
#include "bindings.h"

namespace bdinterp::bindings {

void bind_baselines(py::module_& m) {
  m.def("linear_interpolate", &linear_interpolate, py::arg("source"), py::arg("target"), py::arg("t"));
  py::class_<ArapInterpolator>(m, "ArapInterpolator")
      .def(py::init<const Positions&, const Positions&, const Faces&>(), py::arg("source"),
           py::arg("target"), py::arg("faces"))
      .def("at", &ArapInterpolator::at, py::arg("t"), py::call_guard<py::gil_scoped_release>());
}

}  // namespace bdinterp::bindings
