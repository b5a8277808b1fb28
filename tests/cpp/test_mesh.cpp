#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "bdinterp/interpolator.h"
#include "mesh/mesh.h"
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
  expect_invalid([] { Mesh(faces({{0, 1, 5}}), 3); }, "face 0: vertex index 5 out of range");
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {1, 1, 2}}), 3); }, "face 1: repeats a vertex");
  expect_invalid([] { Mesh(faces({{0, -1, 2}}), 3); }, "out of range");
}

TEST(Mesh, RejectsNonManifoldEdgeAndOrientation) {
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}), 5); },
                 "face 0: its edge (0, 1) is shared by 3 faces");
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {0, 1, 3}}), 4); }, "orientation is inconsistent");
}

TEST(Mesh, RejectsBowtieVertex) {
  // Two triangles sharing only vertex 0.
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {0, 3, 4}}), 5); }, "vertex 0: non-manifold");
}

TEST(Mesh, PieceLabelsFollowTheLowestVertexOfEachPiece) {
  // The later faces hold the lower vertices; 4 and 9 are in no face; 5 and 8 meet in no face.
  const Eigen::VectorXi labels = piece_labels(faces({{5, 6, 7}, {7, 6, 8}, {2, 3, 1}, {0, 1, 3}}), 10);
  const std::vector<int> got(labels.data(), labels.data() + labels.size());
  EXPECT_EQ(got, (std::vector<int>{0, 0, 0, 0, 1, 2, 2, 2, 2, 3}));
  expect_invalid([] { piece_labels(faces({{0, 1, 2}, {0, 3, 4}}), 5); }, "vertex 0: non-manifold");
  expect_invalid([] { piece_labels(faces({{0, 1, 5}}), 3); }, "out of range");
}

TEST(Mesh, RejectsAVertexWithAClosedAndAnOpenFanInOnePiece) {
  // Vertex 0 is inside the closed fan of faces 0-2 and at the tip of face 5; faces 3 and 4 join
  // both across edges, so it is one piece whose boundary passes 0 once: only the fans tell.
  expect_invalid([] { Mesh(faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {2, 1, 4}, {5, 4, 1}, {0, 4, 5}}), 6); },
                 "vertex 0: non-manifold: its 4 faces do not form a single fan");
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

TEST(Mesh, VertexFacesListEachFaceAtItsThreeVerticesInFanOrder) {
  // A hexagon fan round vertex 0 (faces 0..5) and an isolated vertex 7.
  const Mesh mesh(faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}}), 8);
  const auto list = [&](int v) {
    std::vector<int> out;
    for (int f : mesh.vertex_faces(v)) out.push_back(f);
    return out;
  };
  // Clockwise round v (the faces are counter-clockwise), each face once: the closed fan from its
  // lowest face, an open fan from one end to the other.
  EXPECT_EQ(list(0), (std::vector<int>{0, 5, 4, 3, 2, 1}));
  EXPECT_EQ(list(1), (std::vector<int>{5, 0}));
  EXPECT_EQ(list(4), (std::vector<int>{2, 3}));
  EXPECT_EQ(mesh.vertex_faces(4).size(), 2);
  EXPECT_EQ(mesh.vertex_faces(7).size(), 0);
  EXPECT_EQ(mesh.corner_of_vertex(3, 5), 2);
}

TEST(Mesh, OneFanAtFindsTheVerticesThatRemovedFacesPinch) {
  const Mesh mesh(faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}}), 7);
  const auto without = [](std::vector<int> gone) {
    return [gone](int f) { return std::find(gone.begin(), gone.end(), f) == gone.end(); };
  };
  EXPECT_TRUE(mesh.one_fan_at(0, without({})));          // the closed fan
  EXPECT_TRUE(mesh.one_fan_at(0, without({5})));         // an open fan: 0..4
  EXPECT_TRUE(mesh.one_fan_at(0, without({1, 2})));      // 3, 4, 5, 0 across the edge (0, 1)
  EXPECT_FALSE(mesh.one_fan_at(0, without({1, 4})));     // {2, 3} and {5, 0}
  EXPECT_FALSE(mesh.one_fan_at(0, without({0, 2, 4})));  // three single faces
  EXPECT_TRUE(mesh.one_fan_at(0, without({0, 1, 2, 3, 4})));  // one face left
  EXPECT_TRUE(mesh.one_fan_at(1, without({})));          // a boundary vertex: faces 5, 0
  EXPECT_TRUE(mesh.one_fan_at(1, without({0})));
}

}  // namespace
}  // namespace bdinterp

namespace bdinterp {
namespace {

TEST(Mesh, DualWalkReachesEveryFaceOnceAcrossSharedEdges) {
  const auto m = testing::jittered_grid(9, 7, 1.0, 1.0, 4);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int f = mesh.edge_faces()(e, 0), g = mesh.edge_faces()(e, 1);
    EXPECT_EQ(mesh.opposite_face(e, f), g);
    if (g >= 0) EXPECT_EQ(mesh.opposite_face(e, g), f);
    EXPECT_EQ(mesh.face_edges()(f, mesh.corner_of_edge(f, e)), e);
  }
  const auto walk = mesh.dual_walk({5});
  ASSERT_EQ(static_cast<int>(walk.size()), mesh.num_faces() - 1);
  std::vector<int> order(mesh.num_faces(), -1);
  order[5] = 0;
  for (size_t k = 0; k < walk.size(); ++k) {
    const Mesh::DualStep& s = walk[k];
    EXPECT_EQ(order[s.face], -1) << "face " << s.face << " reached twice";
    EXPECT_GE(order[s.parent], 0) << "parent of " << s.face << " not reached before it";
    order[s.face] = static_cast<int>(k) + 1;
    EXPECT_EQ(mesh.face_edges()(s.face, s.face_corner), mesh.face_edges()(s.parent, s.parent_corner));
  }
  // The central face: as far from the boundary as the walk goes, i.e. in the middle of the grid.
  const int c = mesh.central_face();
  Eigen::RowVector2d centre = Eigen::RowVector2d::Zero();
  for (int k = 0; k < 3; ++k) {
    EXPECT_FALSE(mesh.is_boundary_vertex(m.F(c, k)));
    centre += m.V.row(m.F(c, k)) / 3.0;
  }
  EXPECT_LT((centre - Eigen::RowVector2d(0.5, 0.5)).norm(), 0.25);
}

}  // namespace
}  // namespace bdinterp
