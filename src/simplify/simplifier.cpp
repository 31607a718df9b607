// The simplifier: mixed triangle/quad half-edge collapse over key steps.
//
//   S. Wundrak, T. Henn, A. Stork. Dynamic Progressive Triangle-Quadrilateral Meshes. WSCG 2006.
//     §2 collapse on mixed meshes, (P1*) second-order neighbours, planes of skew quads;
//     §3 one quadric per vertex per animation step, cost = max over steps (method 1*).
//   M. Garland, P. Heckbert. Surface Simplification Using Quadric Error Metrics. SIGGRAPH 1997.
//   H. Hoppe. Progressive Meshes. SIGGRAPH 1996. (P2), (P3), vertex splits.
//   P. Cignoni. Mesh simplification (lecture): lazy heap with temporal marks, boundary quadrics.
//
// Roles kept apart: cost (quadric.h), legality (legality.h + the checks below), the mesh being
// changed (collapse_mesh.h), the queue, and the listener (CollapseListener). Read top to
// bottom: key steps and quadrics, vertex classes, one collapse's cost and legality, the loop,
// the public entry.
//
// The queue is the lecture's lazy heap with temporal marks: every edge the vertex classes allow
// to collapse in some direction is queued once, for its cheaper direction v0 → v1, with that
// cost and the time (collapse count) it was rated. A collapse changes the quadric of v1 only,
// so only v1's edges are re-rated; entries of v0 and v1 rated before that time are stale and
// skipped when popped. Legality is checked when an entry is popped, on the mesh as it is then;
// an illegal entry is dropped (its other direction queued at its own cost), and its vertex is
// marked so that its edges are re-rated as soon as its neighbourhood changes. When the queue
// runs dry before the target, every edge is rated again once: only if that finds no legal
// collapse does the simplifier report that none remains. The queue itself is a radix heap
// (monotone_queue.h); quadrics are kept in floats around their own vertex (quadric.h).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <unordered_set>

#include "collapse_mesh.h"
#include "dynpm/simplify.h"
#include "legality.h"
#include "monotone_queue.h"
#include "parallel.h"
#include "quadric.h"

namespace dynpm {
namespace simplification {
namespace {

constexpr double kPi = 3.14159265358979323846;

uint64_t edge_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t{a} << 32) | b;
}

// The faces of one edge, seen from v0's face list.
struct EdgeFaces {
  std::array<uint32_t, 4> faces{};
  uint32_t count = 0;
  bool diagonal = false;  // v0 and v1 are opposite corners of some quad
  bool too_many = false;  // more than 4 faces
};

// Scratch space for one thread.
struct Scratch {
  explicit Scratch(uint32_t vertex_count) : marks(vertex_count) {}
  std::vector<uint32_t> neighbours;
  std::vector<Vec3> placement;  // per key step, for the collapse under test
  VertexMarks marks;
};

// Vector area × 2 of a face whose corners are given (3 or 4); for a quad the cross product of
// its diagonals, which is also what a skew quad's "area" means.
Vec3 doubled_vector_area(const Vec3* p, int degree) {
  return degree == 3 ? cross(p[1] - p[0], p[2] - p[0]) : cross(p[2] - p[0], p[3] - p[1]);
}

// A quad is convex (and not self-intersecting) when every corner turns the same way as the
// face.
bool quad_is_convex(const Vec3* p, Vec3 normal) {
  for (int i = 0; i < 4; ++i)
    if (dot(cross(p[(i + 1) % 4] - p[i], p[(i + 3) % 4] - p[i]), normal) <= 0) return false;
  return true;
}

class Simplifier {
 public:
  Simplifier(const Topology& topology, const SimplifyOptions& options, CollapseListener* listener)
      : input_(topology), options_(options), listener_(listener), mesh_(topology) {}

  Status load_key_steps(const FrameSource& frames);
  void classify_vertices(const Adjacency& adjacency);
  std::vector<uint8_t> constrained_edges(const Adjacency& adjacency) const;
  void build_quadrics(const std::vector<uint8_t>& constrained);
  Result<SimplifyResult> run(Adjacency adjacency);

