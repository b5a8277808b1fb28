// The interior: CGAL's constrained Delaunay triangulation of the outline, refined by its 2D
// Delaunay mesher (Ruppert/Shewchuk refinement with a smallest-angle and an edge-length bound).
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <map>
#include <queue>

#include "bdinterp/types.h"
#include "sprite/outline.h"

namespace bdinterp::sprite {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
using Mesher = CGAL::Delaunay_mesher_2<CDT, Criteria>;

// One point inside every bounded region outside the sprite (holes): the centroid of a face of each
// component at an even nesting depth, counting the constraints crossed from the infinite face.
std::vector<K::Point_2> hole_seeds(const CDT& cdt) {
  std::map<CDT::Face_handle, int> depth;
  std::vector<K::Point_2> seeds;
  std::queue<std::pair<CDT::Face_handle, int>> next;  // breadth first over depths
  next.push({cdt.infinite_face(), 0});
  std::vector<std::pair<CDT::Face_handle, int>> later;
  while (!next.empty() || !later.empty()) {
    if (next.empty()) {
      for (auto& f : later) next.push(f);
      later.clear();
      continue;
    }
    auto [start, level] = next.front();
    next.pop();
    if (depth.count(start)) continue;
    if (level % 2 == 0 && !cdt.is_infinite(start))
      seeds.push_back(CGAL::centroid(start->vertex(0)->point(), start->vertex(1)->point(),
                                     start->vertex(2)->point()));
    std::vector<CDT::Face_handle> todo{start};
    depth[start] = level;
    while (!todo.empty()) {  // the component of `start`: faces reached without crossing a constraint
      CDT::Face_handle f = todo.back();
      todo.pop_back();
      for (int i = 0; i < 3; ++i) {
        CDT::Face_handle n = f->neighbor(i);
        if (depth.count(n)) continue;
        if (cdt.is_constrained(CDT::Edge(f, i))) {
          later.push_back({n, level + 1});
        } else {
          depth[n] = level;
          todo.push_back(n);
        }
      }
    }
  }
  return seeds;
}

}  // namespace

SpriteMesh triangulate(const std::vector<Loop>& loops, double spacing, double min_angle, double area) {
  CDT cdt;
  size_t outline = 0;
  for (const Loop& loop : loops) {
    std::vector<K::Point_2> points;
    for (const Point& p : loop) points.emplace_back(p.x(), p.y());
    cdt.insert_constraint(points.begin(), points.end(), true);
    outline += loop.size();
  }
  const std::vector<K::Point_2> seeds = hole_seeds(cdt);
  const double sine = std::sin(min_angle * kPi / 180);
  Mesher mesher(cdt, Criteria(sine * sine, spacing));  // CGAL's bound is sin^2(smallest angle)
  mesher.set_seeds(seeds.begin(), seeds.end(), false);
  mesher.init();
  // A bound on the Steiner points (well above what the refinement needs: area / equilateral at
  // spacing / 2, plus the outline) so that no input makes it run away.
  const double budget = 8 * area / (0.433 * spacing * spacing) + 20.0 * outline + 1000;
  for (double steps = 0; !mesher.is_refinement_done(); ++steps) {
    if (steps > budget) throw SolverError("mesh_from_image: the Delaunay refinement did not finish");
    mesher.step_by_step_refine_mesh();
  }
  std::map<CDT::Vertex_handle, int> index;
  std::vector<Eigen::Vector3i> faces;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    Eigen::Vector3i face;
    for (int i = 0; i < 3; ++i) face[i] = index.emplace(f->vertex(i), int(index.size())).first->second;
    faces.push_back(face);
  }
  SpriteMesh mesh;
  mesh.vertices.resize(Eigen::Index(index.size()), 2);
  for (const auto& [v, i] : index) mesh.vertices.row(i) << v->point().x(), v->point().y();
  mesh.faces.resize(Eigen::Index(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) mesh.faces.row(Eigen::Index(f)) = faces[f].transpose();
  mesh.outline_vertices = int(outline);
  return mesh;
}

}  // namespace bdinterp::sprite
