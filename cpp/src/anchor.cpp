#include "bdinterp/anchor.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <numeric>
#include <sstream>

#include "bdinterp/triangle.h"

namespace bdinterp {
namespace {
constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix2d edge_matrix(const Positions& X, const Faces& F, int f) {
  Eigen::Matrix2d D;
  D.col(0) = (X.row(F(f, 1)) - X.row(F(f, 0))).transpose();
  D.col(1) = (X.row(F(f, 2)) - X.row(F(f, 0))).transpose();
  return D;
}

double wrap(double a) { return std::remainder(a, 2 * kPi); }  // to [-pi, pi]

}  // namespace

AnchorFrame::AnchorFrame(const Mesh& disk, const Positions& base, int vertex)
    : mesh_(&disk), vertex_(vertex), base_(base) {
  const Faces& F = disk.faces();
  if (vertex >= 0) {
    for (int f = 0; f < F.rows(); ++f)
      if (F(f, 0) == vertex || F(f, 1) == vertex || F(f, 2) == vertex) region_.push_back(f);
  }
  // Unwrapping order: breadth-first over the dual graph from face 0.
  std::vector<bool> seen(F.rows(), false);
  std::deque<int> queue{0};
  seen[0] = true;
  tree_.push_back({0, -1});
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int c = 0; c < 3; ++c) {
      const int e = disk.face_edges()(f, c);
      const int g = disk.edge_faces()(e, 0) == f ? disk.edge_faces()(e, 1) : disk.edge_faces()(e, 0);
      if (g < 0 || seen[g]) continue;
      seen[g] = true;
      tree_.push_back({g, f});
      queue.push_back(g);
    }
  }
}

double AnchorFrame::base_area(int f) const {
  const Faces& F = mesh_->faces();
  const Eigen::RowVector2d b1 = base_.row(F(f, 1)) - base_.row(F(f, 0));
  const Eigen::RowVector2d b2 = base_.row(F(f, 2)) - base_.row(F(f, 0));
  return 0.5 * std::abs(b1.x() * b2.y() - b1.y() * b2.x());
}

Eigen::VectorXd AnchorFrame::face_rotations(const Positions& X) const {
  const Faces& F = mesh_->faces();
  Eigen::VectorXd rot(F.rows());
  for (const auto& [f, parent] : tree_) {
    // The affine map J (base edges b_k -> edges e_k) written as J z = a z + b conj(z): its closest
    // rotation is arg(a), with a = (e1 conj(b2) - e2 conj(b1)) / (b1 conj(b2) - b2 conj(b1)) and
    // the denominator = -2i cross(b1, b2). No inverse matrices need to be stored.
    const Eigen::RowVector2d e1 = X.row(F(f, 1)) - X.row(F(f, 0)), e2 = X.row(F(f, 2)) - X.row(F(f, 0));
    const Eigen::RowVector2d b1 = base_.row(F(f, 1)) - base_.row(F(f, 0));
    const Eigen::RowVector2d b2 = base_.row(F(f, 2)) - base_.row(F(f, 0));
    const double num_re = (e1.x() * b2.x() + e1.y() * b2.y()) - (e2.x() * b1.x() + e2.y() * b1.y());
    const double num_im = (e1.y() * b2.x() - e1.x() * b2.y()) - (e2.y() * b1.x() - e2.x() * b1.y());
    const double s = b1.x() * b2.y() - b1.y() * b2.x() < 0 ? -1.0 : 1.0;
    const double raw = fast_atan2(s * num_re, -s * num_im);
    rot[f] = parent < 0 ? raw : rot[parent] + wrap(raw - rot[parent]);
  }
  return rot;
}

double AnchorFrame::region_angle(const Eigen::VectorXd& rot) const {
  double sum = 0, total = 0;
  auto add = [&](int f) {
    const double w = base_area(f);
    sum += w * rot[f];
    total += w;
  };
  if (region_.empty()) {
    for (int f = 0; f < rot.size(); ++f) add(f);
  } else {
    for (int f : region_) add(f);
  }
  return sum / total;
}

Eigen::Vector2d AnchorFrame::point_of(const Positions& X) const {
  if (vertex_ >= 0) return X.row(vertex_).transpose();
  const Faces& F = mesh_->faces();
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double area = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const double a = 0.5 * edge_matrix(X, F, f).determinant();  // signed: any orientation works
    sum += a * (X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3.0;
    area += a;
  }
  return sum / area;
}

Eigen::VectorXd AnchorFrame::bulk_rotations(const Positions& X) const {
  Eigen::VectorXd rot = face_rotations(X);
  std::vector<int> order(rot.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return rot[a] < rot[b]; });
  Eigen::VectorXd area(rot.size());
  for (int f = 0; f < rot.size(); ++f) area[f] = base_area(f);
  double half = 0.5 * area.sum(), acc = 0, median = rot[order.back()];
  for (int f : order) {
    acc += area[f];
    if (acc >= half) {
      median = rot[f];
      break;
    }
  }
  rot.array() -= 2 * kPi * std::round(median / (2 * kPi));
  return rot;
}

Frame2 AnchorFrame::measure_input(const Positions& X) const {
  return {point_of(X), region_angle(bulk_rotations(X))};
}

void AnchorFrame::place(Positions& X, const Frame2& target) const {
  const double turn = target.angle - region_angle(face_rotations(X));
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(turn).toRotationMatrix();
  const Eigen::Vector2d p = R * point_of(X);
  const Eigen::RowVector2d shift = (target.point - p).transpose();
  X = (X * R.transpose()).rowwise() + shift;
}

Frame2 blend_frames(const std::vector<Frame2>& inputs, const Eigen::VectorXd& w, const Anchor& anchor) {
  Frame2 out{Eigen::Vector2d::Zero(), 0.0};
  for (size_t i = 0; i < inputs.size(); ++i) {
    out.point += w[static_cast<Eigen::Index>(i)] * inputs[i].point;
    out.angle += w[static_cast<Eigen::Index>(i)] * inputs[i].angle;
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
