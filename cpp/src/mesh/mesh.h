// Immutable topology of a triangle mesh: edges, face<->edge incidence, boundary, connected pieces.
// Construction validates the connectivity and throws InvalidInput naming the offending elements.
#pragma once

#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {

class Mesh {
 public:
  // F: #F by 3 vertex indices in [0, num_vertices). Requires: no repeated index within a face, every
  // edge shared by at most two faces with opposite orientation, every vertex's faces forming one fan.
  // Vertices referenced by no face are allowed ("isolated"); they belong to no piece.
  Mesh(const Faces& F, int num_vertices);

  int num_vertices() const { return num_vertices_; }
  int num_faces() const { return static_cast<int>(F_.rows()); }
  int num_edges() const { return static_cast<int>(E_.rows()); }
  const Faces& faces() const { return F_; }
  // #E by 2: the two vertices of each edge, smaller index first.
  const Edges& edges() const { return E_; }
  // #F by 3: FE(f, c) is the edge opposite corner c of face f (joining F(f,c+1) and F(f,c+2)).
  const Faces& face_edges() const { return FE_; }
  // #E by 2: the faces on either side of each edge; the second is -1 on the boundary.
  const Edges& edge_faces() const { return EF_; }
  // The face across edge e from face f (f must be one of e's faces); -1 on the boundary.
  int opposite_face(int e, int f) const { return EF_(e, 0) == f ? EF_(e, 1) : EF_(e, 0); }
  // The corner of face f opposite its edge e (e must be an edge of f).
  int corner_of_edge(int f, int e) const { return FE_(f, 0) == e ? 0 : (FE_(f, 1) == e ? 1 : 2); }
  // One step of a breadth-first walk over the dual graph (faces adjacent through shared edges):
  // `face` is reached from `parent` across the edge opposite corner `face_corner` of face and
  // `parent_corner` of parent.
  struct DualStep {
    int face, parent, face_corner, parent_corner;
  };
  // Breadth-first order over the dual graph from the faces `roots` (all at distance 0): every face
  // reachable from them, except the roots, with the face it is first reached from. Faces of one
  // parent come in the order of its corners.
  std::vector<DualStep> dual_walk(const std::vector<int>& roots) const;
  // A face farthest (in dual steps) from the boundary (the last one a walk from the boundary faces
  // reaches): short dual paths to every face of its piece. Face 0 on a closed mesh.
  int central_face() const;
  // The faces at vertex v, each once (none for an isolated vertex), clockwise round v for
  // counter-clockwise faces: a closed fan from its lowest face, an open one from end to end. A range
  // walked across the edges at v, so no list is stored (peak memory: docs/BENCHMARKS.md).
  class FaceRange {
   public:
    struct iterator {
      const Mesh* mesh;
      int v, start, f;
      int operator*() const { return f; }
      iterator& operator++() {
        f = mesh->next_round(f, v);
        if (f == start) f = -1;
        return *this;
      }
      bool operator!=(const iterator& o) const { return f != o.f; }
    };
    FaceRange(const Mesh* mesh, int v) : mesh_(mesh), v_(v) {}
    iterator begin() const { return {mesh_, v_, mesh_->fan_start_[v_], mesh_->fan_start_[v_]}; }
    iterator end() const { return {mesh_, v_, mesh_->fan_start_[v_], -1}; }
    int size() const;

   private:
    const Mesh* mesh_;
    int v_;
  };
  FaceRange vertex_faces(int v) const { return FaceRange(this, v); }
  // The corner of face f at its vertex v (v must be a vertex of f).
  int corner_of_vertex(int f, int v) const { return F_(f, 0) == v ? 0 : (F_(f, 1) == v ? 1 : 2); }
  // Whether the faces at v with keep(f) form at most one fan (are joined across the edges at v):
  // true for every vertex of a Mesh with all faces kept; false where removing faces pinches v.
  template <typename Keep>
  bool one_fan_at(int v, Keep keep) const;
  bool is_boundary_vertex(int v) const { return boundary_vertex_[v]; }
  bool is_isolated_vertex(int v) const { return vertex_piece_[v] < 0; }

