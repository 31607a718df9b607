#include "legality.h"

#include <algorithm>
#include <cmath>

#include "core/components.h"
#include "quadrics.h"

namespace dynpm::simplification {

namespace {

constexpr double kPi = 3.14159265358979323846;

uint64_t edge_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t{a} << 32) | b;
}

}  // namespace

bool second_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1,
                                std::span<const uint32_t> edge_faces, VertexMarks& marks) {
  // Mark v1's second-order neighbours, then the corners of the edge's faces with another
  // stamp; no corner of v0's faces may still carry the first.
  const uint32_t in_v1_ring = marks.begin(), in_edge_face = in_v1_ring + 1;
  for (uint32_t f : mesh.faces_of(v1))
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex) marks.set(z, in_v1_ring, in_v1_ring);
  for (uint32_t f : edge_faces)
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex) marks.set(z, in_edge_face, in_v1_ring);
  for (uint32_t f : mesh.faces_of(v0))
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex && z != v0 && z != v1 && marks.get(z, in_v1_ring) == in_v1_ring)
        return false;
  return true;
}

bool first_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1) {
  std::vector<uint32_t> n0, n1;
  mesh.neighbours(v0, n0);
  mesh.neighbours(v1, n1);
  for (uint32_t z : n0) {
    if (z == v1 || std::find(n1.begin(), n1.end(), z) == n1.end()) continue;
    bool shared = false;
    for (uint32_t f : mesh.faces_of(v0)) {
      const Face& face = mesh.face(f);
      shared |= face.contains(v1) && face.contains(z);
    }
    if (!shared) return false;
  }
  return true;
}

FeatureEdges::FeatureEdges(const Topology& input, const SimplifyOptions& options)
    : part_ids_(input.part_ids), keep_part_boundaries_(options.keep_part_boundaries) {
  for (const Edge& e : options.feature_edges) user_.insert(edge_key(e.a, e.b));
}

bool FeatureEdges::is_feature_edge(uint32_t a, uint32_t b, std::span<const uint32_t> faces) const {
  if (faces.size() >= 3) return true;  // non-manifold: shells meeting in a T-joint
  if (faces.size() == 2 && keep_part_boundaries_ && part_ids_[faces[0]] != part_ids_[faces[1]])
    return true;
  return !user_.empty() && user_.count(edge_key(a, b)) != 0;
}

CollapseRules::CollapseRules(const Topology& input, const SimplifyOptions& options,
                             const CollapseMesh& mesh, const KeyStepQuadrics& key_steps)
    : input_(input),
      options_(options),
      mesh_(mesh),
      key_steps_(key_steps),
      features_(input, options),
      cos_max_rotation_(std::cos(options.max_normal_rotation_degrees * kPi / 180.0)) {}

bool CollapseRules::optimal() const { return options_.placement == Placement::kOptimal; }

void CollapseRules::classify_vertices(const Adjacency& adjacency) {
  const uint32_t n = input_.vertex_count;
  std::vector<uint8_t> boundary_edges(n, 0), feature_edges(n, 0);
  for (size_t e = 0; e < adjacency.edge_count(); ++e) {
    const Edge edge = adjacency.edge(e);
    const auto faces = adjacency.faces_of_edge(e);
    auto bump = [](uint8_t& c) { c = static_cast<uint8_t>(std::min(c + 1, 255)); };
    if (faces.size() == 1) {
      bump(boundary_edges[edge.a]), bump(boundary_edges[edge.b]);
    } else if (features_.is_feature_edge(edge.a, edge.b, faces)) {
      bump(feature_edges[edge.a]), bump(feature_edges[edge.b]);
    }
  }
  class_.assign(n, VertexClass::kInterior);
  for (uint32_t v = 0; v < n; ++v) {
    const uint8_t kind = adjacency.vertex_kind(v);
    const bool pinched = (kind & kNonManifoldFan) && !(kind & kOnNonManifoldEdge);
    if (pinched || (boundary_edges[v] && feature_edges[v]) || boundary_edges[v] > 2 ||
        feature_edges[v] > 2 || boundary_edges[v] == 1 || feature_edges[v] == 1)
      class_[v] = VertexClass::kLocked;
    else if (feature_edges[v] == 2)
      class_[v] = VertexClass::kFeature;
    else if (boundary_edges[v] == 2)
      class_[v] = VertexClass::kBoundary;
  }
  for (uint32_t v : options_.locked_vertices)
    if (v < n) class_[v] = VertexClass::kLocked;

  // Connected components, for (P3): a component keeps at least 3 or 4 vertices. Numbered 0, 1, …
  // so that the live counts take one entry per component, not per vertex.
  size_t components = 0;
  component_ = connected_components(input_, components);
  component_live_.assign(components, 0);
  for (uint32_t v = 0; v < n; ++v)
    if (mesh_.vertex_alive(v)) ++component_live_[component_[v]];
  if (component_live_.size() <= 65536) {  // 2 B per vertex instead of 4 for the whole run
    small_component_.assign(component_.begin(), component_.end());
    std::vector<uint32_t>().swap(component_);
  }
}

