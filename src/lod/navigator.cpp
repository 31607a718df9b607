// The navigator: splits applied or undone in place between levels; positions per step.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "core/prefetch.h"
#include "dynpm/lod.h"
#include "shown_merge.h"

namespace dynpm {

Navigator::Navigator(const ProgressiveMesh& mesh)
    : mesh_(&mesh), faces_(mesh.base_faces), face_count_(mesh.base_face_count) {
  faces_.resize(mesh.face_count_after(mesh.split_count()));
}

namespace {

// Consecutive splits touch faces spread over the whole mesh: at 1 M vertices nearly every face a
// split names is a cache miss. The records say which faces split i will touch long before it
// runs, so the navigator asks for them this many splits ahead and the misses overlap.
constexpr uint32_t kPrefetchSplits = 8;
constexpr int kNext[] = {1, 2, 0, 1};  // the corner after slot s of a triangle is kNext[s]

// The split records as plain pointers held in locals: the face stores (uint32_t) cannot then
// alias them or the navigator's counters, which the compiler would otherwise reload after each.
struct SplitStream {
  uint32_t base_vertex_count;
  const uint32_t* parent;
  const uint32_t* moved_start;
  const uint32_t* moved_faces;
  const uint32_t* wing_start;
  const SplitWing* wings;
};

// core/prefetch.h: a bare __builtin_prefetch loop is deleted by GCC at -O2.
inline void prefetch_face(const Face* face) { prefetch<true>(face); }

void prefetch_faces(const SplitStream& m, uint32_t i, const Face* faces) {
  for (uint32_t k = m.moved_start[i]; k < m.moved_start[i + 1]; ++k)
    prefetch_face(faces + m.moved_faces[k]);
  for (uint32_t k = m.wing_start[i]; k < m.wing_start[i + 1]; ++k)
    prefetch_face(faces + m.wings[k].face);
}

// apply_split() and undo_split() in stream order without their checks, inlined into the loops
// of set_level(): the same faces in fewer instructions per split (at 1 M vertices the faces
// mostly arrive with the prefetches, and the time goes to the work per split).
#if defined(__GNUC__)
using Corners = uint32_t __attribute__((vector_size(16)));
// The corner holding `from` takes `to`: one compare and select over the whole face.
inline void replace_corner(Face& face, uint32_t from, uint32_t to) {
  static_assert(sizeof(Face) == sizeof(Corners));
  Corners c;
  std::memcpy(&c, face.v.data(), sizeof c);
  const Corners hit = (Corners)(c == Corners{from, from, from, from});
  c = (c & ~hit) | (Corners{to, to, to, to} & hit);
  std::memcpy(face.v.data(), &c, sizeof c);
}
#else
inline void replace_corner(Face& face, uint32_t from, uint32_t to) {
  for (uint32_t& c : face.v) c = c == from ? to : c;
}
#endif

// A triangle's corners from slot s on move one slot up and v0 takes slot s; remove_corner() is
// the inverse. Selects rather than a loop, which GCC makes a call to memmove.
inline void insert_corner(Face& face, int s, uint32_t v0) {
  const auto [a, b, c, d] = face.v;
  (void)d;  // kNoVertex: the face is a triangle
  face.v = {s == 0 ? v0 : a, s == 1 ? v0 : (s == 0 ? a : b), s == 2 ? v0 : (s <= 1 ? b : c),
            s == 3 ? v0 : c};
}

inline void remove_corner(Face& face, int s) {
  const auto [a, b, c, d] = face.v;
  face.v = {s == 0 ? b : a, s <= 1 ? c : b, s <= 2 ? d : c, kNoVertex};
}

inline void refine_split(const SplitStream& m, uint32_t i, Face* faces, uint32_t& face_count) {
  const uint32_t v0 = m.base_vertex_count + i;
  const uint32_t v1 = m.parent[i];
  for (uint32_t k = m.moved_start[i], end = m.moved_start[i + 1]; k < end; ++k)
    replace_corner(faces[m.moved_faces[k]], v1, v0);
  for (uint32_t k = m.wing_start[i], end = m.wing_start[i + 1]; k < end; ++k) {
    const SplitWing& w = m.wings[k];
    const int s = w.v0_slot();
    if (w.was_triangle()) {  // the triangle the collapse removed comes back
      Face& face = faces[face_count++];
      const bool follows = w.v1_follows_v0();
      face.v[3] = kNoVertex;
      face.v[s] = v0;
      face.v[kNext[s]] = follows ? v1 : w.vertex;
      face.v[kNext[s + 1]] = follows ? w.vertex : v1;
    } else {  // the triangle becomes the quad again: v0 back into its slot
      insert_corner(faces[w.face], s, v0);
    }
  }
}

inline void coarsen_split(const SplitStream& m, uint32_t i, Face* faces, uint32_t& face_count) {
  const uint32_t v0 = m.base_vertex_count + i;
  const uint32_t v1 = m.parent[i];
  for (uint32_t k = m.wing_start[i + 1], begin = m.wing_start[i]; k-- > begin;) {
    const SplitWing& w = m.wings[k];
    if (w.was_triangle()) {
      --face_count;
    } else {
      remove_corner(faces[w.face], w.v0_slot());
    }
  }
  for (uint32_t k = m.moved_start[i], end = m.moved_start[i + 1]; k < end; ++k)
    replace_corner(faces[m.moved_faces[k]], v0, v1);
}

}  // namespace

namespace {

// Levels level → k with the faces of the split kPrefetchSplits ahead asked for, or without
// (kPrefetch false: the faces stay in cache and the prefetches would only cost instructions).
template <bool kPrefetch>
void move_levels(const SplitStream& m, uint32_t& level, uint32_t k, Face* faces,
                 uint32_t& face_count) {
  if (kPrefetch)
    for (uint32_t i = level; i < std::min(k, level + kPrefetchSplits); ++i)
      prefetch_faces(m, i, faces);
  for (; level < k; ++level) {
    if (kPrefetch && level + kPrefetchSplits < k) prefetch_faces(m, level + kPrefetchSplits, faces);
    refine_split(m, level, faces, face_count);
  }
  if (kPrefetch)
    for (uint32_t i = level; i-- > k && i + kPrefetchSplits >= level;) prefetch_faces(m, i, faces);
  while (level > k) {
    --level;
    if (kPrefetch && level >= k + kPrefetchSplits)
      prefetch_faces(m, level - kPrefetchSplits, faces);
    coarsen_split(m, level, faces, face_count);
  }
}

// Face arrays up to this many bytes stay in a core's L2 cache (1–2 MB on current x86 cores);
// on the crash boxes (80 KB) the prefetches cost more time than they saved.
constexpr size_t kCachedFaceBytes = size_t{1} << 20;

}  // namespace

void Navigator::set_level(uint32_t k) {
  const SplitStream m{mesh_->base_vertex_count,  mesh_->parent.data(),
                      mesh_->moved_start.data(), mesh_->moved_faces.data(),
                      mesh_->wing_start.data(),  mesh_->wings.data()};
  uint32_t level = level_, face_count = face_count_;
  k = std::min(k, mesh_->split_count());
  if (faces_.size() * sizeof(Face) > kCachedFaceBytes)
    move_levels<true>(m, level, k, faces_.data(), face_count);
  else
    move_levels<false>(m, level, k, faces_.data(), face_count);
  level_ = level;
  face_count_ = face_count;
}

void Navigator::set_vertex_count(uint32_t n) {
  set_level(n > mesh_->base_vertex_count ? n - mesh_->base_vertex_count : 0);
}

uint32_t level_of_error(const ProgressiveMesh& mesh, double e) {
  // Level errors never increase along the stream: binary search for the first level ≤ e.
  if (mesh.base_error <= e) return 0;
  const auto& err = mesh.error;
  const auto it = std::partition_point(err.begin(), err.end(), [e](float x) { return x > e; });
  return static_cast<uint32_t>(it - err.begin()) + 1;
}

void Navigator::set_error(double e) { set_level(level_of_error(*mesh_, e)); }

void Navigator::positions(double t, std::span<float> out) const {
  const size_t steps = mesh_->step_count();
  const size_t n = size_t{vertex_count()} * 3;
  assert(out.size() >= n);
  t = std::clamp(t, 0.0, static_cast<double>(steps - 1));
  const size_t t0 = static_cast<size_t>(std::floor(t));
  const size_t t1 = std::min(t0 + 1, steps - 1);
  const float a = static_cast<float>(t - static_cast<double>(t0));
  const float* p0 = mesh_->positions[t0].data();
  const float* p1 = mesh_->positions[t1].data();
  if (a == 0.0f || t0 == t1) {
    std::copy_n(p0, n, out.data());
    return;
  }
  for (size_t j = 0; j < n; ++j) out[j] = p0[j] + a * (p1[j] - p0[j]);
}

void Navigator::field_values(size_t field, size_t t, std::span<float> out,
                             FieldAggregate aggregate) const {
  const ProgressiveMesh& m = *mesh_;
  const ProgressiveField& f = m.fields[field];
  const bool per_face = f.info.location == FieldLocation::kElement;
  const std::vector<float>& values = f.values[t];
  const uint32_t shown = per_face ? face_count_ : vertex_count();
  assert(out.size() >= shown);
  // The pass of FORMAT.md run from the last split present down to this level: each undone split
  // merges what its new vertex (the faces it creates) stands for into the parent (their heirs).
  // Merge order: faces of a split in reverse creation order, as the file's pass.
  ShownMerge merged(values, aggregate);
  uint32_t face_end = static_cast<uint32_t>(values.size());  // faces after split i
  for (uint32_t i = m.split_count(); i-- > level_;)
    face_end = merge_undone_split(m, i, per_face, face_end, merged);
  for (uint32_t i = 0; i < shown; ++i) out[i] = merged.shown(i);
}

double Navigator::field_error(size_t field) const {
  const ProgressiveField& f = mesh_->fields[field];
  return level_ == 0 ? f.base_error : f.error[level_ - 1];
}

uint32_t Navigator::ancestor(uint32_t v, uint32_t k) const {
  const uint32_t b = mesh_->base_vertex_count;
  while (v >= b + k) v = mesh_->parent[v - b];
  return v;
}

void Navigator::geomorph(uint32_t from, double alpha, double t, std::span<float> out) const {
  positions(t, out);
  const uint32_t b = mesh_->base_vertex_count;
  from = std::min(from, level_);
  const float a = static_cast<float>(std::clamp(alpha, 0.0, 1.0));
  // A parent is created before its children, so one pass in vertex order finds every vertex's
  // ancestor at level `from` from its parent's.
  std::vector<uint32_t> anc(level_ - from);
  for (uint32_t v = b + from; v < vertex_count(); ++v) {
    const uint32_t p = mesh_->parent[v - b];
    anc[v - b - from] = p < b + from ? p : anc[p - b - from];
  }
  std::vector<float> end(out.begin(), out.begin() + size_t{vertex_count()} * 3);
  for (uint32_t v = b + from; v < vertex_count(); ++v) {
    const uint32_t u = anc[v - b - from];
    for (int c = 0; c < 3; ++c) {
      // (1 − a)·start + a·end: exactly the end points at a = 0 and a = 1.
      out[size_t{v} * 3 + c] = (1 - a) * end[size_t{u} * 3 + c] + a * end[size_t{v} * 3 + c];
    }
  }
}

Topology Navigator::topology() const {
  Topology out;
  out.vertex_count = vertex_count();
  out.faces.assign(faces_.begin(), faces_.begin() + face_count_);
  out.part_ids.assign(mesh_->part_ids.begin(), mesh_->part_ids.begin() + face_count_);
  out.element_ids.assign(mesh_->element_ids.begin(), mesh_->element_ids.begin() + face_count_);
  out.node_ids.assign(mesh_->node_ids.begin(), mesh_->node_ids.begin() + vertex_count());
  out.part_names = mesh_->part_names;
  return out;
}

Result<OriginalOrder> original_order(const Navigator& full) {
  const ProgressiveMesh& m = full.mesh();
  // Every split applied is all it takes: a model read up to one step has every vertex and face.
  if (full.level() != m.full_split_count)
    return Status::error("the input's order needs the fully refined mesh");
  OriginalOrder out;
  Topology& t = out.topology;
  t.vertex_count = m.full_vertex_count;
  t.part_names = m.part_names;
  t.node_ids.resize(t.vertex_count);
  out.vertex_of_original.resize(t.vertex_count);
  for (uint32_t v = 0; v < t.vertex_count; ++v) {
    out.vertex_of_original[m.vertex_original_index[v]] = v;
    t.node_ids[m.vertex_original_index[v]] = m.node_ids[v];
  }
  const auto faces = full.faces();
  t.faces.resize(faces.size());
  t.part_ids.resize(faces.size());
  t.element_ids.resize(faces.size());
  out.face_of_original.resize(faces.size());
  for (uint32_t f = 0; f < faces.size(); ++f) {
    const uint32_t o = m.face_original_index[f];
    out.face_of_original[o] = f;
    Face face = faces[f];
    for (uint32_t& c : face.v)
      if (c != kNoVertex) c = m.vertex_original_index[c];
    t.faces[o] = face;
    t.part_ids[o] = m.part_ids[f];
    t.element_ids[o] = m.element_ids[f];
  }
  return out;
}

}  // namespace dynpm
