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
// changed (collapse_mesh.h), the queue (a lazy binary heap, one candidate per vertex, stamped
// with the vertex's version), and the listener (CollapseListener). Read top to bottom: key
// steps and quadrics, vertex classes, one candidate, the loop, the public entry.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <unordered_set>

#include "collapse_mesh.h"
#include "dynpm/simplify.h"
#include "legality.h"
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
  std::vector<uint32_t> neighbours, ring;
  std::vector<std::pair<double, uint32_t>> options;  // (error, v1) of the legal-by-class collapses
  std::vector<Vec3> placement;  // per key step, for the candidate under test
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
  void build_quadrics(const Adjacency& adjacency);
  Result<SimplifyResult> run();

 private:
  size_t key_count() const { return key_steps_.size(); }
  Vec3 position(uint32_t v, size_t k) const { return load(&positions_[(size_t{v} * key_count() + k) * 3]); }
  Quadric& quadric(uint32_t v, size_t k) { return quadrics_[size_t{v} * key_count() + k]; }
  const Quadric& quadric(uint32_t v, size_t k) const { return quadrics_[size_t{v} * key_count() + k]; }
  bool optimal() const { return options_.placement == Placement::kOptimal; }

  bool is_feature_edge(uint32_t a, uint32_t b, std::span<const uint32_t> faces) const;
  EdgeFaces edge_faces(uint32_t v0, uint32_t v1) const;
  double collapse_error(uint32_t v0, uint32_t v1, std::vector<Vec3>& placement) const;
  bool topology_allows(uint32_t v0, uint32_t v1, const EdgeFaces& edge, Scratch& s) const;
  bool face_stays_sound(const Face& face, size_t k, uint32_t skip, uint32_t moved, Vec3 target) const;
  bool geometry_allows(uint32_t v0, uint32_t v1, const std::vector<Vec3>& placement) const;
  void best_candidate(uint32_t v0, Scratch& s, double& error, uint32_t& target) const;

  void recompute(uint32_t v, Scratch& s);
  void push(uint32_t v);
  Status collapse(uint32_t v0, uint32_t v1, double error, Scratch& s);
  Status check_mesh(size_t collapse_index) const;
  bool stop_reached(std::string& reason) const;

  const Topology& input_;
  const SimplifyOptions& options_;
  CollapseListener* listener_;
  CollapseMesh mesh_;

  std::vector<size_t> key_steps_;
  std::vector<float> positions_;   // #V × #key steps × xyz (vertex-major: one vertex's steps together)
  std::vector<Quadric> quadrics_;  // #V × #key steps
  double diagonal_ = 1;
  double cos_max_rotation_ = 0;

  std::vector<VertexClass> class_;
  std::unordered_set<uint64_t> user_features_;
  std::vector<uint32_t> component_, component_live_;  // (P3) per connected component
  TopologyStats initial_stats_;

  // The queue: the best candidate of each vertex, and heap entries stamped with the vertex's
  // version at push time; an entry whose stamp is old is skipped on pop (temporal marks).
  struct Entry {
    double error;
    uint32_t vertex, version;
    bool operator>(const Entry& o) const {
      return error != o.error ? error > o.error : vertex > o.vertex;  // deterministic ties
    }
  };
  std::vector<Entry> heap_;
  std::vector<double> candidate_error_;
  std::vector<uint32_t> candidate_target_, version_;

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
        return Status::error("key step " + std::to_string(t) + " does not exist (the animation has " +
                             std::to_string(steps) + " steps)");
  }
  if (optimal() && key_steps_.size() != steps)
    return Status::error("optimal placement moves vertices in every step, so every step must be a "
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
  component_live_.assign(n, 0);
  for (uint32_t v = 0; v < n; ++v) {
    component_[v] = find(v);
    if (mesh_.vertex_alive(v)) ++component_live_[component_[v]];
  }
}

