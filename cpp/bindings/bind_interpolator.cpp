// The Interpolator, constructed from an Anchor and an InterpolatorOptions (both bound as classes).
// Every call that solves releases the GIL first; the Interpolator then takes its own mutex, so a
// thread waiting for that mutex never holds the GIL and the two locks cannot deadlock.
#include "bdinterp/interpolator.h"
#include "parallel/parallel.h"
#include "bindings.h"

namespace bdinterp::bindings {
namespace {

using Release = py::call_guard<py::gil_scoped_release>;
// JointKind's names in Python, in the enum's order.
constexpr const char* kJointKinds[] = {"pin", "glued", "slide", "given"};
// RootReason's names in Python, in the enum's order.
constexpr const char* kRootReasons[] = {"anchor", "still", "travels", "turns", "given", "path"};

// A read-write property for a field of the nested FlattenOptions.
template <typename T>
void flatten_field(py::class_<InterpolatorOptions>& cls, const char* name, T FlattenOptions::*member,
                   const char* doc) {
  cls.def_property(
      name, [member](const InterpolatorOptions& o) { return o.flatten.*member; },
      [member](InterpolatorOptions& o, T v) { o.flatten.*member = v; }, doc);
}

void bind_options(py::module_& m) {
  py::class_<InterpolatorOptions> cls(
      m, "InterpolatorOptions", "Options of an Interpolator; every field has the library's default.");
  cls.def(py::init<>())
      .def_readwrite("base", &InterpolatorOptions::base, "the shape the maps start from")
      .def_readwrite("threads", &InterpolatorOptions::threads,
                     "workers of frames() and threads of one frame (0 = one per core, 1 = sequential)")
      .def_readwrite("max_flatness", &InterpolatorOptions::max_flatness,
                     "self-check: the largest layout residual a returned frame may have")
      .def_readwrite("strict", &InterpolatorOptions::strict,
                     "raise SolverError for a frame that fails the self-check (else: flagged in stats)")
      .def_readwrite("folds", &InterpolatorOptions::folds,
                     "folded inputs: cut out and fill their fold region (docs/FOLDS.md); False: the "
                     "paper's method on the whole mesh")
      .def_readwrite("joints", &InterpolatorOptions::joints,
                     "pieces that overlap in the base shape and are held by a pin or glued stay joined "
                     "(docs/JOINTS.md); False: every piece placed on its own")
      .def_property(
          "joint_links",
          [](const InterpolatorOptions& o) {
            py::list out;
            for (const JointLink& l : o.joint_links) out.append(py::make_tuple(l.parent_vertex, l.child_vertex, l.point));
            return out;
          },
          [](InterpolatorOptions& o, const std::vector<std::tuple<int, int, Eigen::Vector2d>>& links) {
            o.joint_links.clear();
            for (const auto& [parent, child, point] : links) o.joint_links.push_back({parent, child, point});
          },
          "the tree of joints as given: (parent vertex, child vertex, point (2,)) per child piece; "
          "empty: the joints found from the overlaps")
      .def_property_readonly_static(
          "MAX_THREADS", [](py::object) { return InterpolatorOptions::kMaxThreads; });
  flatten_field(cls, "tolerance", &FlattenOptions::tolerance,
                "stop when max |2 pi - angle sum| <= tolerance (radians)");
  flatten_field(cls, "refinement", &FlattenOptions::refinement,
                "then refine towards tolerance * refinement while steps halve the residual (1: stop at "
                "the tolerance)");
  flatten_field(cls, "max_iterations", &FlattenOptions::max_iterations,
                "Newton steps before SolverError");
  flatten_field(cls, "reuse_factorization", &FlattenOptions::reuse_factorization,
                "allow chord steps with an earlier factorisation");
}

void bind_threading_info(py::module_& m) {
  m.def(
      "threading_info",
      [] {
        const parallel::Runtimes r = parallel::runtimes();
        auto file = [](const std::string& f) { return f.empty() ? py::object(py::none()) : py::object(py::str(f)); };
        py::dict d;
        d["usable_cores"] = parallel::usable_cores();
        d["machine_busy"] = parallel::machine_busy();
        d["blas"] = file(r.blas);
        d["blas_threads"] = r.blas_threads;
        d["openmp"] = file(r.openmp);
        return d;
      },
      "How bdinterp sees this process's threads: usable_cores (online CPUs within the affinity mask "
      "and the cgroup CPU quota), machine_busy (the pool's last verdict: frames' loops run serially "
      "while other programs leave fewer than two cores), blas (the file of the BLAS CHOLMOD calls, or "
      "None), blas_threads (it is OpenBLAS, held at one thread during every call), openmp (the file "
      "of the OpenMP runtime CHOLMOD calls, whose teams may shrink to the idle cores; None if none).");
}

// The joints an Interpolator found or was given, their roots, and what they cost to choose.
void bind_joints(py::class_<Interpolator>& cls) {
  cls.def(
          "joints",
          [](const Interpolator& I) {
            py::list out;
            for (const auto& j : I.joints())
              out.append(py::dict(py::arg("parent") = j.parent_vertex, py::arg("child") = j.child_vertex,
                                  py::arg("point") = j.point, py::arg("pin") = j.pin,
                                  py::arg("kind") = kJointKinds[static_cast<int>(j.kind)], py::arg("fit") = j.fit));
            return out;
          },
          "The joints between pieces, parents first: dicts parent, child (each piece's lowest vertex), "
          "point (the joint point in the base shape), kind ('pin', 'glued', 'slide' or 'given'), pin (both "
          "pieces carry the point to one place in every input) and fit (that gap relative to the size).")
      .def(
          "joint_roots",
          [](const Interpolator& I) {
            py::list out;
            for (const auto& r : I.joint_roots())
              out.append(py::dict(py::arg("piece") = r.vertex, py::arg("reason") = kRootReasons[static_cast<int>(r.reason)],
                                  py::arg("point") = r.point, py::arg("rank") = r.rank));
            return out;
          },
          "The root of every tree of joints (a piece in no joint is its own tree): dicts piece (its "
          "lowest vertex), reason ('anchor', 'still', 'travels', 'turns', 'given' or 'path'), point (for "
          "'turns': the fixed point of the piece's own motion) and rank (for 'turns': the fixed point's "
          "distance outside the piece over the pins' reach x its size, plus its largest turn / pi).")
      .def_property_readonly("joints_seconds", &Interpolator::joints_seconds,
                             "Wall-clock seconds the joints took when it was made (the tree found or the "
                             "given links checked, each joint's sites and offsets); 0 without joints.");
}

}  // namespace

void bind_interpolator(py::module_& m) {
  bind_options(m);
  bind_threading_info(m);
  m.def("piece_labels", &piece_labels, py::arg("faces"), py::arg("num_vertices"),
        "(n,) the piece of every vertex as the Interpolator splits the mesh, numbered in order of "
        "each piece's lowest vertex; a vertex in no face is a piece of its own.");
  py::class_<Interpolator> cls(m, "Interpolator");
  cls.def(py::init<const std::vector<Positions>&, const Faces&, const Anchor&,
                    const InterpolatorOptions&>(),
           py::arg("shapes"), py::arg("faces"), py::arg("anchor") = Anchor::centroid(),
           py::arg("options") = InterpolatorOptions{}, Release())
      .def("at", &Interpolator::at, py::arg("t"), Release())
      .def("blend", &Interpolator::blend, py::arg("weights"), Release())
      .def("frames_into", &Interpolator::frames, py::arg("ts"), py::arg("out").noconvert(), Release(),
           "Writes frame j into rows [j n, (j+1) n) of out, a C-contiguous float64 (len(ts) n, 2) array.")
      .def_property_readonly(
          "stats",
          [](const Interpolator& I) {
            py::gil_scoped_release release;  // last_stats() takes the mutex a solve may hold
            return I.last_stats();
          },
          "FrameStats of the last at()/blend(), or of all frames of frames_into().")
      .def("folded_faces", &Interpolator::folded_faces, py::arg("shape"),
           "Faces of input `shape` folded (reversed) relative to the base shape.")
      .def("forget", &Interpolator::forget, Release(),
           "Drops cached solutions and factorisations: the next frame is computed cold.")
      .def("floor_seconds", &Interpolator::floor_seconds, py::arg("repeats") = 5, Release(),
           "Median seconds of one Cholesky factorisation + solve of the interior cotan Laplacian.")
      .def_property_readonly("options", &Interpolator::options, "The options it was built with.")
      .def_property_readonly("threads", &Interpolator::threads,
                             "options.threads (read-only: an Interpolator keeps the threads it was built with).")
      .def_property_readonly("num_vertices", &Interpolator::num_vertices)
      .def_property_readonly("num_shapes", &Interpolator::num_shapes);
  bind_joints(cls);
}

}  // namespace bdinterp::bindings