// The faces of one edge, seen from v0's face list.
struct CollapseRules::EdgeFaces {
  std::array<uint32_t, 4> faces{};
  uint32_t count = 0;
  bool diagonal = false;  // v0 and v1 are opposite corners of some quad
  bool too_many = false;  // more than 4 faces
  std::span<const uint32_t> span() const { return {faces.data(), count}; }
};

CollapseRules::EdgeFaces CollapseRules::edge_faces(uint32_t v0, uint32_t v1) const {
  EdgeFaces edge;
  for (uint32_t f : mesh_.faces_of(v0)) {
    const Face& face = mesh_.face(f);
    const int i1 = corner_of(face, v1);
    if (i1 < 0) continue;
    const int d = face.degree();
    const int i0 = corner_of(face, v0);
    if (face.v[(i0 + 1) % d] != v1 && face.v[(i0 + d - 1) % d] != v1) edge.diagonal = true;
    if (edge.count == edge.faces.size()) {
      edge.too_many = true;
      continue;
    }
    edge.faces[edge.count++] = f;
  }
  return edge;
}

// A vanishing triangle (v0, v1, w) merges its edges (v0, w) and (v1, w) into one. Where both
// are boundary or feature edges, the triangle is its sheet's (or its part's) last face between
// them, and the collapse would delete it there instead of sliding along them: a rib's last
// triangle leaves its T-joint (the joint drops to two faces, the rib is gone), a part enclosed
// by another loses its last triangle (the part is gone), two boundary or feature lines fuse.
bool CollapseRules::keeps_every_sheet(uint32_t v0, uint32_t v1, const EdgeFaces& edge) const {
  // An interior v0 has no boundary or feature edge, and never gets one: a collapse hands a
  // vertex only edges it had or edges of interior vertices. User feature edges are pairs a
  // collapse can bring together, so then every triangle is looked at.
  if (class_[v0] == VertexClass::kInterior && !features_.has_user_edges()) return true;
  // The faces holding the edge (a, b), up to five (three or more make it a feature anyway).
  auto faces_of_edge = [this](uint32_t a, uint32_t b, std::array<uint32_t, 5>& out) {
    uint32_t n = 0;
    for (uint32_t f : mesh_.faces_of(a)) {
      const Face& face = mesh_.face(f);
      const int d = face.degree(), i = corner_of(face, a);
      if ((face.v[(i + 1) % d] == b || face.v[(i + d - 1) % d] == b) && n < out.size())
        out[n++] = f;
    }
    return std::span<const uint32_t>(out.data(), n);
  };
  std::array<uint32_t, 5> scratch;
  for (uint32_t k = 0; k < edge.count; ++k) {
    const Face& face = mesh_.face(edge.faces[k]);
    if (!face.is_triangle()) continue;
    uint32_t w = kNoVertex;
    for (int c = 0; c < 3; ++c)
      if (face.v[c] != v0 && face.v[c] != v1) w = face.v[c];
    auto constrained = [&](uint32_t a) {
      const auto faces = faces_of_edge(a, w, scratch);
      return faces.size() == 1 || features_.is_feature_edge(a, w, faces);
    };
    if (constrained(v0) && constrained(v1)) return false;
  }
  return true;
}