 private:
  size_t key_count() const { return key_steps_.size(); }
  Vec3 position(uint32_t v, size_t k) const {
    return load(&positions_[(size_t{v} * key_count() + k) * 3]);
  }
  LocalQuadric& quadric(uint32_t v, size_t k) { return quadrics_[size_t{v} * key_count() + k]; }
  const LocalQuadric& quadric(uint32_t v, size_t k) const {
    return quadrics_[size_t{v} * key_count() + k];
  }
  Quadric merged_quadric(uint32_t v0, uint32_t v1, size_t k) const;
  bool optimal() const { return options_.placement == Placement::kOptimal; }

  bool is_feature_edge(uint32_t a, uint32_t b, std::span<const uint32_t> faces) const;
  EdgeFaces edge_faces(uint32_t v0, uint32_t v1) const;
  double collapse_error(uint32_t v0, uint32_t v1, std::vector<Vec3>& placement) const;
  double half_edge_error(uint32_t v0, uint32_t v1) const;
  std::pair<double, double> half_edge_errors(uint32_t a, uint32_t b) const;
  double cost(uint32_t v0, uint32_t v1, Scratch& s) const;
  bool topology_allows(uint32_t v0, uint32_t v1, const EdgeFaces& edge, Scratch& s) const;
  bool keeps_every_sheet(uint32_t v0, uint32_t v1, const EdgeFaces& edge) const;
  bool face_stays_sound(const Face& face, size_t k, uint32_t skip, uint32_t moved,
                        Vec3 target) const;
  bool geometry_allows(uint32_t v0, uint32_t v1, const std::vector<Vec3>& placement) const;
  bool legal(uint32_t v0, uint32_t v1, Scratch& s) const;

  struct Entry;
  bool stale(const Entry& e) const;
  void rate_edges_of(uint32_t v, Scratch& s, std::vector<Entry>& out,
                     bool larger_only = false) const;
  void rate_all_edges();
  void drop_stale_entries();
  Status collapse(uint32_t v0, uint32_t v1, double error, Scratch& s);
  Status check_mesh(size_t collapse_index) const;
  bool stop_reached(std::string& reason) const;

  const Topology& input_;
  const SimplifyOptions& options_;
  CollapseListener* listener_;
  CollapseMesh mesh_;

  std::vector<size_t> key_steps_;
  std::vector<float>
      positions_;  // #V × #key steps × xyz (vertex-major: one vertex's steps together)
  std::vector<LocalQuadric> quadrics_;  // #V × #key steps, each around its own vertex
  double diagonal_ = 1;
  double cos_max_rotation_ = 0;

  std::vector<VertexClass> class_;
  std::unordered_set<uint64_t> user_features_;
  std::vector<uint32_t> component_, component_live_;  // (P3) per connected component
  TopologyStats initial_stats_;

  // The queue (see the top of this file). time_ counts collapses; changed_[v] is the time v's
  // quadric last changed; an entry rated before that time is stale. One entry per edge, for
  // its cheaper direction v0 → v1; when that is illegal, the other direction is queued at its
  // own cost (one_way marks an entry whose other direction is not allowed or already queued).
  struct Entry {
    float error;
    uint32_t v0, v1;
    uint32_t time : 31;
    uint32_t one_way : 1;
    float key() const { return error; }
  };
  MonotoneQueue<Entry> queue_;
  size_t queue_size_after_cleanup_ = 0;
  std::vector<Entry> fresh_;
  std::vector<uint32_t> changed_;
  std::vector<uint8_t> rejected_;  // an entry of this vertex was dropped as illegal
  uint32_t time_ = 1;