void Simplifier::build_quadrics(const Adjacency& adjacency) {
  const uint32_t n = input_.vertex_count;
  const size_t k_count = key_count();
  quadrics_.assign(size_t{n} * k_count, Quadric{});
  // Gathered per vertex (no two threads write one quadric); each face's plane is computed once
  // per corner, which is cheaper than storing a plane per face and step.
  parallel_for(size_t{n} * k_count, thread_count(options_.threads), [&](size_t begin, size_t end,
                                                                        unsigned) {
    for (size_t i = begin; i < end; ++i) {
      const uint32_t v = static_cast<uint32_t>(i / k_count);
      const size_t k = i % k_count;
      Quadric q;
      for (uint32_t f : adjacency.faces_of_vertex(v)) {
        const Face& face = input_.faces[f];
        const int d = face.degree();
        Vec3 p[4];
        for (int c = 0; c < d; ++c) p[c] = position(face.v[c], k);
        // The face's plane: a triangle's own; for a quad, possibly skew, the mean of its corner
        // normals through its centroid (paper §2). Weighted by area.
        const Vec3 area2 = doubled_vector_area(p, d);
        const double area = 0.5 * length(area2);
        if (area <= 0) continue;
        Vec3 normal = normalized(area2), centre = p[0];
        if (d == 4) {
          Vec3 sum{};
          for (int c = 0; c < 4; ++c) sum = sum + normalized(cross(p[(c + 1) % 4] - p[c], p[(c + 3) % 4] - p[c]));
          if (length(sum) > 0) normal = normalized(sum);
          centre = (p[0] + p[1] + p[2] + p[3]) * 0.25;
        }
        q.add_plane(normal, -dot(normal, centre), area);

        // Constraint planes through v's boundary and feature edges in this face,
        // perpendicular to the face, weighted by the squared edge length.
        const int i0 = corner_of(face, v);
        for (int other : {(i0 + 1) % d, (i0 + d - 1) % d}) {
          const uint32_t w = face.v[other];
          auto e = adjacency.find_edge(v, w);
          if (!e) continue;
          const auto edge_faces = adjacency.faces_of_edge(*e);
          if (edge_faces.size() != 1 && !is_feature_edge(v, w, edge_faces)) continue;
          const Vec3 along = p[other] - p[i0];
          const Vec3 m = normalized(cross(along, normal));
          if (length(m) == 0) continue;
          q.add_plane(m, -dot(m, p[i0]), options_.boundary_weight * dot(along, along));
        }
      }
      quadric(v, k) = q;
    }
  });
}

// ---------------------------------------------------------------------------------------------
// One candidate: cost, topology, geometry

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

// Paper method (1*): the largest error over the key steps, each a weighted RMS distance to the
// planes of (Q_t,v0 + Q_t,v1), at v1's position (half-edge) or at the minimiser (optimal).
double Simplifier::collapse_error(uint32_t v0, uint32_t v1, std::vector<Vec3>& placement) const {
  double worst = 0;
  placement.resize(key_count());
  const bool moves = optimal() && class_[v1] != VertexClass::kLocked;
  for (size_t k = 0; k < key_count(); ++k) {
    const Quadric q = quadric(v0, k) + quadric(v1, k);
    Vec3 p = position(v1, k);
    if (moves) {
      if (auto m = q.minimiser()) {
        p = *m;
      } else if (class_[v1] == VertexClass::kInterior && q.evaluate(position(v0, k)) < q.evaluate(p)) {
        p = position(v0, k);  // ill-conditioned: the better endpoint
      }
    }
    placement[k] = p;
    worst = std::max(worst, q.mean_squared(p));
  }
  return std::sqrt(worst) / diagonal_;
}

