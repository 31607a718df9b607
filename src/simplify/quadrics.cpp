#include "quadrics.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "core/pages.h"
#include "core/parallel.h"

namespace dynpm::simplification {

std::vector<uint8_t> constrained_edges(const Topology& input, const Adjacency& adjacency,
                                       const FeatureEdges& features) {
  std::vector<uint8_t> constrained(input.faces.size(), 0);
  for (size_t e = 0; e < adjacency.edge_count(); ++e) {
    const Edge edge = adjacency.edge(e);
    const auto faces = adjacency.faces_of_edge(e);
    if (faces.size() != 1 && !features.is_feature_edge(edge.a, edge.b, faces)) continue;
    for (uint32_t f : faces) {
      const Face& face = input.faces[f];
      const int d = face.degree(), c = corner_of(face, edge.a);
      constrained[f] |=
          static_cast<uint8_t>(1u << (face.v[(c + 1) % d] == edge.b ? c : (c + d - 1) % d));
    }
  }
  return constrained;
}

Status KeyStepQuadrics::load_key_steps(const FrameSource& frames, const Topology& input,
                                       std::span<const size_t> key_steps,
                                       std::span<const CostField> fields, FieldForm form,
                                       FieldCombine combine, unsigned threads,
                                       const ProgressCallback& progress) {
  const uint32_t vertex_count = input.vertex_count;
  key_count_ = key_steps.size();
  positions_.resize(size_t{vertex_count} * key_count_ * 3);
  fields_.choose(fields, fields.empty() ? std::vector<FieldInfo>{} : frames.fields(), form,
                 key_count_, vertex_count);
  combine_ = combine;
  BoundingBox box;
  if (progress) progress("reading key steps", 0, key_count_);
  size_t done = 0;
  DYNPM_RETURN_IF_ERROR(
      for_each_step(frames, key_steps, threads, [&](size_t k, std::span<const float> step) {
        box.extend(step);
        for (uint32_t v = 0; v < vertex_count; ++v)
          std::copy_n(&step[size_t{v} * 3], 3, position_data(v, k));
        Status loaded = fields_.load_step(frames, input, k, key_steps[k]);
        if (loaded.ok() && progress) progress("reading key steps", ++done, key_count_);
        return loaded;
      }));
  box_ = box;
  diagonal_ = box.diagonal() > 0 ? box.diagonal() : 1.0;
  fields_.finish(diagonal_);
  return {};
}

namespace {

// Planes through the constrained edges of the face at its corner `at`, perpendicular to the
// face, weighted by boundary_weight · |edge|².
void add_constraint_planes(Quadric& q, const Vec3* p, int degree, int at, uint8_t constrained,
                           Vec3 face_normal, double boundary_weight) {
  const int before = (at + degree - 1) % degree;
  for (int other : {(at + 1) % degree, before}) {
    const int edge_bit = other == before ? before : at;
    if (!(constrained & (1u << edge_bit))) continue;
    const Vec3 along = p[other] - p[at];
    const Vec3 m = normalized(cross(along, face_normal));
    if (length(m) == 0) continue;
    q.add_plane(m, -dot(m, p[at]), boundary_weight * dot(along, along));
  }
}

// The shape term: weight · |p − v|², v at the origin. In a flat region, where every plane
// costs nothing, it makes a collapse cost the (area-weighted RMS) distance from v1 to the
// vertices it stands for, so compact clusters win over long slivers and fans.
void add_regularizer(Quadric& q, double weight) { q.add_isotropic(weight); }

}  // namespace

// A face's unit normal (its plane's: a skew quad's quad_plane()) and its area. Both come from
// differences of its corners, so they are the same around whichever point the corners are
// given; the plane's offset is not, and is taken around each corner's own vertex.
// Key steps whose face shapes an opening island holds at once.
constexpr size_t kShapeKeySteps = 4;

struct FaceShape {
  Vec3 normal;
  double area = 0;
};
FaceShape face_shape(const Vec3* p, int degree) {
  FaceShape s;
  s.area = 0.5 * length(doubled_vector_area(p, degree));
  if (s.area > 0) s.normal = face_plane(p, degree).normal;
  return s;
}

// In coordinates around v: the planes of v's faces weighted by their areas, and their
// constraint planes at v.
template <class Shape>
Quadric KeyStepQuadrics::vertex_quadric(const CollapseMesh& mesh, uint32_t v, size_t k,
                                        Shape&& shape) const {
  const Vec3 origin = position(v, k);
  Quadric q;
  double area = 0;
  for (uint32_t f : mesh.faces_of(v)) {
    const Face& face = input_->faces[f];
    const int d = face.degree();
    Vec3 p[4];  // the face's corners around v
    for (int c = 0; c < d; ++c) p[c] = position(face.v[c], k) - origin;
    const FaceShape s = shape(f, p, d);
    if (!(s.area > 0)) continue;
    // Through the centroid (a quad) or the first corner (a triangle), as face_plane() has it.
    const Vec3 through = d == 4 ? (p[0] + p[1] + p[2] + p[3]) * 0.25 : p[0];
    q.add_plane(s.normal, -dot(s.normal, through), s.area);
    add_constraint_planes(q, p, d, corner_of(face, v), constrained_[f], s.normal, boundary_weight_);
    if (regularize_ > 0) area += s.area;
  }
  if (regularize_ > 0) add_regularizer(q, regularize_ * area);
  return q;
}

void KeyStepQuadrics::build(const Topology& input, const CollapseMesh& mesh,
                            std::vector<uint8_t> constrained, double boundary_weight,
                            double regularize, unsigned threads) {
  input_ = &input;
  constrained_ = std::move(constrained);
  boundary_weight_ = boundary_weight;
  regularize_ = regularize;
  fields_.build(input, mesh, positions_, threads);
  const uint32_t n = input.vertex_count;
  if (mesh.island_count() > 1) {  // made as the islands open
    island_quadrics_.resize(mesh.island_count());
    island_rows_.assign(n, nullptr);
    island_face_slot_.assign(input.faces.size(), kNoIndex);
    return;
  }
  quadrics_.assign(size_t{n} * key_count_, LocalQuadric{});
  parallel_for_chunks(size_t{n} * key_count_, threads, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const uint32_t v = static_cast<uint32_t>(i / key_count_);
      const size_t k = i % key_count_;
      quadric(v, k) = LocalQuadric::narrow(vertex_quadric(
          mesh, v, k, [](uint32_t, const Vec3* p, int d) { return face_shape(p, d); }));
    }
  });
  std::vector<uint8_t>().swap(constrained_);
}