  std::vector<uint32_t> moved_, ring_;
  std::vector<float> record_positions_;
  size_t collapses_ = 0;
  double max_error_done_ = 0;
  uint32_t target_vertices_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Key steps and quadrics

Status Simplifier::load_key_steps(const FrameSource& frames) {
  const size_t steps = frames.step_count();
  if (steps == 0) return Status::error("the animation has no time step");
  if (options_.key_steps.empty()) {
    key_steps_.resize(steps);
    std::iota(key_steps_.begin(), key_steps_.end(), size_t{0});
  } else {
    key_steps_ = options_.key_steps;
    std::sort(key_steps_.begin(), key_steps_.end());
    key_steps_.erase(std::unique(key_steps_.begin(), key_steps_.end()), key_steps_.end());
    for (size_t t : key_steps_)
      if (t >= steps)
        return Status::error("key step " + std::to_string(t) +
                             " does not exist (the animation has " + std::to_string(steps) +
                             " steps)");
  }
  if (optimal() && key_steps_.size() != steps)
    return Status::error(
        "optimal placement moves vertices in every step, so every step must be a "
        "key step (use --key-steps all or half-edge placement)");

  const uint32_t n = input_.vertex_count;
  const size_t k_count = key_steps_.size();
  positions_.resize(size_t{n} * k_count * 3);
  std::vector<float> step(size_t{n} * 3);
  BoundingBox box;
  for (size_t k = 0; k < k_count; ++k) {
    DYNPM_RETURN_IF_ERROR(frames.read_step(key_steps_[k], step));
    box.extend(step);
    for (uint32_t v = 0; v < n; ++v)
      std::copy_n(&step[size_t{v} * 3], 3, &positions_[(size_t{v} * k_count + k) * 3]);
  }
  diagonal_ = box.diagonal() > 0 ? box.diagonal() : 1.0;
  cos_max_rotation_ = std::cos(options_.max_normal_rotation_degrees * kPi / 180.0);
  return {};
}

bool Simplifier::is_feature_edge(uint32_t a, uint32_t b, std::span<const uint32_t> faces) const {
  if (faces.size() >= 3) return true;  // non-manifold: shells meeting in a T-joint
  if (faces.size() == 2 && options_.keep_part_boundaries &&
      input_.part_ids[faces[0]] != input_.part_ids[faces[1]])
    return true;
  return !user_features_.empty() && user_features_.count(edge_key(a, b)) != 0;
}

void Simplifier::classify_vertices(const Adjacency& adjacency) {
  const uint32_t n = input_.vertex_count;
  for (const Edge& e : options_.feature_edges) user_features_.insert(edge_key(e.a, e.b));
  std::vector<uint8_t> boundary_edges(n, 0), feature_edges(n, 0);
  for (size_t e = 0; e < adjacency.edge_count(); ++e) {
    const Edge edge = adjacency.edge(e);
    const auto faces = adjacency.faces_of_edge(e);
    auto bump = [](uint8_t& c) { c = static_cast<uint8_t>(std::min(c + 1, 255)); };
    if (faces.size() == 1) {
      bump(boundary_edges[edge.a]), bump(boundary_edges[edge.b]);
    } else if (is_feature_edge(edge.a, edge.b, faces)) {
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

  // Connected components, for (P3): a component keeps at least 3 or 4 vertices.
  component_.resize(n);
  std::iota(component_.begin(), component_.end(), 0u);
  auto find = [&](uint32_t x) {
    while (component_[x] != x) x = component_[x] = component_[component_[x]];
    return x;
  };
  for (size_t e = 0; e < adjacency.edge_count(); ++e)
    component_[find(adjacency.edge(e).a)] = find(adjacency.edge(e).b);
  for (uint32_t v = 0; v < n; ++v) component_[v] = find(v);  // each vertex's root
  // Numbered 0, 1, … so that the live counts take one entry per component, not per vertex.
  std::vector<uint32_t> number(n, kNoVertex);  // root → component
  component_live_.clear();
  for (uint32_t v = 0; v < n; ++v) {
    uint32_t& c = number[component_[v]];
    if (c == kNoVertex) {
      c = static_cast<uint32_t>(component_live_.size());
      component_live_.push_back(0);
    }
    if (mesh_.vertex_alive(v)) ++component_live_[c];
    component_[v] = c;
  }
}

// Which edges of each face carry a constraint plane: bit c is the edge from corner c to the next
// corner, set when that edge is a boundary or feature edge.
std::vector<uint8_t> Simplifier::constrained_edges(const Adjacency& adjacency) const {
  std::vector<uint8_t> constrained(input_.faces.size(), 0);
  for (size_t e = 0; e < adjacency.edge_count(); ++e) {
    const Edge edge = adjacency.edge(e);
    const auto faces = adjacency.faces_of_edge(e);
    if (faces.size() != 1 && !is_feature_edge(edge.a, edge.b, faces)) continue;
    for (uint32_t f : faces) {
      const Face& face = input_.faces[f];
      const int d = face.degree(), c = corner_of(face, edge.a);
      constrained[f] |=
          static_cast<uint8_t>(1u << (face.v[(c + 1) % d] == edge.b ? c : (c + d - 1) % d));
    }
  }
  return constrained;
}

void Simplifier::build_quadrics(const std::vector<uint8_t>& constrained) {
  const uint32_t n = input_.vertex_count;
  const size_t k_count = key_count();
  quadrics_.assign(size_t{n} * k_count, LocalQuadric{});
  // Gathered per vertex (no two threads write one quadric), in coordinates around the vertex;
  // each face's plane is computed once per corner, which is cheaper than storing a plane per
  // face and step.
  parallel_for(
      size_t{n} * k_count, thread_count(options_.threads), [&](size_t begin, size_t end, unsigned) {
        for (size_t i = begin; i < end; ++i) {
          const uint32_t v = static_cast<uint32_t>(i / k_count);
          const size_t k = i % k_count;
          const Vec3 origin = position(v, k);
          Quadric q;
          for (uint32_t f : mesh_.faces_of(v)) {
            const Face& face = input_.faces[f];
            const int d = face.degree();
            Vec3 p[4];
            for (int c = 0; c < d; ++c) p[c] = position(face.v[c], k) - origin;
            // The face's plane: a triangle's own; for a quad, possibly skew, the mean of its corner
            // normals through its centroid (paper §2). Weighted by area.
            const Vec3 area2 = doubled_vector_area(p, d);
            const double area = 0.5 * length(area2);
            if (area <= 0) continue;
            Vec3 normal = normalized(area2), centre = p[0];
            if (d == 4) {
              Vec3 sum{};
              for (int c = 0; c < 4; ++c)
                sum = sum + normalized(cross(p[(c + 1) % 4] - p[c], p[(c + 3) % 4] - p[c]));
              if (length(sum) > 0) normal = normalized(sum);
              centre = (p[0] + p[1] + p[2] + p[3]) * 0.25;
            }
            q.add_plane(normal, -dot(normal, centre), area);

            // Constraint planes through v's boundary and feature edges in this face,
            // perpendicular to the face, weighted by the squared edge length.
            const int i0 = corner_of(face, v), before = (i0 + d - 1) % d;
            for (int other : {(i0 + 1) % d, before}) {
              const int edge_bit = other == before ? before : i0;
              if (!(constrained[f] & (1u << edge_bit))) continue;
              const Vec3 along = p[other] - p[i0];
              const Vec3 m = normalized(cross(along, normal));
              if (length(m) == 0) continue;
              q.add_plane(m, -dot(m, p[i0]), options_.boundary_weight * dot(along, along));
            }
          }
          quadric(v, k) = LocalQuadric::narrow(q);
        }
      });
}

// ---------------------------------------------------------------------------------------------
// One collapse: cost, topology, geometry

EdgeFaces Simplifier::edge_faces(uint32_t v0, uint32_t v1) const {
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

// Q_t,v0 + Q_t,v1 with its origin at v1's position in key step k.
Quadric Simplifier::merged_quadric(uint32_t v0, uint32_t v1, size_t k) const {
  return quadric(v1, k).widen() +
         quadric(v0, k).widen().translated(position(v1, k) - position(v0, k));
}

// Paper method (1*): the largest error over the key steps, each a weighted RMS distance to the
// planes of (Q_t,v0 + Q_t,v1), at v1's position (half-edge) or at the minimiser (optimal).
double Simplifier::collapse_error(uint32_t v0, uint32_t v1, std::vector<Vec3>& placement) const {
  double worst = 0;
  placement.resize(key_count());
  const bool moves = optimal() && class_[v1] != VertexClass::kLocked;
  for (size_t k = 0; k < key_count(); ++k) {
    const Quadric q = merged_quadric(v0, v1, k);
    const Vec3 p1 = position(v1, k);
    Vec3 offset{};  // from v1's position
    if (moves) {
      if (auto m = q.minimiser()) {
        offset = *m;
      } else if (class_[v1] == VertexClass::kInterior &&
                 q.evaluate(position(v0, k) - p1) < q.evaluate(offset)) {
        offset = position(v0, k) - p1;  // ill-conditioned: the better endpoint
      }
    }
    placement[k] = p1 + offset;
    worst = std::max(worst, q.mean_squared(offset));
  }
  return std::sqrt(worst) / diagonal_;
}

// collapse_error() for half-edge placement, without the placement: v1's own quadric is c at its
// position, v0's is evaluated across the edge.
double Simplifier::half_edge_error(uint32_t v0, uint32_t v1) const {
  double worst = 0;
  for (size_t k = 0; k < key_count(); ++k) {
    const LocalQuadric& q1 = quadric(v1, k);
    const Quadric q0 = quadric(v0, k).widen();
    const double weight = q0.w + double{q1.w};
    if (!(weight > 0)) continue;
    const double moved = q0.evaluate(position(v1, k) - position(v0, k));
    worst = std::max(worst, (moved + double{q1.c}) / weight);
    if (q0.w > 0) worst = std::max(worst, moved / q0.w);  // see half_edge_errors()
  }
  return std::sqrt(worst) / diagonal_;
}

// half_edge_error() of a → b and of b → a at once: the rating of an edge needs both, and the
// quadrics are loaded once.
std::pair<double, double> Simplifier::half_edge_errors(uint32_t a, uint32_t b) const {
  double worst_ab = 0, worst_ba = 0;
  for (size_t k = 0; k < key_count(); ++k) {
    const Quadric qa = quadric(a, k).widen(), qb = quadric(b, k).widen();
    const double weight = qa.w + qb.w;
    if (!(weight > 0)) continue;
    const Vec3 d = position(b, k) - position(a, k);
    const double moved_a = qa.evaluate(d), moved_b = qb.evaluate(Vec3{} - d);
    worst_ab = std::max(worst_ab, (moved_a + qb.c) / weight);
    worst_ba = std::max(worst_ba, (moved_b + qa.c) / weight);
    // Never less than the moved vertex's own mean squared distance: divided by the merged
    // weight alone, a light vertex (a boundary corner) next to a heavy one (which has absorbed
    // many collapses) would be swallowed at almost no cost, cutting the corner.
    if (qa.w > 0) worst_ab = std::max(worst_ab, moved_a / qa.w);
    if (qb.w > 0) worst_ba = std::max(worst_ba, moved_b / qb.w);
  }
  return {std::sqrt(worst_ab) / diagonal_, std::sqrt(worst_ba) / diagonal_};
}

double Simplifier::cost(uint32_t v0, uint32_t v1, Scratch& s) const {
  return optimal() ? collapse_error(v0, v1, s.placement) : half_edge_error(v0, v1);
}

bool Simplifier::topology_allows(uint32_t v0, uint32_t v1, const EdgeFaces& edge,
                                 Scratch& s) const {
  // (P3): a component keeps more than 4 vertices, or more than 3 at a boundary.
  const bool at_border =
      class_[v0] != VertexClass::kInterior || class_[v1] != VertexClass::kInterior;
  if (component_live_[component_[v0]] <= (at_border ? 3u : 4u)) return false;
  // No sheet or part may lose its last face between two boundary or feature edges.
  if (!keeps_every_sheet(v0, v1, edge)) return false;
  // (P1*): otherwise the collapse leaves a vertex of valence two (paper Fig. 4 and 5).
  return second_order_neighbours_ok(mesh_, v0, v1, std::span(edge.faces.data(), edge.count),
                                    s.marks);
}

// A vanishing triangle (v0, v1, w) merges its edges (v0, w) and (v1, w) into one. Where both
// are boundary or feature edges, the triangle is its sheet's (or its part's) last face between
// them, and the collapse would delete it there instead of sliding along them: a rib's last
// triangle leaves its T-joint (the joint drops to two faces, the rib is gone), a part enclosed
// by another loses its last triangle (the part is gone), two boundary or feature lines fuse.
bool Simplifier::keeps_every_sheet(uint32_t v0, uint32_t v1, const EdgeFaces& edge) const {
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
      return faces.size() == 1 || is_feature_edge(a, w, faces);
    };
    if (constrained(v0) && constrained(v1)) return false;
  }
  return true;
}

// Whether a face stays sound in key step k when vertex `moved` goes to `target` and vertex
// `skip` leaves it (a quad of the collapsed edge becoming a triangle): its normal turns by no
// more than the limit, it keeps an area, and a convex quad stays convex.
bool Simplifier::face_stays_sound(const Face& face, size_t k, uint32_t skip, uint32_t moved,
                                  Vec3 target) const {
  Vec3 before[4], after[4];
  const int d = face.degree();
  int n = 0;
  for (int c = 0; c < d; ++c) {
    const uint32_t v = face.v[c];
    before[c] = position(v, k);
    if (v == skip) continue;
    after[n++] = v == moved ? target : before[c];
  }
  const Vec3 old_normal = doubled_vector_area(before, d);
  const Vec3 new_normal = doubled_vector_area(after, n);
  // Compared squared, without square roots: this runs for every moved face in every key step.
  const double new_squared = dot(new_normal, new_normal), old_squared = dot(old_normal, old_normal);
  const double least_area = 1e-12 * diagonal_ * diagonal_;
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
bool Simplifier::geometry_allows(uint32_t v0, uint32_t v1,
                                 const std::vector<Vec3>& placement) const {
  for (size_t k = 0; k < key_count(); ++k) {
    for (uint32_t f : mesh_.faces_of(v0)) {
      const Face& face = mesh_.face(f);
      const bool on_edge = face.contains(v1);
      if (on_edge && face.is_triangle()) continue;  // vanishes
      // On the edge: v0 leaves the quad (v1 may move); elsewhere v0 goes to v1's place.
      const Vec3 target = placement.empty() ? position(v1, k) : placement[k];
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

// Whether v0 may collapse into v1 now: the edge kind the vertex classes ask for, (P3), no sheet
// off a feature, (P1*), and no fold or degenerate face in any key step.
bool Simplifier::legal(uint32_t v0, uint32_t v1, Scratch& s) const {
  const EdgeFaces edge = edge_faces(v0, v1);
  if (edge.count == 0 || edge.diagonal || edge.too_many) return false;
  const Along along = can_collapse(class_[v0], class_[v1]);
  if (along == Along::kBoundaryEdge && edge.count != 1) return false;
  if (along == Along::kFeatureEdge &&
      !is_feature_edge(v0, v1, std::span<const uint32_t>(edge.faces.data(), edge.count)))
    return false;
  if (!topology_allows(v0, v1, edge, s)) return false;
  if (optimal())
    collapse_error(v0, v1, s.placement);
  else
    s.placement.clear();
  return geometry_allows(v0, v1, s.placement);
}

bool Simplifier::stale(const Entry& e) const {
  return changed_[e.v0] > e.time || changed_[e.v1] > e.time;
}

// Every edge at v (with larger_only, those to a larger vertex) that the vertex classes allow in
// some direction, queued for its cheaper allowed direction.
void Simplifier::rate_edges_of(uint32_t v, Scratch& s, std::vector<Entry>& out,
                               bool larger_only) const {
  mesh_.neighbours(v, s.neighbours);
  // The neighbours' quadrics and positions are scattered in memory: ask for all of them before
  // the first is needed, so the cache misses overlap instead of following one another.
  for (uint32_t w : s.neighbours) {
    __builtin_prefetch(&quadrics_[size_t{w} * key_count()]);
    __builtin_prefetch(&positions_[size_t{w} * key_count() * 3]);
  }
  for (uint32_t w : s.neighbours) {
    if (larger_only && w < v) continue;
    const bool forward = can_collapse(class_[v], class_[w]) != Along::kNever;
    const bool backward = can_collapse(class_[w], class_[v]) != Along::kNever;
    if (!forward && !backward) continue;
    if (forward && backward) {
      const auto [there, back] =
          optimal() ? std::pair{cost(v, w, s), cost(w, v, s)} : half_edge_errors(v, w);
      out.push_back(there <= back ? Entry{static_cast<float>(there), v, w, time_, 0}
                                  : Entry{static_cast<float>(back), w, v, time_, 0});
    } else {
      const uint32_t a = forward ? v : w, b = forward ? w : v;
      out.push_back({static_cast<float>(cost(a, b, s)), a, b, time_, 1});
    }
  }
}

// Every edge once, in parallel: at the start, and when the queue runs dry.
void Simplifier::rate_all_edges() {
  const uint32_t n = input_.vertex_count;
  const unsigned threads = thread_count(options_.threads);
  std::vector<std::vector<Entry>> parts(threads);
  std::vector<Scratch> scratch(threads, Scratch(0));
  parallel_for(n, threads, [&](size_t begin, size_t end, unsigned t) {
    for (size_t v = begin; v < end; ++v)
      if (mesh_.vertex_alive(static_cast<uint32_t>(v)))
        rate_edges_of(static_cast<uint32_t>(v), scratch[t], parts[t], true);
  });
  queue_.clear();
  for (auto& part : parts) {
    for (const Entry& e : part) queue_.push(e);
    std::vector<Entry>().swap(part);  // its memory back before the next part is queued
  }
  queue_size_after_cleanup_ = queue_.size();
  std::fill(rejected_.begin(), rejected_.end(), 0);
}

// Stale entries are dropped when the queue has doubled since the last time.
void Simplifier::drop_stale_entries() {
  if (queue_.size() <= 2 * queue_size_after_cleanup_ + 1024) return;
  queue_.remove_if([&](const Entry& e) { return stale(e); });
  queue_size_after_cleanup_ = queue_.size();
}

// ---------------------------------------------------------------------------------------------
// The loop

Status Simplifier::collapse(uint32_t v0, uint32_t v1, double error, Scratch& s) {
  // Optimal placement: s.placement holds v1's new positions, computed with `error`.
  const std::vector<Vec3>& placement = s.placement;

  CollapseRecord record;
  record.error = error;
  mesh_.collapse(v0, v1, record, moved_);
  --component_live_[component_[v0]];
  for (size_t k = 0; k < key_count(); ++k) {
    Quadric q = merged_quadric(v0, v1, k);  // around v1's position
    if (optimal()) {
      const Vec3 before = position(v1, k);
      float* p = &positions_[(size_t{v1} * key_count() + k) * 3];
      p[0] = static_cast<float>(placement[k].x), p[1] = static_cast<float>(placement[k].y),
      p[2] = static_cast<float>(placement[k].z);
      q = q.translated(position(v1, k) - before);  // around the new one
    }
    quadric(v1, k) = LocalQuadric::narrow(q);
  }
  if (optimal())
    record.v1_new_positions = {&positions_[size_t{v1} * key_count() * 3], key_count() * 3};
  changed_[v0] = changed_[v1] = ++time_;  // their queued entries are now stale
  ++collapses_;
  max_error_done_ = std::max(max_error_done_, error);
  if (listener_) listener_->on_collapse(record);
  if (options_.check_every_collapse) DYNPM_RETURN_IF_ERROR(check_mesh(collapses_));

  // v1's quadric changed: re-rate its edges. Neighbours with a dropped entry get another
  // chance, since their surroundings changed.
  fresh_.clear();
  rate_edges_of(v1, s, fresh_);
  mesh_.second_order_neighbours(v1, ring_);
  for (uint32_t w : ring_) {
    if (!rejected_[w]) continue;
    rejected_[w] = 0;
    rate_edges_of(w, s, fresh_);
  }
  for (const Entry& e : fresh_) queue_.push(e);
  drop_stale_entries();
  return {};
}

Status Simplifier::check_mesh(size_t collapse_index) const {
  std::vector<uint32_t> original;
  const Topology now = mesh_.to_topology(input_, original);
  const ValidationReport report = validate(now);
  const std::string where = "after collapse " + std::to_string(collapse_index) + ": ";
  for (const Problem& p : report.problems)
    if (p.severity == Severity::kError) return Status::error(where + p.message);
  const TopologyStats stats = topology_stats(now, Adjacency::build(now));
  if (stats.euler_characteristic != initial_stats_.euler_characteristic)
    return Status::error(where + "Euler characteristic changed from " +
                         std::to_string(initial_stats_.euler_characteristic) + " to " +
                         std::to_string(stats.euler_characteristic));
  if (stats.boundary_loops != initial_stats_.boundary_loops)
    return Status::error(where + "boundary loops changed from " +
                         std::to_string(initial_stats_.boundary_loops) + " to " +
                         std::to_string(stats.boundary_loops));
  if (stats.components != initial_stats_.components)
    return Status::error(where + "components changed");
  if (options_.keep_part_boundaries && stats.parts != initial_stats_.parts)  // a part is gone
    return Status::error(where + "parts changed from " + std::to_string(initial_stats_.parts) +
                         " to " + std::to_string(stats.parts));
  if (report.count(ProblemKind::kRepeatedVertex) || report.count(ProblemKind::kDuplicateFace))
    return Status::error(where + "a face repeats a vertex or another face");
  return {};
}

bool Simplifier::stop_reached(std::string& reason) const {
  if (mesh_.live_vertices() <= target_vertices_) {
    reason = "reached " + std::to_string(mesh_.live_vertices()) + " vertices";
    return true;
  }
  if (options_.target_faces && mesh_.live_faces() <= *options_.target_faces) {
    reason = "reached " + std::to_string(mesh_.live_faces()) + " faces";
    return true;
  }
  return false;
}

// Takes the input's adjacency (validate() built it) and frees it once the vertex classes and
// constraint edges are known, before the quadrics and the queue take their memory.
Result<SimplifyResult> Simplifier::run(Adjacency adjacency) {
  std::vector<uint8_t> constrained;
  initial_stats_ = topology_stats(input_, adjacency);
  classify_vertices(adjacency);
  constrained = constrained_edges(adjacency);
  adjacency = {};
  build_quadrics(constrained);
  constrained = {};

  target_vertices_ = options_.target_vertices.value_or(0);
  if (options_.target_ratio) {
    const auto by_ratio = static_cast<uint32_t>(
        std::ceil(*options_.target_ratio * double(initial_stats_.referenced_vertices)));
    target_vertices_ = std::max(target_vertices_, by_ratio);
  }

  changed_.assign(input_.vertex_count, 0);
  rejected_.assign(input_.vertex_count, 0);
  rate_all_edges();
  ++time_;
  Scratch s(input_.vertex_count);

  SimplifyResult result;
  bool rated_again = false;  // every edge was re-rated since the last collapse
  while (true) {
    if (stop_reached(result.stop_reason)) {
      result.target_reached = true;
      break;
    }
    if (queue_.empty()) {
      if (!rated_again) {  // edges dropped as illegal may have become legal
        rate_all_edges();
        ++time_;
        rated_again = true;
        continue;
      }
      result.stop_reason =
          "no legal collapse remains at " + std::to_string(mesh_.live_vertices()) + " vertices";
      break;
    }
    const Entry entry = queue_.pop();
    if (stale(entry)) continue;
    if (options_.max_error && entry.error > *options_.max_error) {
      result.target_reached = true;
      result.stop_reason = "the next collapse would exceed the maximum error";
      break;
    }
    if (!legal(entry.v0, entry.v1, s)) {
      rejected_[entry.v0] = 1;
      if (!entry.one_way) {
        queue_.push({static_cast<float>(cost(entry.v1, entry.v0, s)), entry.v1, entry.v0, time_, 1});
      }
      continue;
    }
    // The cost exactly as rated (the heap keeps it as float), and with optimal placement the
    // positions collapse() moves v1 to.
    const double error = cost(entry.v0, entry.v1, s);
    DYNPM_RETURN_IF_ERROR(collapse(entry.v0, entry.v1, error, s));
    rated_again = false;
  }

  result.topology = mesh_.to_topology(input_, result.original_vertex);
  result.key_steps = key_steps_;
  result.collapses = collapses_;
  result.max_error = max_error_done_;
  if (optimal()) {
    result.key_step_positions.assign(key_count(), {});
    for (size_t k = 0; k < key_count(); ++k) {
      auto& out = result.key_step_positions[k];
      out.reserve(result.original_vertex.size() * 3);
      for (uint32_t v : result.original_vertex)
        out.insert(out.end(), &positions_[(size_t{v} * key_count() + k) * 3],
                   &positions_[(size_t{v} * key_count() + k) * 3] + 3);
    }
  }
  return result;
}

}  // namespace
}  // namespace simplification

Result<SimplifyResult> simplify(const Topology& topology, const FrameSource& frames,
                                const SimplifyOptions& options, CollapseListener* listener) {
  std::optional<Adjacency> adjacency;
  const ValidationReport report = validate(topology, adjacency);
  if (!report.ok()) {
    for (const Problem& p : report.problems)
      if (p.severity == Severity::kError) return Status::error("invalid input mesh: " + p.message);
  }
  if (frames.vertex_count() != topology.vertex_count)
    return Status::error("the time steps hold " + std::to_string(frames.vertex_count()) +
                         " vertices, the faces use " + std::to_string(topology.vertex_count));
  if (options.target_ratio && !(*options.target_ratio > 0 && *options.target_ratio <= 1))
    return Status::error("the target ratio must be in (0, 1]");
  simplification::Simplifier simplifier(topology, options, listener);
  DYNPM_RETURN_IF_ERROR(simplifier.load_key_steps(frames));
  if (!adjacency) adjacency = Adjacency::build(topology);
  return simplifier.run(std::move(*adjacency));
}

}  // namespace dynpm