bool Simplifier::topology_allows(uint32_t v0, uint32_t v1, const EdgeFaces& edge, Scratch& s) const {
  // (P3): a component keeps more than 4 vertices, or more than 3 at a boundary.
  const bool at_border = class_[v0] != VertexClass::kInterior || class_[v1] != VertexClass::kInterior;
  if (component_live_[component_[v0]] <= (at_border ? 3u : 4u)) return false;
  // (P1*): otherwise the collapse leaves a vertex of valence two (paper Fig. 4 and 5).
  return second_order_neighbours_ok(mesh_, v0, v1, std::span(edge.faces.data(), edge.count), s.marks);
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
  const double new_length = length(new_normal), old_length = length(old_normal);
  if (new_length <= 1e-12 * diagonal_ * diagonal_) return false;  // no area left
  if (old_length > 0 && dot(old_normal, new_normal) < cos_max_rotation_ * old_length * new_length)
    return false;  // folds over
  if (n == 4 && quad_is_convex(before, old_normal) && !quad_is_convex(after, new_normal)) return false;
  return true;
}

// No moved face may fold over or degenerate in any key step.
bool Simplifier::geometry_allows(uint32_t v0, uint32_t v1, const std::vector<Vec3>& placement) const {
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
      if (!face.contains(v0) && !face_stays_sound(face, k, kNoVertex, v1, placement[k])) return false;
    }
  }
  return true;
}

// The cheapest legal collapse of v0 into one of its neighbours (target kNoVertex if none):
// rate every neighbour the vertex classes allow, then run the costlier checks cheapest first
// until one passes.
void Simplifier::best_candidate(uint32_t v0, Scratch& s, double& error, uint32_t& target) const {
  error = std::numeric_limits<double>::infinity();
  target = kNoVertex;
  const VertexClass c0 = class_[v0];
  if (c0 == VertexClass::kLocked || !mesh_.vertex_alive(v0)) return;
  mesh_.neighbours(v0, s.neighbours);
  s.options.clear();
  for (uint32_t v1 : s.neighbours) {
    const Along along = can_collapse(c0, class_[v1]);
    if (along == Along::kNever) continue;
    s.options.emplace_back(collapse_error(v0, v1, s.placement), v1);
  }
  std::sort(s.options.begin(), s.options.end());
  for (const auto& [e, v1] : s.options) {
    const EdgeFaces edge = edge_faces(v0, v1);
    if (edge.count == 0 || edge.diagonal || edge.too_many) continue;
    const Along along = can_collapse(c0, class_[v1]);
    if (along == Along::kBoundaryEdge && edge.count != 1) continue;
    if (along == Along::kFeatureEdge &&
        !is_feature_edge(v0, v1, std::span<const uint32_t>(edge.faces.data(), edge.count)))
      continue;
    if (!topology_allows(v0, v1, edge, s)) continue;
    if (optimal()) collapse_error(v0, v1, s.placement);
    else s.placement.clear();
    if (!geometry_allows(v0, v1, s.placement)) continue;
    error = e;
    target = v1;
    return;
  }
}

// ---------------------------------------------------------------------------------------------
// The loop

void Simplifier::push(uint32_t v) {
  if (candidate_target_[v] == kNoVertex) return;
  heap_.push_back({candidate_error_[v], v, version_[v]});
  std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
}

void Simplifier::recompute(uint32_t v, Scratch& s) {
  ++version_[v];
  best_candidate(v, s, candidate_error_[v], candidate_target_[v]);
  push(v);
}