void KeyStepQuadrics::open_island(size_t i, const CollapseMesh& mesh) {
  size_t count = 0;
  mesh.for_each_island_vertex(i, [&](uint32_t) { ++count; });
  std::vector<LocalQuadric>& block = island_quadrics_[i];
  block = spare_blocks_.take();
  block.resize(count * key_count_);
  release_unused_capacity(block);  // a larger island's rows past this one's
  // Each face's shape once a key step, not once a corner (a quad's plane normalizes five
  // vectors): the island's faces numbered as met, their shapes around their first corner, a
  // few key steps at a time (all 25 of a large island's would hold 13 MB a thread).
  thread_local std::vector<uint32_t> faces;
  thread_local std::vector<FaceShape> shapes;
  faces.clear();
  mesh.for_each_island_vertex(i, [&](uint32_t v) {
    for (uint32_t f : mesh.faces_of(v))
      if (island_face_slot_[f] == kNoIndex) {
        island_face_slot_[f] = static_cast<uint32_t>(faces.size());
        faces.push_back(f);
      }
  });
  LocalQuadric* row = block.data();
  mesh.for_each_island_vertex(i, [&](uint32_t v) {
    island_rows_[v] = row;
    row += key_count_;
  });
  for (size_t k0 = 0; k0 < key_count_; k0 += kShapeKeySteps) {
    const size_t keys = std::min(kShapeKeySteps, key_count_ - k0);
    shapes.resize(faces.size() * keys);
    for (size_t j = 0; j < faces.size(); ++j) {
      const Face& face = input_->faces[faces[j]];
      const int d = face.degree();
      for (size_t k = k0; k < k0 + keys; ++k) {
        Vec3 p[4];
        for (int c = 0; c < d; ++c) p[c] = position(face.v[c], k) - position(face.v[0], k);
        shapes[j * keys + k - k0] = face_shape(p, d);
      }
    }
    mesh.for_each_island_vertex(i, [&](uint32_t v) {
      for (size_t k = k0; k < k0 + keys; ++k)
        island_rows_[v][k] =
            LocalQuadric::narrow(vertex_quadric(mesh, v, k, [&](uint32_t f, const Vec3*, int) {
              return shapes[size_t{island_face_slot_[f]} * keys + k - k0];
            }));
    });
  }
  const size_t held = held_ += count;
  for (size_t most = most_held_; most < held && !most_held_.compare_exchange_weak(most, held);) {
  }
}

