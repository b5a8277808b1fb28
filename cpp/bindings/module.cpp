#include "bindings.h"

namespace bdinterp::bindings {

PYBIND11_MODULE(_core, m) {
  m.doc() = "bdinterp compiled core: bounded-distortion planar shape interpolation";
  // InvalidInput derives from std::invalid_argument, which pybind11 already maps to ValueError.
  py::register_exception<SolverError>(m, "SolverError", PyExc_RuntimeError);
  bind_anchor(m);
  bind_stats(m);
  bind_interpolator(m);
  bind_distortion(m);
  bind_baselines(m);
}

}  // namespace bdinterp::bindings
