#include "mesh/mesh.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <numeric>
#include <sstream>

#include "linalg/sparse_cholesky.h"

namespace bdinterp {
namespace {

std::string edge_name(int a, int b) {
  std::ostringstream s;
  s << "(" << std::min(a, b) << ", " << std::max(a, b) << ")";
  return s.str();
}

// Union-find over faces, used to find connected pieces.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

void check_face_indices(const Faces& F, int num_vertices) {
  if (num_vertices <= 0) throw InvalidInput("mesh has no vertices");
  if (F.rows() == 0) throw InvalidInput("mesh has no faces");
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = F(f, c);
      if (v < 0 || v >= num_vertices) {
        std::ostringstream s;
        s << "vertex index " << v << " out of range [0, " << num_vertices << ")";
        throw InvalidInput(Where::of_face(f), s.str());
      }
    }
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2)) {
      std::ostringstream s;
      s << "repeats a vertex (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2) << ")";
      throw InvalidInput(Where::of_face(f), s.str());
    }
  }
}

}  // namespace

Mesh::Mesh(const Faces& F, int num_vertices) : num_vertices_(num_vertices), F_(F) {
  check_face_indices(F, num_vertices);
  build_edges();
  find_fan_starts();
  const std::vector<int> next_on_boundary = chain_boundary();
  find_pieces();
  check_fans();
  collect_loops(next_on_boundary);
}

void Mesh::build_edges() {
  const Faces& F = F_;
  const int nf = static_cast<int>(F.rows());
  // Half-edges sorted by undirected key; equal keys are the two sides of one edge.
  std::vector<std::pair<std::uint64_t, int>> he(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      he[3 * f + c] = {std::min(a, b) << 32 | std::max(a, b), 3 * f + c};
    }
  }
  std::sort(he.begin(), he.end());
  FE_.resize(nf, 3);
  std::vector<std::array<int, 4>> edges;  // a, b, f0, f1
  edges.reserve(he.size() / 2 + 1);
  for (size_t k = 0; k < he.size();) {
    size_t j = k;
    while (j < he.size() && he[j].first == he[k].first) ++j;
    const int h0 = he[k].second, f0 = h0 / 3;
    const int a = F(f0, (h0 % 3 + 1) % 3), b = F(f0, (h0 % 3 + 2) % 3);
    if (j - k > 2) {
      std::ostringstream s;
      s << "its edge " << edge_name(a, b) << " is shared by " << (j - k) << " faces (";
      for (size_t q = k; q < j; ++q) s << (q > k ? ", " : "") << he[q].second / 3;
      s << "): the mesh is not manifold";
      throw InvalidInput(Where::of_face(f0), s.str());
    }
    int f1 = -1;
    if (j - k == 2) {
      const int h1 = he[k + 1].second;
      f1 = h1 / 3;
      if (F(f1, (h1 % 3 + 1) % 3) == a) {
        std::ostringstream s;
        s << "traverses edge " << edge_name(a, b) << " in the same direction as face " << f1
          << ": face orientation is inconsistent";
        throw InvalidInput(Where::of_face(f0), s.str());
      }
    }
    for (size_t q = k; q < j; ++q) FE_(he[q].second / 3, he[q].second % 3) = static_cast<int>(edges.size());
    edges.push_back({std::min(a, b), std::max(a, b), f0, f1});
    k = j;
  }
  E_.resize(static_cast<int>(edges.size()), 2);
  EF_.resize(static_cast<int>(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) {
    E_.row(e) << edges[e][0], edges[e][1];
    EF_.row(e) << edges[e][2], edges[e][3];
  }
}

std::vector<int> Mesh::chain_boundary() {
  // Boundary half-edges: each boundary vertex must start exactly one (else its faces form several fans).
  boundary_vertex_.assign(num_vertices_, false);
  std::vector<int> next_on_boundary(num_vertices_, -1);
  for (int e = 0; e < num_edges(); ++e) {
    if (EF_(e, 1) >= 0) continue;
    const int f = EF_(e, 0), c = corner_of_edge(f, e);
    const int a = F_(f, (c + 1) % 3), b = F_(f, (c + 2) % 3);  // boundary walked with the face on the left
    if (next_on_boundary[a] >= 0) {
      std::ostringstream s;
      s << "non-manifold: its faces form more than one fan";
      throw InvalidInput(Where::of_vertex(a), s.str());
    }
    next_on_boundary[a] = b;
    boundary_vertex_[a] = boundary_vertex_[b] = true;
  }
  return next_on_boundary;
}