void KeyStepQuadrics::close_island(size_t i, const CollapseMesh& mesh) {
  mesh.for_each_island_vertex(i, [&](uint32_t v) { island_rows_[v] = nullptr; });
  held_ -= island_quadrics_[i].size() / key_count_;
  island_quadrics_[i].clear();
  spare_blocks_.give(std::exchange(island_quadrics_[i], {}));
}

void KeyStepQuadrics::drop_spare_blocks() { spare_blocks_.clear(); }

Quadric KeyStepQuadrics::merged_quadric(uint32_t v0, uint32_t v1, size_t k) const {
  return quadric(v1, k).widen() +
         quadric(v0, k).widen().translated(position(v1, k) - position(v0, k));
}

double KeyStepQuadrics::collapse_error(uint32_t v0, uint32_t v1, VertexClass v1_class,
                                       std::vector<Vec3>& placement) const {
  placement.resize(key_count_);
  const bool moves = v1_class != VertexClass::kLocked;
  return worst_over_key_steps<1>(
      key_count_, diagonal_, combine_, !fields_.empty(), [&](size_t k, auto& worst) {
        const Quadric q = merged_quadric(v0, v1, k);
        const Vec3 p1 = position(v1, k);
        Vec3 offset{};  // from v1's position
        if (moves) {
          if (auto m = q.minimiser()) {
            offset = *m;
          } else if (v1_class == VertexClass::kInterior &&
                     q.evaluate(position(v0, k) - p1) < q.evaluate(offset)) {
            offset = position(v0, k) - p1;  // ill-conditioned: the better endpoint
          }
        }
        placement[k] = p1 + offset;
        worst[0].offer(q.mean_squared(offset), fields_.squared(v0, v1, k, p1 - position(v0, k)));
      })[0];
}

double KeyStepQuadrics::half_edge_error(uint32_t v0, uint32_t v1) const {
  return worst_over_key_steps<1>(
      key_count_, diagonal_, combine_, !fields_.empty(), [&](size_t k, auto& worst) {
        const LocalQuadric& q1 = quadric(v1, k);
        const Quadric q0 = quadric(v0, k).widen();
        const double weight = q0.w + double{q1.w};
        if (!(weight > 0)) return;
        const Vec3 offset = position(v1, k) - position(v0, k);
        const double moved = q0.evaluate(offset);
        const double field = fields_.squared(v0, v1, k, offset);
        worst[0].offer((moved + double{q1.c}) / weight, field);
        if (q0.w > 0) worst[0].offer(moved / q0.w, field);  // the floor, see half_edge_errors()
      })[0];
}

