#include <gtest/gtest.h>

#include "bdinterp/mesh.h"
#include "test_checks.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

using testing::expect_invalid;

Faces faces(std::initializer_list<std::array<int, 3>> rows) {
  Faces F(static_cast<int>(rows.size()), 3);
  int r = 0;
  for (const auto& row : rows) F.row(r++) << row[0], row[1], row[2];
  return F;
}

TEST(Mesh, EdgeCountsFollowEuler) {
  const auto m = testing::jittered_grid(7, 5);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  // Disk: V - E + F = 1.
  EXPECT_EQ(mesh.num_vertices() - mesh.num_edges() + mesh.num_faces(), 1);
  EXPECT_EQ(mesh.num_pieces(), 1);
  ASSERT_EQ(mesh.boundary_loops().size(), 1u);
  EXPECT_EQ(mesh.boundary_loops()[0].size(), 2u * (7 + 5));
  // Every edge is opposite the corner that FE says, in each adjacent face.
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edges()(f, c);
      const int a = m.F(f, (c + 1) % 3), b = m.F(f, (c + 2) % 3);
      EXPECT_EQ(mesh.edges()(e, 0), std::min(a, b));
      EXPECT_EQ(mesh.edges()(e, 1), std::max(a, b));
      EXPECT_TRUE(mesh.edge_faces()(e, 0) == f || mesh.edge_faces()(e, 1) == f);
    }
  }
}

TEST(Mesh, RejectsBadIndices) {
  expect_invalid([] { Mesh(faces({{0, 1, 5}}), 3); }, "face 0 has vertex index 5 out of range");
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {1, 1, 2}}), 3); }, "face 1 repeats a vertex");
  expect_invalid([] { Mesh(faces({{0, -1, 2}}), 3); }, "out of range");
}

TEST(Mesh, RejectsNonManifoldEdgeAndOrientation) {
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}), 5); },
                 "edge (0, 1) is shared by 3 faces");
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {0, 1, 3}}), 4); }, "orientation is inconsistent");
}

TEST(Mesh, RejectsBowtieVertex) {
  // Two triangles sharing only vertex 0.
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {0, 3, 4}}), 5); }, "vertex 0 is non-manifold");
}

TEST(Mesh, SplitsPiecesAndRejectsHoles) {
  const auto m = testing::jittered_grid(2, 2);
  // Two copies side by side: two pieces.
  Faces two(2 * m.F.rows(), 3);
  two << m.F, (m.F.array() + 9).matrix();
  const Mesh mesh(two, 18);
  EXPECT_EQ(mesh.num_pieces(), 2);
  EXPECT_EQ(split_into_disks(mesh).size(), 2u);

  // A 3x3 grid with the middle cell's two faces removed has a hole.
  const auto g = testing::jittered_grid(3, 3);
  Faces holed(g.F.rows() - 2, 3);
  for (int f = 0, k = 0; f < g.F.rows(); ++f)
    if (f / 2 != 4) holed.row(k++) = g.F.row(f);
  const Mesh with_hole(holed, 16);
  expect_invalid([&] { split_into_disks(with_hole); }, "2 boundary loops");
}

TEST(Mesh, IsolatedVerticesBelongToNoPiece) {
  const Mesh mesh(faces({{0, 1, 2}}), 4);
  EXPECT_TRUE(mesh.is_isolated_vertex(3));
  EXPECT_EQ(mesh.piece_of_vertex(3), -1);
}

}  // namespace
}  // namespace bdinterp