  // Connected pieces (through shared edges). piece_of_face(f) / piece_of_vertex(v) in [0, num_pieces),
  // -1 for isolated vertices.
  int num_pieces() const { return num_pieces_; }
  int piece_of_face(int f) const { return face_piece_[f]; }
  int piece_of_vertex(int v) const { return vertex_piece_[v]; }
  // Closed boundary loops, each a list of vertices in order; loop_piece(k) gives its piece.
  const std::vector<std::vector<int>>& boundary_loops() const { return loops_; }
  int loop_piece(int k) const { return loop_piece_[k]; }

 private:
  void build_edges();
  void find_fan_starts();
  // The face after / before f round its vertex v, across an edge of f at v; -1 past the boundary.
  int next_round(int f, int v) const { return opposite_face(FE_(f, (corner_of_vertex(f, v) + 2) % 3), f); }
  int previous_round(int f, int v) const { return opposite_face(FE_(f, (corner_of_vertex(f, v) + 1) % 3), f); }
  std::vector<int> chain_boundary();  // next vertex along the boundary, -1 inside
  void find_pieces();
  void check_fans() const;
  void collect_loops(const std::vector<int>& next_on_boundary);

  int num_vertices_;
  Faces F_;
  Edges E_;
  Faces FE_;
  Edges EF_;
  std::vector<int> fan_start_;  // per vertex: where vertex_faces starts (an open fan's end), -1 if isolated
  std::vector<bool> boundary_vertex_;
  int num_pieces_ = 0;
  std::vector<int> face_piece_, vertex_piece_;
  std::vector<std::vector<int>> loops_;
  std::vector<int> loop_piece_;
};

template <typename Keep>
bool Mesh::one_fan_at(int v, Keep keep) const {
  int runs = 0, first = -1;  // runs of kept faces in fan order
  bool last_kept = false;
  for (int f : vertex_faces(v)) {
    const bool kept = keep(f);
    if (kept && !last_kept) ++runs;
    if (first < 0) first = f;
    last_kept = kept;
  }
  // Round an inner vertex the fan closes: a run through its last and first faces is one.
  if (runs > 1 && !is_boundary_vertex(v) && last_kept && keep(first)) --runs;
  return runs <= 1;
}

// A connected piece extracted as a mesh of its own. `vertices` maps local to global vertex indices,
// `faces` local to global face indices.
struct Piece {
  Mesh mesh;
  std::vector<int> vertices;
  std::vector<int> faces;
};

// The interior vertices of a disk (neither on the boundary nor isolated), numbered in increasing
// vertex order, and the positions of the entries of their vertex-adjacency matrix in its lower
// triangle stored by compressed columns (rows sorted, diagonal first): the sparsity of the
// flattening's Hessian, which the layout reuses.
struct InteriorPattern {
  std::vector<int> index;     // #V: interior number, -1 for boundary and isolated vertices
  std::vector<int> vertex;    // #interior: the vertex of each interior number
  std::vector<int> diag_pos;  // #interior: position of the diagonal entry
  std::vector<int> edge_pos;  // #E: position of the entry of an edge between interior vertices, else -1
  int size() const { return static_cast<int>(vertex.size()); }
};
// col_ptr (#interior + 1) and rows (nnz) receive the compressed-column pattern itself.
InteriorPattern interior_pattern(const Mesh& disk, std::vector<int>& col_ptr, std::vector<int>& rows);
// The lower compressed-column pattern (col_ptr, rows) of a symmetric matrix over the unknowns
// of_vertex (#V, values in [0, n) or -1) of `mesh`: a diagonal per unknown and an entry per pair of
// different unknowns joined by an edge. In the result, index = of_vertex, vertex = each unknown's
// lowest vertex, edge_pos = the entry of each edge (-1 inside one unknown or at a fixed end); built
// by SymmetricPattern. interior_pattern() is this over the interior numbering. Throws InvalidInput
// if an unknown has no vertex.
InteriorPattern unknowns_pattern(const Mesh& mesh, const std::vector<int>& of_vertex, int n,
                                 std::vector<int>& col_ptr, std::vector<int>& rows);

// Splits `mesh` into its pieces and checks each is a topological disk (exactly one boundary loop);
// throws InvalidInput for a piece with holes or without boundary.
std::vector<Piece> split_into_disks(const Mesh& mesh);
// The same but allowing holes (pieces with several boundary loops); throws only for closed pieces.
std::vector<Piece> split_into_pieces(const Mesh& mesh);

}  // namespace bdinterp