void Mesh::find_pieces() {
  const int nf = num_faces();
  DisjointSets sets(nf);
  for (int e = 0; e < num_edges(); ++e)
    if (EF_(e, 1) >= 0) sets.unite(EF_(e, 0), EF_(e, 1));
  face_piece_.assign(nf, -1);
  std::vector<int> root_piece(nf, -1);
  for (int f = 0; f < nf; ++f) {
    const int r = sets.find(f);
    if (root_piece[r] < 0) root_piece[r] = num_pieces_++;
    face_piece_[f] = root_piece[r];
  }
  vertex_piece_.assign(num_vertices_, -1);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      int& p = vertex_piece_[F_(f, c)];
      if (p >= 0 && p != face_piece_[f]) {
        std::ostringstream s;
        s << "shared by pieces that have no edge in common (non-manifold vertex)";
        throw InvalidInput(Where::of_vertex(F_(f, c)), s.str());
      }
      p = face_piece_[f];
    }
  }
}

void Mesh::find_fan_starts() {
  fan_start_.assign(num_vertices_, -1);
  for (int f = F_.rows() - 1; f >= 0; --f)
    for (int c = 0; c < 3; ++c) fan_start_[F_(f, c)] = f;  // the lowest face at each vertex
  // Back round each vertex to the end of an open fan. The faces round v are a chain or a cycle (an
  // edge has at most two faces, oppositely oriented), so the walk ends within the vertex's faces.
  for (int v = 0; v < num_vertices_; ++v) {
    const int f0 = fan_start_[v];
    if (f0 < 0) continue;
    int end = f0, f = previous_round(f0, v);
    for (; f >= 0 && f != f0; f = previous_round(f, v)) end = f;
    if (f < 0) fan_start_[v] = end;  // else a closed fan: start at its lowest face
  }
}

int Mesh::FaceRange::size() const {
  int n = 0;
  for (iterator i = begin(); i != end(); ++i) ++n;
  return n;
}

void Mesh::check_fans() const {
  std::vector<int> faces_at(num_vertices_, 0);
  for (int f = 0; f < F_.rows(); ++f)
    for (int c = 0; c < 3; ++c) ++faces_at[F_(f, c)];
  for (int v = 0; v < num_vertices_; ++v) {
    if (vertex_faces(v).size() == faces_at[v]) continue;  // the fan from fan_start_ holds them all
    std::ostringstream s;
    s << "non-manifold: its " << faces_at[v] << " faces do not form a single fan";
    throw InvalidInput(Where::of_vertex(v), s.str());
  }
}

void Mesh::collect_loops(const std::vector<int>& next_on_boundary) {
  std::vector<bool> seen(num_vertices_, false);
  for (int v = 0; v < num_vertices_; ++v) {
    if (next_on_boundary[v] < 0 || seen[v]) continue;
    std::vector<int> loop;
    for (int w = v; !seen[w]; w = next_on_boundary[w]) {
      seen[w] = true;
      loop.push_back(w);
    }
    loop_piece_.push_back(vertex_piece_[v]);
    loops_.push_back(std::move(loop));
  }
}

std::vector<Mesh::DualStep> Mesh::dual_walk(const std::vector<int>& roots) const {
  std::vector<bool> seen(num_faces(), false);
  std::deque<int> queue;
  for (int r : roots) {
    if (seen[r]) continue;
    seen[r] = true;
    queue.push_back(r);
  }
  std::vector<DualStep> order;
  order.reserve(num_faces());
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int c = 0; c < 3; ++c) {
      const int e = FE_(f, c), g = opposite_face(e, f);
      if (g < 0 || seen[g]) continue;
      seen[g] = true;
      order.push_back({g, f, corner_of_edge(g, e), c});
      queue.push_back(g);
    }
  }
  return order;
}

int Mesh::central_face() const {
  std::vector<int> boundary_faces;
  for (int e = 0; e < num_edges(); ++e)
    if (EF_(e, 1) < 0) boundary_faces.push_back(EF_(e, 0));
  if (boundary_faces.empty()) return 0;
  const std::vector<DualStep> walk = dual_walk(boundary_faces);
  if (!walk.empty()) return walk.back().face;
  // Every face touches the boundary: the last distinct root.
  std::vector<bool> seen(num_faces(), false);
  int last = boundary_faces.front();
  for (int f : boundary_faces) {
    if (!seen[f]) last = f;
    seen[f] = true;
  }
  return last;
}