std::pair<double, double> KeyStepQuadrics::half_edge_errors(uint32_t a, uint32_t b) const {
  const auto error = worst_over_key_steps<2>(
      key_count_, diagonal_, combine_, !fields_.empty(), [&](size_t k, auto& worst) {
        const Quadric qa = quadric(a, k).widen(), qb = quadric(b, k).widen();
        const double weight = qa.w + qb.w;
        if (!(weight > 0)) return;
        const Vec3 d = position(b, k) - position(a, k);
        const double moved_a = qa.evaluate(d), moved_b = qb.evaluate(Vec3{} - d);
        const double field_a = fields_.squared(a, b, k, d);  // the spread's is the same both ways
        const double field_b = fields_.squared(b, a, k, Vec3{} - d);
        worst[0].offer((moved_a + qb.c) / weight, field_a);
        worst[1].offer((moved_b + qa.c) / weight, field_b);
        // The cost floor: never less than the moved vertex's own mean squared distance. Divided by
        // the merged weight alone, a light vertex (a boundary corner) next to a heavy one (which
        // has absorbed many collapses) would be swallowed at almost no cost, cutting the corner.
        if (qa.w > 0) worst[0].offer(moved_a / qa.w, field_a);
        if (qb.w > 0) worst[1].offer(moved_b / qb.w, field_b);
      });
  return {error[0], error[1]};
}

std::span<const float> KeyStepQuadrics::merge(uint32_t v0, uint32_t v1,
                                              const std::vector<Vec3>* placement,
                                              MergeScratch& scratch) {
  std::vector<Vec3>& offsets = scratch.offsets;
  std::vector<Vec3>& moves = scratch.moves;
  offsets.resize(key_count_);
  moves.resize(placement ? key_count_ : 0);
  for (size_t k = 0; k < key_count_; ++k) {
    Quadric q = merged_quadric(v0, v1, k);  // around v1's position
    offsets[k] = position(v1, k) - position(v0, k);
    if (placement) {
      const Vec3 before = position(v1, k);
      moves[k] = (*placement)[k] - before;
      float* p = position_data(v1, k);
      p[0] = static_cast<float>((*placement)[k].x), p[1] = static_cast<float>((*placement)[k].y),
      p[2] = static_cast<float>((*placement)[k].z);
      q = q.translated(position(v1, k) - before);  // around the new one
    }
    quadric(v1, k) = LocalQuadric::narrow(q);
  }
  fields_.merge(v0, v1, offsets, moves);
  return {position_data(v1, 0), key_count_ * 3};
}

size_t KeyStepQuadrics::collapses_before_drop(const CollapseMesh& mesh) const {
  const size_t rows = quadrics_.size() / std::max<size_t>(key_count_, 1);
  const size_t live = mesh.live_vertices();
  return live * 16 > rows * 15 ? live - rows * 15 / 16 : 0;
}

void KeyStepQuadrics::drop_removed(const CollapseMesh& mesh) {
  const size_t rows = quadrics_.size() / std::max<size_t>(key_count_, 1);
  if (!island_rows_.empty() || collapses_before_drop(mesh) > 0 || rows < 64) return;
  const uint32_t n = mesh.vertex_count();
  // The first time, rows are still vertices: the table is made after the rows have moved and
  // their pages are released, so that its 4 B per vertex never add to the collapse's peak.
  const bool first = row_.empty();
  const size_t q = key_count_, p = key_count_ * 3;
  uint32_t next = 0;
  for (uint32_t v = 0; v < n; ++v) {
    if (!mesh.vertex_alive(v)) {
      if (!first) row_[v] = kNoVertex;
      continue;
    }
    const uint32_t from = first ? v : row_[v];  // ≥ next: rows keep the vertex order
    if (from != next) {
      std::copy_n(&quadrics_[from * q], q, &quadrics_[next * q]);
      std::copy_n(&positions_[from * p], p, &positions_[next * p]);
    }
    if (!first) row_[v] = next;
    ++next;
  }
  quadrics_.resize(next * q);
  positions_.resize(next * p);
  release_unused_capacity(quadrics_);
  release_unused_capacity(positions_);
  if (!first) return;
  row_.resize(n);
  next = 0;
  for (uint32_t v = 0; v < n; ++v) row_[v] = mesh.vertex_alive(v) ? next++ : kNoVertex;
}

std::vector<float> KeyStepQuadrics::positions_of(std::span<const uint32_t> vertices,
                                                 size_t k) const {
  std::vector<float> out;
  out.reserve(vertices.size() * 3);
  for (uint32_t v : vertices) out.insert(out.end(), position_data(v, k), position_data(v, k) + 3);
  return out;
}

}  // namespace dynpm::simplification