Status Simplifier::collapse(uint32_t v0, uint32_t v1, double error, Scratch& s) {
  std::vector<Vec3>& placement = s.placement;
  if (optimal()) collapse_error(v0, v1, placement);  // the same placement the candidate had

  CollapseRecord record;
  record.error = error;
  mesh_.collapse(v0, v1, record, moved_);
  --component_live_[component_[v0]];
  for (size_t k = 0; k < key_count(); ++k) {
    quadric(v1, k) += quadric(v0, k);
    if (optimal()) {
      float* p = &positions_[(size_t{v1} * key_count() + k) * 3];
      p[0] = static_cast<float>(placement[k].x), p[1] = static_cast<float>(placement[k].y),
      p[2] = static_cast<float>(placement[k].z);
    }
  }
  if (optimal())
    record.v1_new_positions = {&positions_[size_t{v1} * key_count() * 3], key_count() * 3};
  ++version_[v0];  // its queued entries are now stale
  candidate_target_[v0] = kNoVertex;
  ++collapses_;
  max_error_done_ = std::max(max_error_done_, error);
  if (listener_) listener_->on_collapse(record);
  if (options_.check_every_collapse) DYNPM_RETURN_IF_ERROR(check_mesh(collapses_));

  // Everything whose neighbourhood, quadric or position changed: v1 and every vertex sharing a
  // face with it.
  mesh_.second_order_neighbours(v1, ring_);
  recompute(v1, s);
  for (uint32_t w : ring_) recompute(w, s);

  // Drop stale entries when they outnumber the live ones.
  if (heap_.size() > 4 * size_t{mesh_.live_vertices()} + 1024) {
    std::erase_if(heap_, [&](const Entry& e) { return e.version != version_[e.vertex]; });
    std::make_heap(heap_.begin(), heap_.end(), std::greater<>());
  }
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

Result<SimplifyResult> Simplifier::run() {
  const Adjacency adjacency = Adjacency::build(input_);
  initial_stats_ = topology_stats(input_, adjacency);
  classify_vertices(adjacency);
  build_quadrics(adjacency);

  target_vertices_ = options_.target_vertices.value_or(0);
  if (options_.target_ratio) {
    const auto by_ratio = static_cast<uint32_t>(
        std::ceil(*options_.target_ratio * double(initial_stats_.referenced_vertices)));
    target_vertices_ = std::max(target_vertices_, by_ratio);
  }

  // Every vertex's first candidate, in parallel; then the heap.
  const uint32_t n = input_.vertex_count;
  candidate_error_.assign(n, 0);
  candidate_target_.assign(n, kNoVertex);
  version_.assign(n, 0);
  const unsigned threads = thread_count(options_.threads);
  std::vector<Scratch> scratch(threads, Scratch(n));
  parallel_for(n, threads, [&](size_t begin, size_t end, unsigned t) {
    for (size_t v = begin; v < end; ++v)
      best_candidate(static_cast<uint32_t>(v), scratch[t], candidate_error_[v], candidate_target_[v]);
  });
  heap_.reserve(size_t{n} * 2);
  for (uint32_t v = 0; v < n; ++v)
    if (candidate_target_[v] != kNoVertex) heap_.push_back({candidate_error_[v], v, 0});
  std::make_heap(heap_.begin(), heap_.end(), std::greater<>());

  SimplifyResult result;
  Scratch& s = scratch[0];
  while (true) {
    if (stop_reached(result.stop_reason)) {
      result.target_reached = true;
      break;
    }
    if (heap_.empty()) {
      result.stop_reason = "no legal collapse remains at " + std::to_string(mesh_.live_vertices()) +
                           " vertices";
      break;
    }
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    const Entry entry = heap_.back();
    heap_.pop_back();
    const uint32_t v0 = entry.vertex;
    if (entry.version != version_[v0]) continue;  // stale
    if (options_.max_error && entry.error > *options_.max_error) {
      result.target_reached = true;
      result.stop_reason = "the next collapse would exceed the maximum error";
      break;
    }
    const uint32_t v1 = candidate_target_[v0];
    // (P3) depends on the component's size, which other collapses change.
    const bool at_border = class_[v0] != VertexClass::kInterior || class_[v1] != VertexClass::kInterior;
    if (component_live_[component_[v0]] <= (at_border ? 3u : 4u)) continue;
    DYNPM_RETURN_IF_ERROR(collapse(v0, v1, entry.error, s));
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
  const ValidationReport report = validate(topology);
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
  return simplifier.run();
}

}  // namespace dynpm
