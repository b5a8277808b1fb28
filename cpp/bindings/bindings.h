// One binder per area of the library; module.cpp calls them all.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bdinterp/types.h"

namespace bdinterp::bindings {

namespace py = pybind11;

void bind_anchor(py::module_& m);
void bind_stats(py::module_& m);
void bind_interpolator(py::module_& m);
void bind_distortion(py::module_& m);
void bind_baselines(py::module_& m);
#ifdef BDINTERP_SPRITE
void bind_sprite(py::module_& m);  // the sprite mesher, where built with CGAL
#endif

}  // namespace bdinterp::bindings
