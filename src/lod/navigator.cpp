// The navigator: splits applied or undone in place between levels; positions per step.
#include <algorithm>
#include <cassert>
#include <cmath>

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
// split names is a cache miss. The records say which faces the splits ahead will touch, so the
// loops ask for the face this many entries on in the moved-face and wing arrays (6–8 splits
// ahead) as they go, and the misses overlap.
constexpr uint32_t kAhead = 16;
constexpr int kNext[] = {1, 2, 0, 1};  // the corner after slot s of a triangle is kNext[s]

// The split records, and what the navigator learned of them, as plain pointers held in locals:
// the face stores (uint32_t) cannot then alias them or the navigator's counters, which the
// compiler would otherwise reload after each.
//
// What is learned: what a split writes besides its record, read from the faces as the splits
// before it left them the first time it is applied (a level's faces are a function of the split
// count, so it never changes). Later applies and undos then only store to the faces: the loops
// do not wait for a face to arrive (the stores drain in the background), and they have no branch
// on what they find.
struct SplitStream {
  uint32_t base_vertex_count;
  const uint32_t* parent;
  const uint32_t* moved_start;
  const uint32_t* moved_faces;
  const uint32_t* wing_start;
  const SplitWing* wings;
  uint32_t last_moved, last_wing;  // the last entry of moved_faces and of wings
  const uint8_t* moved_slot;       // per moved face: the parent's slot
  const uint8_t* wing_slots;       // per wing, split applied: v1's slot | w's slot << 2
  const uint32_t* wing_opposite;   // per wing: the fourth corner, kNoVertex in a triangle
};

// core/prefetch.h: a bare __builtin_prefetch loop is deleted by GCC at -O2. Moved face or wing k
// being written, the one kAhead on (back, when undoing) is asked for.
inline uint32_t entry_ahead(uint32_t k, uint32_t last, bool back) {
  return back ? k - std::min(k, kAhead) : std::min(k + kAhead, last);
}
template <bool kPrefetch>
inline void ask_moved(const SplitStream& m, const Face* faces, uint32_t k, bool back = false) {
  if (kPrefetch) prefetch<true>(faces + m.moved_faces[entry_ahead(k, m.last_moved, back)]);
}
template <bool kPrefetch>
inline void ask_wing(const SplitStream& m, const Face* faces, uint32_t k, bool back = false) {
  if (kPrefetch) prefetch<true>(faces + m.wings[entry_ahead(k, m.last_wing, back)].face);
}

// Undoing reads the records backwards, which the hardware's prefetchers follow less well: at
// 1 M vertices undoing went at 0.7 times the speed of applying, and the same once each stream's
// records kBehind splits back are asked for (the wings', 24 B a split, mattered most).
constexpr uint32_t kBehind = 64;
inline void ask_records_behind(const SplitStream& m, uint32_t i) {
  auto behind = [](uint32_t k) { return k - std::min(k, kBehind); };
  prefetch(m.parent + behind(i));
  prefetch(m.moved_start + behind(i));
  prefetch(m.wing_start + behind(i));
  prefetch(m.moved_slot + behind(m.moved_start[i]));
  prefetch(m.wing_slots + behind(m.wing_start[i]));
  prefetch(m.wing_opposite + behind(m.wing_start[i]));
  prefetch(m.wings + behind(m.wing_start[i]));
  prefetch(m.moved_faces + behind(m.moved_start[i]));
}

inline int slot_of(const Face& face, uint32_t v) {  // without a branch on which slot it is
  return (face.v[1] == v) + 2 * (face.v[2] == v) + 3 * (face.v[3] == v);
}

struct LearnedSlots {  // where learn_split() writes: SplitStream's last three, writable
  uint8_t* moved_slot;
  uint8_t* wing_slots;
  uint32_t* wing_opposite;
};

// Reads the faces split i will write (before it is applied) and records its slots.
template <bool kPrefetch>
inline void learn_split(const SplitStream& m, uint32_t i, const Face* faces,
                        const LearnedSlots& out) {
  const uint32_t v1 = m.parent[i];
  for (uint32_t k = m.moved_start[i], end = m.moved_start[i + 1]; k < end; ++k) {
    ask_moved<kPrefetch>(m, faces, k);
    const Face& face = faces[m.moved_faces[k]];
    out.moved_slot[k] = static_cast<uint8_t>(slot_of(face, v1));
    assert(face.v[out.moved_slot[k]] == v1);  // a face named twice would have lost it
  }
  for (uint32_t k = m.wing_start[i], end = m.wing_start[i + 1]; k < end; ++k) {
    ask_wing<kPrefetch>(m, faces, k);
    const SplitWing& w = m.wings[k];
    const int s = w.v0_slot();
    int s1, sw;
    if (w.was_triangle()) {  // v0, then v1 and w in the record's orientation
      s1 = w.v1_follows_v0() ? kNext[s] : kNext[s + 1];
      sw = 3 - s - s1;
      out.wing_opposite[k] = kNoVertex;
    } else {  // a triangle (v1, w, x) whose corners from slot s on move one slot up
      const Face& face = faces[w.face];
      const int t1 = slot_of(face, v1), tw = slot_of(face, w.vertex);
      assert(face.v[t1] == v1 && face.v[tw] == w.vertex && face.is_triangle());
      s1 = t1 + (t1 >= s);
      sw = tw + (tw >= s);
      out.wing_opposite[k] = face.v[3 - t1 - tw];
    }
    out.wing_slots[k] = static_cast<uint8_t>(s1 | sw << 2);
  }
}