namespace {
std::vector<Piece> split(const Mesh& mesh, bool allow_holes) {
  const int np = mesh.num_pieces();
  std::vector<int> loops_per_piece(np, 0);
  for (size_t k = 0; k < mesh.boundary_loops().size(); ++k) ++loops_per_piece[mesh.loop_piece(k)];
  std::vector<std::vector<int>> pf(np), pv(np);
  for (int f = 0; f < mesh.num_faces(); ++f) pf[mesh.piece_of_face(f)].push_back(f);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.piece_of_vertex(v) >= 0) pv[mesh.piece_of_vertex(v)].push_back(v);
  for (int p = 0; p < np; ++p) {
    if (loops_per_piece[p] == 1 || (allow_holes && loops_per_piece[p] > 1)) continue;
    std::ostringstream s;
    s << "piece " << p << " (the piece of this face: faces " << pf[p].front() << ".." << pf[p].back() << ", "
      << pv[p].size() << " vertices) ";
    if (loops_per_piece[p] == 0) {
      s << "has no boundary (a closed surface cannot be flattened)";
    } else {
      s << "has " << loops_per_piece[p] << " boundary loops: pieces with holes are not supported; "
        << "loops start at vertices";
      for (size_t k = 0; k < mesh.boundary_loops().size(); ++k)
        if (mesh.loop_piece(k) == p) s << " " << mesh.boundary_loops()[k].front();
    }
    throw InvalidInput(Where::of_face(pf[p].front()), s.str());
  }
  std::vector<int> local(mesh.num_vertices(), -1);
  // Faces sorted by vertices, as edges are: a pooled face chunk reads lines its own core wrote (BENCHMARKS.md).
  const Faces& G = mesh.faces();
  auto key = [&](int f) {
    std::array<int, 3> k{G(f, 0), G(f, 1), G(f, 2)};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (auto& faces : pf) std::sort(faces.begin(), faces.end(), [&](int a, int b) { return key(a) < key(b); });
  std::vector<Piece> pieces;
  pieces.reserve(np);
  for (int p = 0; p < np; ++p) {
    for (size_t i = 0; i < pv[p].size(); ++i) local[pv[p][i]] = static_cast<int>(i);
    Faces F(static_cast<int>(pf[p].size()), 3);
    for (size_t k = 0; k < pf[p].size(); ++k)
      for (int c = 0; c < 3; ++c) F(k, c) = local[mesh.faces()(pf[p][k], c)];
    pieces.push_back(Piece{Mesh(F, static_cast<int>(pv[p].size())), pv[p], pf[p]});
  }
  return pieces;
}
}  // namespace

std::vector<Piece> split_into_disks(const Mesh& mesh) { return split(mesh, false); }
std::vector<Piece> split_into_pieces(const Mesh& mesh) { return split(mesh, true); }

InteriorPattern unknowns_pattern(const Mesh& mesh, const std::vector<int>& of_vertex, int n,
                                 std::vector<int>& col_ptr, std::vector<int>& rows) {
  InteriorPattern p;
  p.index = of_vertex;
  p.vertex.assign(n, -1);
  for (int v = static_cast<int>(of_vertex.size()) - 1; v >= 0; --v)
    if (of_vertex[v] >= 0) p.vertex[of_vertex[v]] = v;
  for (int k = 0; k < n; ++k)
    if (p.vertex[k] < 0) throw InvalidInput("flatten: unknown " + std::to_string(k) + " has no vertex");
  const Edges& E = mesh.edges();
  std::vector<std::pair<int, int>> ends(E.rows()), joined;  // per edge: its ends' unknowns
  for (int e = 0; e < E.rows(); ++e) {
    ends[e] = {of_vertex[E(e, 0)], of_vertex[E(e, 1)]};
    if (ends[e].first < 0 || ends[e].second < 0 || ends[e].first == ends[e].second) ends[e] = {-1, -1};
    else joined.push_back(ends[e]);
  }
  SymmetricPattern s(n, std::move(joined));  // several edges may join the same two unknowns
  p.diag_pos.assign(s.col_ptr.begin(), s.col_ptr.end() - 1);  // the diagonal comes first in its column
  p.edge_pos.assign(E.rows(), -1);
  for (int e = 0; e < E.rows(); ++e)
    if (ends[e].first >= 0) p.edge_pos[e] = s.position(ends[e].first, ends[e].second);
  col_ptr = std::move(s.col_ptr);
  rows = std::move(s.rows);
  return p;
}

InteriorPattern interior_pattern(const Mesh& disk, std::vector<int>& col_ptr, std::vector<int>& rows) {
  std::vector<int> index(disk.num_vertices(), -1);
  int n = 0;
  for (int v = 0; v < disk.num_vertices(); ++v)
    if (!disk.is_boundary_vertex(v) && !disk.is_isolated_vertex(v)) index[v] = n++;
  return unknowns_pattern(disk, index, n, col_ptr, rows);
}

}  // namespace bdinterp
