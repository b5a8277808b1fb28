#include "bindings.h"

namespace bdinterp::bindings {
namespace {

// -1 (no such index) as None.
py::object index_or_none(int i) { return i >= 0 ? py::object(py::int_(i)) : py::object(py::none()); }

// The Python error of an InvalidInput: an instance of `type` with what() as its message and the
// detail and location as attributes, so that callers name the place in their own terms.
py::object python_error(const py::handle& type, const InvalidInput& e) {
  py::object error = type(e.what());
  error.attr("detail") = e.detail();
  error.attr("shape") = index_or_none(e.where().shape);
  error.attr("face") = index_or_none(e.where().face);
  error.attr("vertex") = index_or_none(e.where().vertex);
  return error;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "bdinterp compiled core: bounded-distortion planar shape interpolation";
  py::register_exception<SolverError>(m, "SolverError", PyExc_RuntimeError);
  // A ValueError (what callers caught before it had fields); static: the translator outlives init.
  static py::exception<InvalidInput> invalid(m, "InvalidInputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidInput& e) {
      PyErr_SetObject(invalid.ptr(), python_error(invalid, e).ptr());
    }
  });
  // The Python layer's own errors, built by the same rule (bdinterp.errors.invalid).
  m.def(
      "_invalid_input",
      [](const std::string& detail, int shape, int face, int vertex) {
        return python_error(invalid, InvalidInput(Where{shape, face, vertex}, detail));
      },
      py::arg("detail"), py::arg("shape") = -1, py::arg("face") = -1, py::arg("vertex") = -1);
  bind_anchor(m);
  bind_stats(m);
  bind_interpolator(m);
  bind_distortion(m);
  bind_baselines(m);
#ifdef BDINTERP_SPRITE
  bind_sprite(m);
#endif
  m.attr("has_sprite_mesher") = py::bool_(
#ifdef BDINTERP_SPRITE
      true
#else
      false
#endif
  );
}

}  // namespace bdinterp::bindings