// Split i, learned: stores only. Both kinds of wing alike: v0, v1, w and the fourth corner each
// to its slot (a re-created triangle's face is the next one, face_count).
template <bool kPrefetch>
inline void apply_known(const SplitStream& m, uint32_t i, Face* faces, uint32_t& face_count) {
  const uint32_t v0 = m.base_vertex_count + i;
  const uint32_t v1 = m.parent[i];
  for (uint32_t k = m.moved_start[i], end = m.moved_start[i + 1]; k < end; ++k) {
    ask_moved<kPrefetch>(m, faces, k);
    faces[m.moved_faces[k]].v[m.moved_slot[k]] = v0;
  }
  for (uint32_t k = m.wing_start[i], end = m.wing_start[i + 1]; k < end; ++k) {
    ask_wing<kPrefetch>(m, faces, k);
    const SplitWing& w = m.wings[k];
    const int s = w.v0_slot(), s1 = m.wing_slots[k] & 3, sw = m.wing_slots[k] >> 2;
    uint32_t* c = faces[w.face].v.data();
    c[s] = v0;
    c[s1] = v1;
    c[sw] = w.vertex;
    c[6 - s - s1 - sw] = m.wing_opposite[k];
    face_count += w.was_triangle();
  }
}

// Undoes split i, learned: stores only. A quad wing loses v0, its corners after slot s one slot
// down. A re-created triangle leaves the current faces (face_count); it is written the same way,
// where it no longer counts, so that no branch depends on the kind of wing.
template <bool kPrefetch>
inline void undo_known(const SplitStream& m, uint32_t i, Face* faces, uint32_t& face_count) {
  const uint32_t v1 = m.parent[i];
  if (kPrefetch) ask_records_behind(m, i);
  for (uint32_t k = m.wing_start[i + 1], begin = m.wing_start[i]; k-- > begin;) {
    ask_wing<kPrefetch>(m, faces, k, true);
    const SplitWing& w = m.wings[k];
    const int s = w.v0_slot(), s1 = m.wing_slots[k] & 3, sw = m.wing_slots[k] >> 2;
    const int sx = 6 - s - s1 - sw;
    uint32_t* c = faces[w.face].v.data();
    c[s1 - (s1 > s)] = v1;
    c[sw - (sw > s)] = w.vertex;
    c[sx - (sx > s)] = m.wing_opposite[k];
    c[3] = kNoVertex;
    face_count -= w.was_triangle();
  }
  for (uint32_t k = m.moved_start[i], end = m.moved_start[i + 1]; k < end; ++k) {
    ask_moved<kPrefetch>(m, faces, k, true);
    faces[m.moved_faces[k]].v[m.moved_slot[k]] = v1;
  }
}

// Levels level → k, all learned below max(level, k) but splits [learned, k), which are learned
// first (kPrefetch false: the faces stay in cache and the prefetches would only cost
// instructions).
template <bool kPrefetch>
void move_levels(const SplitStream& m, const LearnedSlots& out, uint32_t learned, uint32_t& level,
                 uint32_t k, Face* faces, uint32_t& face_count) {
  for (; level < std::min(k, learned); ++level) apply_known<kPrefetch>(m, level, faces, face_count);
  for (; level < k; ++level) {
    learn_split<kPrefetch>(m, level, faces, out);
    apply_known<false>(m, level, faces, face_count);  // the faces are in cache now
  }
  while (level > k) undo_known<kPrefetch>(m, --level, faces, face_count);
}

// Face arrays up to this many bytes stay in a core's L2 cache (1–2 MB on current x86 cores);
// on the crash boxes (80 KB) the prefetches cost more time than they saved.
constexpr size_t kCachedFaceBytes = size_t{1} << 20;

}  // namespace

void Navigator::set_level(uint32_t k) {
  const ProgressiveMesh& mesh = *mesh_;
  k = std::min(k, mesh.split_count());
  if (k > learned_) {     // room for what splits [learned_, k) will learn
    if (learned_ == 0) {  // all of it at once, not twice by growing: pages are given as touched
      moved_slot_.reserve(mesh.moved_faces.size());
      wing_slots_.reserve(mesh.wings.size());
      wing_opposite_.reserve(mesh.wings.size());
    }
    moved_slot_.resize(mesh.moved_start[k]);
    wing_slots_.resize(mesh.wing_start[k]);
    wing_opposite_.resize(mesh.wing_start[k]);
  }
  const SplitStream m{mesh.base_vertex_count,
                      mesh.parent.data(),
                      mesh.moved_start.data(),
                      mesh.moved_faces.data(),
                      mesh.wing_start.data(),
                      mesh.wings.data(),
                      static_cast<uint32_t>(mesh.moved_faces.size() - 1),
                      static_cast<uint32_t>(mesh.wings.size() - 1),
                      moved_slot_.data(),
                      wing_slots_.data(),
                      wing_opposite_.data()};
  const LearnedSlots out{moved_slot_.data(), wing_slots_.data(), wing_opposite_.data()};
  uint32_t level = level_, face_count = face_count_;
  if (faces_.size() * sizeof(Face) > kCachedFaceBytes)
    move_levels<true>(m, out, learned_, level, k, faces_.data(), face_count);
  else
    move_levels<false>(m, out, learned_, level, k, faces_.data(), face_count);
  learned_ = std::max(learned_, k);
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
