// FrameStats as a typed, read-only object with a dict view (stats["residual"], stats.as_dict()).
#include <string>
#include <vector>

#include "bdinterp/interpolator.h"
#include "bindings.h"

namespace bdinterp::bindings {
namespace {

// Binds one field read-only and records its name, so the dict view lists exactly the attributes.
// C: FrameStats or a base of it (the fields it shares with FlattenReport).
template <typename T, typename C>
void field(py::class_<FrameStats>& cls, std::vector<std::string>& names, const char* name,
           T C::*member, const char* doc) {
  cls.def_readonly(name, member, doc);
  names.emplace_back(name);
}

}  // namespace

void bind_stats(py::module_& m) {
  py::class_<FrameStats> cls(m, "FrameStats",
                             "Statistics of the last at()/blend(), or of all frames of frames().");
  auto names = std::make_shared<std::vector<std::string>>();
  field(cls, *names, "iterations", &FrameStats::iterations,
        "Newton steps of one convex solve (the most over solves, pieces and frames)");
  field(cls, *names, "convex_solves", &FrameStats::convex_solves,
        "convex solves (summed): one per piece, more where a piece's holes need closing");
  field(cls, *names, "residual", &FrameStats::residual,
        "max |2 pi - angle sum| at interior vertices (radians)");
  field(cls, *names, "broken_triangles", &FrameStats::broken_triangles,
        "faces violating the triangle inequality at the solution");
  field(cls, *names, "max_broken_triangles", &FrameStats::max_broken_triangles,
        "the most broken triangles seen during Newton");
  field(cls, *names, "line_search_steps", &FrameStats::line_search_steps,
        "step halvings over all iterations (summed)");
  field(cls, *names, "flatness", &FrameStats::flatness, "layout residual (see Layout::embed)");
  field(cls, *names, "pieces", &FrameStats::pieces, "connected pieces solved");
  field(cls, *names, "factorizations", &FrameStats::factorizations,
        "numeric Cholesky factorisations (summed over pieces)");
  field(cls, *names, "chord_steps", &FrameStats::chord_steps,
        "Newton steps that reused an earlier factorisation (summed)");
  field(cls, *names, "seconds", &FrameStats::seconds, "wall-clock seconds in C++");
  field(cls, *names, "converged", &FrameStats::converged,
        "every frame passed the self-check (finite, no broken triangles, flat layout)");
  field(cls, *names, "warnings", &FrameStats::warnings,
        "why not, naming the first failing frame; empty when converged");
  field(cls, *names, "hole_closure", &FrameStats::hole_closure,
        "per hole: the translation period of the flat metric around it / the hole's perimeter");
  field(cls, *names, "fold_faces", &FrameStats::fold_faces,
        "faces of the fold region (folded inputs, docs/FOLDS.md); 0 when no input folds");
  field(cls, *names, "fold_free_vertices", &FrameStats::fold_free_vertices,
        "vertices filled in by the fold region's Poisson solve");
  field(cls, *names, "joints", &FrameStats::joints,
        "joints between overlapping pieces (docs/JOINTS.md); 0 when they are off or none overlap");
  field(cls, *names, "threads", &FrameStats::threads,
        "threads that ran: frames()'s workers (one thread each), or the most one loop of a frame ran on");
  cls.def("keys", [names](const FrameStats&) { return *names; }, "The attribute names.")
      .def("as_dict",
           [names](py::object self) {
             py::dict d;
             for (const auto& n : *names) d[n.c_str()] = self.attr(n.c_str());
             return d;
           })
      .def("__getitem__",
           [names](py::object self, const std::string& key) {
             for (const auto& n : *names)
               if (n == key) return self.attr(key.c_str());
             throw py::key_error("FrameStats has no field '" + key + "'");
           })
      .def("__repr__", [names](py::object self) {
        std::string s;
        for (const auto& n : *names) {
          const auto value = py::repr(self.attr(n.c_str())).cast<std::string>();
          s += (s.empty() ? "" : ", ") + n + "=" + value;
        }
        return "FrameStats(" + s + ")";
      });
}

}  // namespace bdinterp::bindings