// Whether a face stays sound in key step k when vertex `moved` goes to `target` and vertex
// `skip` leaves it (a quad of the collapsed edge becoming a triangle): its normal turns by no
// more than the limit, it keeps an area, and a convex quad stays convex.
bool CollapseRules::face_stays_sound(const Face& face, size_t k, uint32_t skip, uint32_t moved,
                                     Vec3 target) const {
  Vec3 before[4], after[4];
  const int d = face.degree();
  int n = 0;
  for (int c = 0; c < d; ++c) {
    const uint32_t v = face.v[c];
    before[c] = key_steps_.position(v, k);
    if (v == skip) continue;
    after[n++] = v == moved ? target : before[c];
  }
  const Vec3 old_normal = doubled_vector_area(before, d);
  const Vec3 new_normal = doubled_vector_area(after, n);
  // Compared squared, without square roots: this runs for every moved face in every key step.
  const double new_squared = dot(new_normal, new_normal), old_squared = dot(old_normal, old_normal);
  const double least_area = 1e-12 * key_steps_.diagonal() * key_steps_.diagonal();
  if (new_squared <= least_area * least_area) return false;  // no area left
  if (old_squared > 0) {  // folds over: cos(angle) < cos_max_rotation_
    const double cosine_times_lengths = dot(old_normal, new_normal);
    const double bound_squared = cos_max_rotation_ * cos_max_rotation_ * old_squared * new_squared;
    const bool below = cos_max_rotation_ >= 0
                           ? cosine_times_lengths < 0 ||
                                 cosine_times_lengths * cosine_times_lengths < bound_squared
                           : cosine_times_lengths < 0 &&
                                 cosine_times_lengths * cosine_times_lengths > bound_squared;
    if (below) return false;
  }
  if (n == 4 && quad_is_convex(before, old_normal) && !quad_is_convex(after, new_normal))
    return false;
  return true;
}

// No moved face may fold over or degenerate in any key step.
bool CollapseRules::no_face_folds(uint32_t v0, uint32_t v1,
                                  const std::vector<Vec3>& placement) const {
  for (size_t k = 0; k < key_steps_.key_count(); ++k) {
    for (uint32_t f : mesh_.faces_of(v0)) {
      const Face& face = mesh_.face(f);
      const bool on_edge = face.contains(v1);
      if (on_edge && face.is_triangle()) continue;  // vanishes
      // On the edge: v0 leaves the quad (v1 may move); elsewhere v0 goes to v1's place.
      const Vec3 target = placement.empty() ? key_steps_.position(v1, k) : placement[k];
      if (!face_stays_sound(face, k, on_edge ? v0 : kNoVertex, on_edge ? v1 : v0, target))
        return false;
    }
    if (!optimal()) continue;
    for (uint32_t f : mesh_.faces_of(v1)) {  // v1 itself moves
      const Face& face = mesh_.face(f);
      if (!face.contains(v0) && !face_stays_sound(face, k, kNoVertex, v1, placement[k]))
        return false;
    }
  }
  return true;
}

// Every rule of the collapse v0 → v1, cheapest first; each is a pure test of the mesh as it is
// now, except (P1*), which stamps `marks`.
bool CollapseRules::allows(uint32_t v0, uint32_t v1, VertexMarks& marks,
                           std::vector<Vec3>& placement) const {
  // An edge of at most four faces, not a quad's diagonal.
  const EdgeFaces edge = edge_faces(v0, v1);
  if (edge.count == 0 || edge.diagonal || edge.too_many) return false;
  // The edge kind the vertex classes ask for (kCanCollapse; (P2) by construction).
  const Along along = can_collapse(class_[v0], class_[v1]);
  if (along == Along::kBoundaryEdge && edge.count != 1) return false;
  if (along == Along::kFeatureEdge && !features_.is_feature_edge(v0, v1, edge.span())) return false;
  // (P3): a component keeps more than 4 vertices, or more than 3 at a boundary.
  const bool at_border =
      class_[v0] != VertexClass::kInterior || class_[v1] != VertexClass::kInterior;
  if (component_live(component_of(v0)) <= (at_border ? 3u : 4u)) return false;
  // No sheet or part may lose its last face between two boundary or feature edges.
  if (!keeps_every_sheet(v0, v1, edge)) return false;
  // (P1*): otherwise the collapse leaves a vertex of valence two (paper Fig. 4 and 5).
  if (!second_order_neighbours_ok(mesh_, v0, v1, edge.span(), marks)) return false;
  // No moved face folds over, loses its area or stops being convex, in any key step (with
  // optimal placement, at v1's new positions).
  if (optimal())
    key_steps_.collapse_error(v0, v1, class_[v1], placement);
  else
    placement.clear();
  return no_face_folds(v0, v1, placement);
}

}  // namespace dynpm::simplification
