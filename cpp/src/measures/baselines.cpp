#include "bdinterp/baselines.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "place/anchor_frame.h"
#include "mesh/geometry.h"
#include "blend/metric_blend.h"
#include "linalg/sparse_cholesky.h"

namespace bdinterp {

Positions linear_interpolate(const Positions& source, const Positions& target, double t) {
  if (source.rows() != target.rows()) {
    std::ostringstream s;
    s << "source has " << source.rows() << " vertices, target has " << target.rows();
    throw InvalidInput(s.str());
  }
  if (!std::isfinite(t)) throw InvalidInput("t must be finite (got " + std::to_string(t) + ")");
  return (1.0 - t) * source + t * target;
}

struct ArapInterpolator::PieceData {
  Piece piece;
  std::vector<Eigen::Matrix<double, 3, 2>> grad;  // per face: barycentric gradients (rows) in the source
  std::vector<double> area;                      // per face: source area
  std::vector<double> theta;                     // per face: unwrapped rotation angle
  std::vector<Eigen::Matrix2d> stretch;          // per face: S with A = R(theta) S
  Eigen::Vector2d c0, c1;                        // area-weighted centroids of source and target
  std::unique_ptr<SparseCholesky> chol;          // cotan Laplacian, vertex 0 removed
  explicit PieceData(Piece p) : piece(std::move(p)) {}
};

ArapInterpolator::ArapInterpolator(const Positions& source, const Positions& target, const Faces& F)
    : source_(source), target_(target) {
  const Mesh mesh(F, static_cast<int>(source.rows()));
  check_shape(mesh, source, 0);
  check_shape(mesh, target, 1);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.is_isolated_vertex(v)) isolated_.push_back(v);
  for (Piece& p : split_into_pieces(mesh)) {
    auto d = std::make_unique<PieceData>(std::move(p));
    const Mesh& m = d->piece.mesh;
    const Faces& PF = m.faces();
    Positions X0(m.num_vertices(), 2), X1(m.num_vertices(), 2);
    for (size_t k = 0; k < d->piece.vertices.size(); ++k) {
      X0.row(k) = source.row(d->piece.vertices[k]);
      X1.row(k) = target.row(d->piece.vertices[k]);
    }
    const Eigen::VectorXd rot = AnchorFrame(m, X0, -1).bulk_rotations(X1);
    std::vector<SymmetricEntry> laplacian;  // cotan, vertex 0 removed (pinned; the centroid is set after)
    for (int f = 0; f < PF.rows(); ++f) {
      const Eigen::Matrix2d D0 = edge_matrix(X0, PF, f), D1 = edge_matrix(X1, PF, f);
      const Eigen::Matrix2d G = D0.inverse();
      Eigen::Matrix<double, 3, 2> g;
      g.row(1) = G.row(0);
      g.row(2) = G.row(1);
      g.row(0) = -G.row(0) - G.row(1);
      d->grad.push_back(g);
      d->area.push_back(0.5 * std::abs(D0.determinant()));
      const double th = rot[f];
      d->theta.push_back(th);
      d->stretch.push_back(Eigen::Rotation2Dd(-th).toRotationMatrix() * (D1 * G));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (PF(f, i) > 0 && PF(f, j) > 0)
            laplacian.push_back({PF(f, i) - 1, PF(f, j) - 1, d->area.back() * g.row(i).dot(g.row(j))});
    }
    d->chol = factorise(m.num_vertices() - 1, laplacian);
    d->c0 = area_centroid(X0, PF);
    d->c1 = area_centroid(X1, PF);
    pieces_.push_back(std::move(d));
  }
}

ArapInterpolator::~ArapInterpolator() = default;

Positions ArapInterpolator::at(double t) {
  if (!std::isfinite(t)) throw InvalidInput("t must be finite (got " + std::to_string(t) + ")");
  Positions out = linear_interpolate(source_, target_, t);  // isolated vertices keep this
  for (auto& d : pieces_) {
    const Mesh& m = d->piece.mesh;
    const Faces& PF = m.faces();
    const int n = m.num_vertices() - 1;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * n);
    for (int f = 0; f < PF.rows(); ++f) {
      const Eigen::Matrix2d A = Eigen::Rotation2Dd(t * d->theta[f]).toRotationMatrix() *
                                ((1 - t) * Eigen::Matrix2d::Identity() + t * d->stretch[f]);
      for (int c = 0; c < 3; ++c) {
        const int v = PF(f, c) - 1;
        if (v < 0) continue;
        const Eigen::Vector2d gc = d->grad[f].row(c).transpose();
        rhs[v] += d->area[f] * A.row(0).dot(gc);
        rhs[n + v] += d->area[f] * A.row(1).dot(gc);
      }
    }
    Positions X = Positions::Zero(m.num_vertices(), 2);
    if (n > 0) {
      d->chol->solve(rhs.data(), rhs.data(), 2);
      for (int v = 1; v <= n; ++v) X.row(v) << rhs[v - 1], rhs[n + v - 1];
    }
    const Eigen::Vector2d shift = (1 - t) * d->c0 + t * d->c1 - area_centroid(X, PF);
    for (size_t k = 0; k < d->piece.vertices.size(); ++k)
      out.row(d->piece.vertices[k]) = X.row(k) + shift.transpose();
  }
  return out;
}

}  // namespace bdinterp
