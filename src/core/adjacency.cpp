// Derived connectivity: vertex → faces and edge → faces in compressed rows, and the kind of
// each vertex's neighbourhood (interior, boundary, non-manifold). Built without hashing: edges
// are gathered per smaller endpoint from the vertex → face rows, so the work is O(#F) plus a
// small sort per vertex, and the edge order is deterministic.
#include <algorithm>
#include <numeric>

#include "dynpm/core.h"

namespace dynpm {
namespace {

// Corner before and after corner i of a face with `degree` corners.
inline uint32_t next_corner(const Face& f, int i, int degree) { return f.v[(i + 1) % degree]; }
inline uint32_t prev_corner(const Face& f, int i, int degree) {
  return f.v[(i + degree - 1) % degree];
}

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace

uint64_t Adjacency::bytes() const {
  const auto of = [](const auto& v) { return uint64_t{v.capacity()} * sizeof(v[0]); };
  return of(vertex_face_start_) + of(vertex_faces_) + of(vertex_edge_start_) + of(edges_) +
         of(edge_face_start_) + of(edge_faces_) + of(vertex_kind_);
}

Adjacency Adjacency::build(const Topology& topology) {
  Adjacency adj;
  const uint32_t vertex_count = topology.vertex_count;
  const auto& faces = topology.faces;

  // vertex → faces
  adj.vertex_face_start_.assign(size_t{vertex_count} + 1, 0);
  for (const Face& f : faces) {
    for (uint32_t c : f.v) {
      if (c == kNoVertex) continue;
      assert(c < vertex_count && "Adjacency::build needs indices in range: validate() first");
      ++adj.vertex_face_start_[c + 1];
    }
  }
  std::partial_sum(adj.vertex_face_start_.begin(), adj.vertex_face_start_.end(),
                   adj.vertex_face_start_.begin());
  adj.vertex_faces_.resize(adj.vertex_face_start_.back());
  {
    std::vector<uint32_t> fill(adj.vertex_face_start_.begin(), adj.vertex_face_start_.end() - 1);
    for (uint32_t fi = 0; fi < faces.size(); ++fi) {
      const Face& f = faces[fi];
      for (int i = 0; i < 4; ++i) {
        uint32_t c = f.v[i];
        // A corner repeated in one face lists the face once.
        if (c == kNoVertex || std::find(f.v.begin(), f.v.begin() + i, c) != f.v.begin() + i)
          continue;
        adj.vertex_faces_[fill[c]++] = fi;
      }
    }
    // Shrink rows that lost repeated corners.
    std::vector<uint32_t> start(size_t{vertex_count} + 1, 0);
    size_t out = 0;
    for (uint32_t v = 0; v < vertex_count; ++v) {
      start[v] = static_cast<uint32_t>(out);
      for (uint32_t k = adj.vertex_face_start_[v]; k < fill[v]; ++k)
        adj.vertex_faces_[out++] = adj.vertex_faces_[k];
    }
    start[vertex_count] = static_cast<uint32_t>(out);
    adj.vertex_faces_.resize(out);
    adj.vertex_face_start_ = std::move(start);
  }

  // One pass over the vertices: gather every (neighbour w, face) pair around a vertex from its
  // faces, sorted by w. Runs with w > a are the edges (a, w) with their faces; a run of
  // exactly two faces is a manifold edge, which joins those faces into one fan — a vertex
  // whose faces form more than one fan is non-manifold. No hashing, no edge look-up, no
  // allocation per vertex, and a deterministic edge order.
  adj.vertex_kind_.assign(vertex_count, kInteriorVertex);
  adj.vertex_edge_start_.assign(size_t{vertex_count} + 1, 0);
  // Reserved, not grown: each doubling of an array of a megabyte or more would be a fresh
  // mapping, its pages faulted in again. Every corner of a face is one (edge, face) pair; a
  // closed mesh has half as many edges as pairs, a mesh with boundaries a few more.
  const size_t pairs = adj.vertex_faces_.size();
  adj.edge_faces_.reserve(pairs);
  adj.edges_.reserve(pairs / 2 + pairs / 16);
  adj.edge_face_start_.reserve(pairs / 2 + pairs / 16 + 1);
  std::vector<std::pair<uint32_t, uint32_t>> around;  // (neighbour w, index into a's faces)
  std::vector<uint32_t> fan;                          // union-find over a's faces
  auto root = [&fan](uint32_t x) {
    while (fan[x] != x) x = fan[x] = fan[fan[x]];
    return x;
  };
  for (uint32_t a = 0; a < vertex_count; ++a) {
    adj.vertex_edge_start_[a] = static_cast<uint32_t>(adj.edges_.size());
    const auto af = adj.faces_of_vertex(a);
    if (af.empty()) {
      adj.vertex_kind_[a] |= kUnreferencedVertex;
      continue;
    }
    around.clear();
    for (uint32_t k = 0; k < af.size(); ++k) {
      const Face& f = faces[af[k]];
      const int degree = f.degree();
      for (int i = 0; i < degree; ++i) {
        if (f.v[i] != a) continue;
        // Both edges at the corner: with inconsistent orientation one of them may be
        // "previous" in both of its faces.
        for (uint32_t w : {next_corner(f, i, degree), prev_corner(f, i, degree)})
          if (w != a && w != kNoVertex) around.emplace_back(w, k);
      }
    }
    std::sort(around.begin(), around.end());  // faces ascend within a run: af is ascending
    around.erase(std::unique(around.begin(), around.end()), around.end());
    fan.resize(af.size());
    std::iota(fan.begin(), fan.end(), 0u);
    size_t joined = 0;
    for (size_t i = 0; i < around.size();) {
      size_t j = i;
      while (j < around.size() && around[j].first == around[i].first) ++j;
      if (j - i == 2) {
        const uint32_t x = root(around[i].second), y = root(around[i + 1].second);
        if (x != y) fan[x] = y, ++joined;
      }
      if (around[i].first > a) {
        adj.edge_face_start_.push_back(static_cast<uint32_t>(adj.edge_faces_.size()));
        adj.edges_.push_back(Edge{a, around[i].first});
        for (size_t k = i; k < j; ++k) adj.edge_faces_.push_back(af[around[k].second]);
      }
      i = j;
    }
    if (af.size() - joined > 1) adj.vertex_kind_[a] |= kNonManifoldFan;
  }
  adj.edge_face_start_.push_back(static_cast<uint32_t>(adj.edge_faces_.size()));
  adj.vertex_edge_start_[vertex_count] = static_cast<uint32_t>(adj.edges_.size());

  // Boundary and non-manifold edges mark their vertices.
  for (size_t e = 0; e < adj.edges_.size(); ++e) {
    const size_t n = adj.faces_of_edge(e).size();
    const uint8_t flag = n == 1 ? kBoundaryVertex : n >= 3 ? kOnNonManifoldEdge : 0;
    adj.vertex_kind_[adj.edges_[e].a] |= flag;
    adj.vertex_kind_[adj.edges_[e].b] |= flag;
  }
  return adj;
}

std::span<const uint32_t> Adjacency::faces_of_vertex(uint32_t v) const {
  return {vertex_faces_.data() + vertex_face_start_[v],
          vertex_faces_.data() + vertex_face_start_[v + 1]};
}

std::span<const uint32_t> Adjacency::faces_of_edge(size_t e) const {
  return {edge_faces_.data() + edge_face_start_[e], edge_faces_.data() + edge_face_start_[e + 1]};
}

std::span<const Edge> Adjacency::edges_from(uint32_t v) const {
  return {edges_.data() + vertex_edge_start_[v], edges_.data() + vertex_edge_start_[v + 1]};
}

std::optional<size_t> Adjacency::find_edge(uint32_t a, uint32_t b) const {
  if (a > b) std::swap(a, b);
  if (b == kNoVertex || a == b) return std::nullopt;
  auto row = edges_from(a);
  auto it = std::lower_bound(row.begin(), row.end(), b,
                             [](const Edge& e, uint32_t key) { return e.b < key; });
  if (it == row.end() || it->b != b) return std::nullopt;
  return static_cast<size_t>(&*it - edges_.data());
}

TopologyStats topology_stats(const Topology& topology, const Adjacency& adjacency) {
  TopologyStats s;
  s.vertices = topology.vertex_count;
  s.faces = topology.faces.size();
  s.triangles = topology.triangle_count();
  s.quads = topology.quad_count();
  s.edges = adjacency.edge_count();
  s.parts = topology.parts().size();

  UnionFind boundary(topology.vertex_count), components(topology.vertex_count);
  for (size_t e = 0; e < adjacency.edge_count(); ++e) {
    const Edge edge = adjacency.edge(e);
    const size_t n = adjacency.faces_of_edge(e).size();
    components.unite(edge.a, edge.b);
    if (n == 1) {
      ++s.boundary_edges;
      boundary.unite(edge.a, edge.b);
    } else if (n >= 3) {
      ++s.non_manifold_edges;
    }
  }
  for (uint32_t v = 0; v < topology.vertex_count; ++v) {
    const uint8_t kind = adjacency.vertex_kind(v);
    if (kind & kUnreferencedVertex) continue;
    ++s.referenced_vertices;
    if (components.find(v) == v) ++s.components;
    if ((kind & kBoundaryVertex) && boundary.find(v) == v) ++s.boundary_loops;
    if (adjacency.is_feature_vertex(v)) ++s.non_manifold_vertices;
  }
  s.euler_characteristic = static_cast<int64_t>(s.referenced_vertices) -
                           static_cast<int64_t>(s.edges) + static_cast<int64_t>(s.faces);
  return s;
}

}  // namespace dynpm
