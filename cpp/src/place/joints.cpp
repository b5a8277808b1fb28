#include "place/joints.h"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>

#include "mesh/turns.h"

namespace bdinterp {

using detail::JointEdge;
using detail::PieceShape;

Eigen::Vector2d Joints::Site::at(const Eigen::Ref<const Positions>& X) const {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int c = 0; c < 3; ++c) p += bary[c] * X.row(v[c]).transpose();
  return p;
}

Joints::Joints(const std::vector<Positions>& shapes, int base, double size, const detail::PieceShapes& pieces,
               int root, const std::vector<detail::GivenJoint>& given)
    : pieces_(pieces) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<JointEdge> tree = given.empty()
                                          ? detail::find_joint_tree(shapes, base, size, pieces_, root, roots_)
                                          : detail::given_joint_tree(shapes, base, size, given, pieces_, roots_);
  for (const detail::GivenJoint& g : given)
    if (g.parent < 0) paths_.push_back({g.child, site(*pieces_[g.child], g.point), {}});
  for (Path& path : paths_)
    for (const Positions& X : shapes) path.point.push_back(path.at.at(X));
  joints_.reserve(tree.size());
  for (const JointEdge& e : tree) add_joint(shapes, base, e, *pieces_[e.parent], *pieces_[e.child]);
  seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Joints::Site Joints::site(const PieceShape& piece, const Eigen::Vector2d& q, int face) {
  int f = face;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  if (f >= 0) bary = piece.barycentric(q, f);
  else piece.locate_nearest(q, f, bary);
  return {{piece.vertex(f, 0), piece.vertex(f, 1), piece.vertex(f, 2)}, bary};
}

void Joints::add_joint(const std::vector<Positions>& shapes, int base, const JointEdge& edge,
                       const PieceShape& in_parent, const PieceShape& in_child) {
  Joint j{edge, site(in_parent, edge.point, edge.faces[0]), site(in_child, edge.point, edge.faces[1]), {}, {}, {}};
  const std::vector<Frame2>&P = *in_parent.piece().frames, &C = *in_child.piece().frames;
  const size_t b = static_cast<size_t>(base);
  j.parent_angle.reserve(shapes.size()), j.relative.reserve(shapes.size()), j.offset.reserve(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i) {
    j.parent_angle.push_back(P[i].angle);
    // The keys' turn of the child against its parent, the short way (a joint does not wind up).
    const double turn = (C[i].angle - C[b].angle) - (P[i].angle - P[b].angle);
    j.relative.push_back(C[b].angle - P[b].angle + detail::wrap_angle(turn));
    j.offset.push_back(j.in_child.at(shapes[i]) - j.in_parent.at(shapes[i]));
  }
  joints_.push_back(std::move(j));
}

void Joints::apply(const Eigen::VectorXd& w, std::vector<double>& angle, Eigen::Ref<Positions> out) const {
  for (const Path& path : paths_) {  // a root on its given path: its point on the chord, its own angle
    Eigen::Vector2d to = Eigen::Vector2d::Zero();
    for (Eigen::Index i = 0; i < w.size(); ++i) to += w[i] * path.point[static_cast<size_t>(i)];
    const Eigen::RowVector2d shift = (to - path.at.at(out)).transpose();
    for (int v : *pieces_[path.piece]->piece().vertices) out.row(v) += shift;
  }
  for (const Joint& j : joints_) {
    const int parent = j.edge.parent, child = j.edge.child;
    double turn = 0;  // the child's angle: the parent's plus the blend of their relative angles
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // the keys' offsets blended in the parent's frame
    for (Eigen::Index i = 0; i < w.size(); ++i) {
      turn += w[i] * j.relative[static_cast<size_t>(i)];
      offset += w[i] * (Eigen::Rotation2Dd(angle[parent] - j.parent_angle[static_cast<size_t>(i)]) *
                        j.offset[static_cast<size_t>(i)]);
    }
    turn += angle[parent];
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(turn - angle[child]).toRotationMatrix();
    angle[child] = turn;
    const Eigen::Vector2d from = j.in_child.at(out), to = j.in_parent.at(out) + offset;
    for (int v : *pieces_[child]->piece().vertices) out.row(v) = (R * (out.row(v).transpose() - from) + to).transpose();
  }
}

}  // namespace bdinterp
