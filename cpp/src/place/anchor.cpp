#include "place/anchor_frame.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "mesh/geometry.h"
#include "parallel/parallel.h"
#include "place/rigid_motion.h"
#include "mesh/triangle.h"
#include "mesh/turns.h"

namespace bdinterp {

AnchorFrame::AnchorFrame(const Mesh& disk, const Positions& base, int vertex)
    : mesh_(&disk), vertex_(vertex), base_(base) {
  const Faces& F = disk.faces();
  std::vector<bool> in_region(F.rows(), vertex < 0);
  if (vertex >= 0)
    for (int f : disk.vertex_faces(vertex)) in_region[f] = true;
  // Unwrapping order: breadth-first over the dual graph from face 0.
  std::vector<int> slot_of(F.rows(), -1);
  slot_of[0] = 0;
  tree_.reserve(F.rows());
  tree_.push_back({0, -1});
  for (const Mesh::DualStep& st : disk.dual_walk({0})) {
    slot_of[st.face] = static_cast<int>(tree_.size());
    tree_.push_back({st.face, slot_of[st.parent]});
  }
  // Per slot: the base edges b1, b2, pre-multiplied by the orientation sign s of the base face, and
  // the face's share of the region's base area.
  base_edges_.resize(static_cast<Eigen::Index>(tree_.size()), 4);
  weight_.resize(static_cast<Eigen::Index>(tree_.size()));
  for (size_t k = 0; k < tree_.size(); ++k) {
    const int f = tree_[k][0];
    const Eigen::Matrix2d b = edge_matrix(base_, F, f);  // b1, b2
    const double s = doubled_area(base_, F, f) < 0 ? -1.0 : 1.0;
    base_edges_.row(static_cast<Eigen::Index>(k)) << s * b(0, 0), s * b(1, 0), s * b(0, 1), s * b(1, 1);
    weight_[static_cast<Eigen::Index>(k)] = in_region[f] ? base_area(f) : 0.0;
  }
  weight_ /= weight_.sum();
}

void AnchorFrame::set_region(const Eigen::VectorXd& face_weight) {
  if (face_weight.size() != mesh_->num_faces() || !(face_weight.minCoeff() >= 0) || !(face_weight.sum() > 0))
    throw InvalidInput("anchor region: need one non-negative weight per face, not all zero");
  for (size_t k = 0; k < tree_.size(); ++k) weight_[static_cast<Eigen::Index>(k)] = face_weight[tree_[k][0]];
  weight_ /= weight_.sum();
  region_ = true;
}

double AnchorFrame::base_area(int f) const { return 0.5 * std::abs(doubled_area(base_, mesh_->faces(), f)); }

Eigen::Vector2d AnchorFrame::measure(const Positions& X, double* rot) const {
  // The affine map J (base edges b_k -> edges e_k) written as J z = a z + b conj(z): its closest
  // rotation is arg(a), with a = (e1 conj(b2) - e2 conj(b1)) / (b1 conj(b2) - b2 conj(b1)) and
  // the denominator = -2i cross(b1, b2). No inverse matrices need to be stored. Each face's angle is
  // moved to within pi of its parent's; the wrapped angles differ by less than 2 pi, so one
  // correction of 2 pi suffices (no remainder). The centroid is accumulated in the same pass.
  const Faces& F = mesh_->faces();
  double* raw = rot + tree_.size();  // second half of the scratch: the angles as atan2 gives them
  const long slots = static_cast<long>(tree_.size());
  const parallel::Loop faces(slots);
  parallel::PerChunk psx(faces.chunks()), psy(faces.chunks()), parea(faces.chunks());  // signed: any orientation works
  faces.run([&](int chunk, long k) {
    const int f = tree_[k][0];
    const int v0 = F(f, 0), v1 = F(f, 1), v2 = F(f, 2);
    const double e1x = X(v1, 0) - X(v0, 0), e1y = X(v1, 1) - X(v0, 1);
    const double e2x = X(v2, 0) - X(v0, 0), e2y = X(v2, 1) - X(v0, 1);
    const double* b = &base_edges_(k, 0);  // s b1, s b2
    const double num_re = (e1x * b[2] + e1y * b[3]) - (e2x * b[0] + e2y * b[1]);
    const double num_im = (e1y * b[2] - e1x * b[3]) - (e2y * b[0] - e2x * b[1]);
    raw[k] = fast_atan2(num_re, -num_im);
    // The centroid of the region given by set_region, else the whole piece's (area-weighted).
    const double a = region_ ? weight_[k] : e1x * e2y - e1y * e2x;
    psx.at(chunk) += a * (X(v0, 0) + X(v1, 0) + X(v2, 0));
    psy.at(chunk) += a * (X(v0, 1) + X(v1, 1) + X(v2, 1));
    parea.at(chunk) += a;
  });
  const double sx = psx.sum(), sy = psy.sum(), area = parea.sum();
  rot[0] = raw[0];
  for (long k = 1; k < slots; ++k) {
    const int parent = tree_[k][1];
    double d = raw[k] - raw[parent];
    if (d > kPi) d -= kTwoPi;
    else if (d < -kPi) d += kTwoPi;
    rot[k] = rot[parent] + d;
  }
  if (vertex_ >= 0) return X.row(vertex_).transpose();
  return Eigen::Vector2d(sx, sy) / (3 * area);
}

Eigen::VectorXd AnchorFrame::face_rotations(const Positions& X) const {
  std::vector<double> scratch(2 * tree_.size());
  measure(X, scratch.data());
  Eigen::VectorXd rot(mesh_->num_faces());
  for (size_t k = 0; k < tree_.size(); ++k) rot[tree_[k][0]] = scratch[k];
  return rot;
}

Eigen::VectorXd AnchorFrame::bulk_rotations(const Positions& X) const {
  Eigen::VectorXd rot = face_rotations(X);
  std::vector<std::pair<double, double>> angle_area(rot.size());
  for (int f = 0; f < rot.size(); ++f) angle_area[f] = {rot[f], base_area(f)};
  rot.array() -= detail::median_turns(std::move(angle_area));
  return rot;
}

Frame2 AnchorFrame::measure_input(const Positions& X) const {
  const Eigen::VectorXd rot = bulk_rotations(X);
  std::vector<double> scratch(2 * tree_.size());
  const Eigen::Vector2d point = measure(X, scratch.data());
  double angle = 0;
  for (size_t k = 0; k < tree_.size(); ++k) angle += weight_[static_cast<Eigen::Index>(k)] * rot[tree_[k][0]];
  return {point, angle};
}

void AnchorFrame::place(Positions& X, const Frame2& target) const {
  // Scratch per thread: frames of one piece are placed concurrently by frames().
  thread_local std::vector<double> scratch;
  scratch.resize(2 * tree_.size());
  const Eigen::Vector2d point = measure(X, scratch.data());
  double angle = 0;  // the region's mean rotation, on the branch as it falls
  for (size_t k = 0; k < tree_.size(); ++k) angle += weight_[static_cast<Eigen::Index>(k)] * scratch[k];
  const double turn = target.angle - angle;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(turn).toRotationMatrix();
  const Eigen::Vector2d p = R * point;
  const Eigen::Vector2d shift = target.point - p;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {  // in place: no temporary of X
    const double x = X(v, 0), y = X(v, 1);
    X(v, 0) = R(0, 0) * x + R(0, 1) * y + shift.x();
    X(v, 1) = R(1, 0) * x + R(1, 1) * y + shift.y();
  }
}

Frame2 blend_frames(const std::vector<Frame2>& inputs, const Eigen::VectorXd& w, const Anchor& anchor,
                    int geodesic_base) {
  Frame2 out{Eigen::Vector2d::Zero(), 0.0};
  if (geodesic_base >= 0) {
    out = geodesic_blend(inputs, w, geodesic_base);
  } else {
    for (size_t i = 0; i < inputs.size(); ++i) {
      out.point += w[static_cast<Eigen::Index>(i)] * inputs[i].point;
      out.angle += w[static_cast<Eigen::Index>(i)] * inputs[i].angle;
    }
  }
  if (anchor.mode != Anchor::Mode::Path) return out;
  // Two shapes: t = w[1]. Add the path's deviation from its own chord.
  const AnchorPath& p = anchor.path;
  const double t = w[1];
  auto sample = [&](double s) {
    const auto it = std::upper_bound(p.t.begin(), p.t.end(), s);
    if (it == p.t.begin()) return Frame2{p.position.row(0).transpose(), p.angle.front()};
    if (it == p.t.end()) return Frame2{p.position.row(p.t.size() - 1).transpose(), p.angle.back()};
    const size_t k = static_cast<size_t>(it - p.t.begin());
    const double a = (s - p.t[k - 1]) / (p.t[k] - p.t[k - 1]);
    return Frame2{((1 - a) * p.position.row(k - 1) + a * p.position.row(k)).transpose(),
                  (1 - a) * p.angle[k - 1] + a * p.angle[k]};
  };
  const Frame2 at = sample(t), s0 = sample(0.0), s1 = sample(1.0);
  out.point += at.point - ((1 - t) * s0.point + t * s1.point);
  out.angle += at.angle - ((1 - t) * s0.angle + t * s1.angle);
  return out;
}

}  // namespace bdinterp
