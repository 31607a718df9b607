// The records and attributes sections of a SPLT (docs/FORMAT.md "Split records", "Split
// attributes"). One function per section codes a split both ways (Coder<kDecode>), so the
// encoder and the decoder cannot drift apart; the decoder's checks sit where it learns a value.
#include "split_records_coding.h"

#include <algorithm>
#include <cmath>

#include "core/face_geometry.h"
#include "dpm_format.h"

namespace dynpm::progressive {
namespace {

// The parts of the coding, for measurements (kRecordPartNames): each may go to its own stream.
enum Part {
  kParent,
  kWingCount,
  kWingKind,
  kQuadFace,
  kQuadBits,
  kTriangleVertex,
  kTriangleBits,
  kMoved,
  kErrors,
  kVertexIndex,
  kNodeId,
  kFaceIndex,
  kFacePart,
  kElementId
};

// Encodes values it is given, or decodes and returns them: one code path for both directions.
template <bool kDecode>
struct Coder {
  std::array<RangeEncoder*, kRecordParts> out{};  // encoder per part (usually all the same)
  RangeDecoder* in = nullptr;
  Part part = kParent;

  int bit(BitModel& m, int b) {
    if constexpr (kDecode) return in->bit(m);
    out[part]->bit(m, b);
    return b;
  }
  uint64_t u(UnsignedModel& m, uint64_t v) {
    if constexpr (kDecode) return m.decode(*in);
    m.encode(*out[part], v);
    return v;
  }
  int64_t s(SignedModel& m, int64_t v) {
    if constexpr (kDecode) return m.decode(*in);
    m.encode(*out[part], v);
    return v;
  }
};

// One split's record (ProgressiveMesh keeps it as a structure of arrays).
struct Record {
  uint32_t parent = 0;
  float error = 0;
  uint32_t wing_count = 0;
  std::array<SplitWing, 4> wings{};
  std::vector<uint32_t> moved;
};

// Fills r with split i (r's lists keep their memory from split to split).
void record_of(const ProgressiveMesh& mesh, uint32_t i, Record& r) {
  r.wings = {};
  r.parent = mesh.parent[i];
  r.error = mesh.error[i];
  r.wing_count = mesh.wing_start[i + 1] - mesh.wing_start[i];
  for (uint32_t k = 0; k < r.wing_count && k < 4; ++k)
    r.wings[k] = mesh.wings[mesh.wing_start[i] + k];
  r.moved.assign(mesh.moved_faces.begin() + mesh.moved_start[i],
                 mesh.moved_faces.begin() + mesh.moved_start[i + 1]);
}

// v's neighbours: the corners next to it in its faces, ascending, each once.
void neighbours(const RecordModels& st, uint32_t v, std::vector<uint32_t>& out) {
  out.clear();
  for (uint32_t f : st.vertex_faces_.of(v)) {
    const Face& face = st.faces_[f];
    const int n = face.degree(), a = corner_of(face, v);
    out.push_back(face.v[(a + 1) % n]);
    out.push_back(face.v[(a + n - 1) % n]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// std::stable_partition without its temporary buffer: the values for which front(v) holds
// first, each part in its order; `rest` is room.
template <class Front>
void stable_front(std::vector<uint32_t>& values, std::vector<uint32_t>& rest, Front front) {
  rest.clear();
  size_t k = 0;
  for (const uint32_t v : values)
    if (front(v))
      values[k++] = v;  // k never passes the value being read
    else
      rest.push_back(v);
  std::copy(rest.begin(), rest.end(), values.begin() + static_cast<ptrdiff_t>(k));
}

// A re-created triangle's orientation, predicted from a face of v1 on the edge v1–w: a mesh
// oriented alike runs the edge the other way in the new face. 0: no such face; else 1 + guess.
// A moved face holds the edge v0–w after the split: it says the other way round.
template <class Moved>
int orientation_guess(const RecordModels& st, uint32_t v1, uint32_t w, const Moved& moved) {
  int guess = 0;
  for (uint32_t f : st.vertex_faces_.of(v1)) {
    const Face& face = st.faces_[f];
    const int n = face.degree(), a = corner_of(face, v1);
    int g = 0;
    if (face.v[(a + 1) % n] == w) g = 1 + 0;  // v1 → w there: w → v1 here, v1 before v0
    if (face.v[(a + n - 1) % n] == w) g = 1 + 1;
    if (g == 0) continue;
    if (!moved(f)) return g;
    if (guess == 0) guess = 3 - g;
  }
  return guess;
}

// What a split's moved faces say about its wings: v1's edges in moved faces by their far end
// and how many moved faces hold them. A wing vertex ends an edge that one moved face holds (the
// frontier between v0's faces and v1's) and is not yet a wing vertex of this split.
struct MovedFan {
  explicit MovedFan(RecordModels::Scratch& s)
      : edge_ends(s.edge_ends), edge_uses(s.edge_uses), used(s.used) {
    edge_ends.clear(), edge_uses.clear(), used.clear();
  }
  std::vector<uint32_t>&edge_ends, &edge_uses, &used;

  void add(const Face& face, uint32_t v1) {
    const int n = face.degree(), a = corner_of(face, v1);
    for (uint32_t v : {face.v[(a + 1) % n], face.v[(a + n - 1) % n]}) {
      const auto it = std::find(edge_ends.begin(), edge_ends.end(), v);
      if (it == edge_ends.end())
        edge_ends.push_back(v), edge_uses.push_back(1);
      else
        ++edge_uses[static_cast<size_t>(it - edge_ends.begin())];
    }
  }
  bool frontier(uint32_t v) const {
    const auto it = std::find(edge_ends.begin(), edge_ends.end(), v);
    return it != edge_ends.end() && edge_uses[static_cast<size_t>(it - edge_ends.begin())] == 1 &&
           std::find(used.begin(), used.end(), v) == used.end();
  }
  // A triangle of v1 whose edge from v1 ends on the frontier.
  bool frontier_triangle(const Face& face, uint32_t v1) const {
    const int a = corner_of(face, v1);
    return frontier(face.v[(a + 1) % 3]) || frontier(face.v[(a + 2) % 3]);
  }
};

std::string at_split(uint32_t i, const std::string& what) {
  return "split " + std::to_string(i) + ": " + what;
}

// The record of split i (vertex v0) against the mesh before it. Empty, or what is wrong.
template <bool kDecode>
std::string code_record(Coder<kDecode>& c, RecordModels& st, uint32_t i, uint32_t v0, Record& r) {
  // The error: how many grid steps down from the split before.
  c.part = kErrors;
  uint32_t code = 0;
  if constexpr (!kDecode) {
    code = error_code_at_least(r.error, st.error_reference_);
    if (error_of_code(code, st.error_reference_) != r.error || code > st.error_code_)
      return at_split(i, "the error is not on the grid or increases (prepare_split_records)");
  }
  const uint64_t down = c.u(st.error_step, st.error_code_ - code);
  if (down > st.error_code_) return at_split(i, "error is not valid");
  st.error_code_ -= static_cast<uint32_t>(down);
  r.error = error_of_code(st.error_code_, st.error_reference_);

  // The parent: within a run of equal errors (the build orders each run by parent, split_order.h)
  // a step from the parent before; else v0 − 1 − parent.
  c.part = kParent;
  if (down == 0 && st.last_parent_ != kNoVertex) {
    const int64_t step = c.s(st.parent_step, int64_t{r.parent} - int64_t{st.last_parent_});
    const int64_t p = int64_t{st.last_parent_} + step;
    if (p < 0 || p >= v0) return at_split(i, "parent out of range");
    r.parent = static_cast<uint32_t>(p);
  } else {
    const uint64_t dp = c.u(st.parent, v0 - 1 - r.parent);
    if (dp >= v0) return at_split(i, "parent out of range");
    r.parent = static_cast<uint32_t>(v0 - 1 - dp);
  }
  st.last_parent_ = r.parent;
  const uint32_t v1 = r.parent;
  const std::span<const uint32_t> fan = std::as_const(st.vertex_faces_).of(v1);
  for (uint32_t f : fan) prefetch(&st.faces_[f]);  // scattered: their misses overlap this way
  // Moved faces first: a bit per face of v1 (ascending), by its kind and how many moved so far.
  // v0's old faces then say where its wings are: each wing vertex is a corner of a moved face.
  c.part = kMoved;
  std::vector<uint32_t>& moved = st.scratch_.moved;
  moved.clear();
  MovedFan edges(st.scratch_);
  st.near_v0_.clear();
  auto near_v0 = [&](uint32_t v) { return st.near_v0_.contains(v); };
  size_t next = 0;  // encoder: r.moved is ascending
  for (uint32_t f : fan) {
    bool beside = false;  // shares a corner other than v1 with a face moved before it
    if (!moved.empty())
      for (uint32_t v : st.faces_[f].v) beside |= v != kNoVertex && v != v1 && near_v0(v);
    const size_t ctx =
        (st.faces_[f].is_triangle() ? 6 : 0) + (beside ? 3 : 0) + std::min<size_t>(moved.size(), 2);
    const bool is_moved = !kDecode && next < r.moved.size() && r.moved[next] == f;
    if (!c.bit(st.moved[ctx], is_moved)) continue;
    moved.push_back(f), next += is_moved;
    for (uint32_t v : st.faces_[f].v)
      if (v != kNoVertex && v != v1) st.near_v0_.insert(v);
    edges.add(st.faces_[f], v1);
  }
  if (!kDecode && moved.size() != r.moved.size())
    return at_split(i, "a moved face is not a face of the parent, or they are not ascending");
  r.moved.swap(moved);
  auto taken = [&](uint32_t f) {  // moved, or already a quad wing of this split
    return std::binary_search(r.moved.begin(), r.moved.end(), f);
  };

  c.part = kWingCount;
  const uint64_t wings = c.u(st.wing_count, r.wing_count);
  if (wings > 4) return at_split(i, "more than 4 wings");
  r.wing_count = static_cast<uint32_t>(wings);
  uint32_t created = 0;
  std::vector<uint32_t>& quads = st.scratch_.quads;  // this split's quad wings so far
  quads.clear();
  for (uint32_t k = 0; k < r.wing_count; ++k) {
    SplitWing& w = r.wings[k];
    // A quad wing's face: an index into v1's free triangles (not moved, not a wing yet) near v0
    // (holding a moved face's corner), or into all when none is; those on the frontier first,
    // each part ascending. Whether there are any, on the frontier or not, predicts its kind.
    std::vector<uint32_t>&triangles = st.scratch_.triangles, &beside = st.scratch_.beside;
    triangles.clear(), beside.clear();
    bool on_frontier = false;
    for (uint32_t f : fan) {
      const Face& face = st.faces_[f];
      if (!face.is_triangle() || taken(f) ||
          std::find(quads.begin(), quads.end(), f) != quads.end())
        continue;
      triangles.push_back(f);
      if (near_v0(face.v[0]) || near_v0(face.v[1]) || near_v0(face.v[2])) beside.push_back(f);
      on_frontier |= edges.frontier_triangle(face, v1);
    }
    if (!beside.empty()) triangles.swap(beside);
    stable_front(triangles, st.scratch_.rest,
                 [&](uint32_t f) { return edges.frontier_triangle(st.faces_[f], v1); });
    const size_t candidates = triangles.empty() ? 0 : on_frontier ? 2 : 1;
    const size_t ctx = 16 * candidates + 4 * (r.wing_count - 1) + k;  // and by count, by place
    c.part = kWingKind;
    const int triangle = c.bit(st.was_triangle[ctx], w.was_triangle());
    if (!triangle) {
      c.part = kQuadFace;
      uint64_t index = 0;
      if constexpr (!kDecode) {
        const auto it = std::find(triangles.begin(), triangles.end(), w.face);
        if (it == triangles.end())
          return at_split(i, "a quad wing is not a triangle of the parent");
        index = static_cast<uint64_t>(it - triangles.begin());
      }
      index = c.u(st.quad_face, index);
      if (index >= triangles.size()) return at_split(i, "quad wing face out of range");
      w.face = triangles[index];
      quads.push_back(w.face);
      // w: the corner after v1 or the one before it, guessed as the one near v0.
      const Face& face = st.faces_[w.face];
      const int a = corner_of(face, v1);
      const uint32_t after = face.v[(a + 1) % 3], before = face.v[(a + 2) % 3];
      if (!kDecode && w.vertex != after && w.vertex != before)
        return at_split(i, "a quad wing's vertex is not in its face");
      c.part = kQuadBits;
      const bool guess_before = near_v0(before) && !near_v0(after);
      const bool is_before =
          c.bit(st.quad_side, (w.vertex == before) != guess_before) != guess_before;
      w.vertex = is_before ? before : after;
      const int b = corner_of(face, w.vertex);
      // v0 goes between v1 and w: one slot, or 0 and 3 alike when they hold slots 0 and 2.
      int slot = std::max(a, b);
      if (std::min(a, b) == 0 && slot == 2)
        slot = c.bit(st.quad_slot_end, w.v0_slot() == 3) ? 3 : 0;
      if (!kDecode && slot != w.v0_slot())
        return at_split(i, "a quad wing's slot is not between v1 and w");
      const int follows = (b + 1) % 3 == a;  // w → v1 in the triangle: w, v0, v1 in the quad
      const int flag = c.bit(st.quad_follows, w.v1_follows_v0() != follows) ^ follows;
      w.flags = static_cast<uint8_t>((flag ? SplitWing::kV1FollowsV0 : 0) |
                                     (slot << SplitWing::kSlotShift));
      edges.used.push_back(w.vertex);
      continue;
    }
    // A triangle wing: w as an index into v1's neighbours (those on the frontier first, then the
    // others near v0, then the rest), or the escape and v0 − 1 − w.
    std::vector<uint32_t>& near = st.scratch_.near;
    neighbours(st, v1, near);
    stable_front(near, st.scratch_.rest, near_v0);
    stable_front(near, st.scratch_.rest, [&](uint32_t v) { return edges.frontier(v); });
    c.part = kTriangleVertex;
    uint64_t index = near.size();
    if constexpr (!kDecode) {
      const auto it = std::find(near.begin(), near.end(), w.vertex);
      if (it != near.end()) index = static_cast<uint64_t>(it - near.begin());
    }
    index = c.u(st.neighbour, index);
    if (index > near.size()) return at_split(i, "wing vertex out of range");
    if (index < near.size()) {
      w.vertex = near[index];
    } else {
      const uint64_t dv = c.u(st.far_vertex, v0 - 1 - w.vertex);
      if (dv >= v0) return at_split(i, "wing vertex out of range");
      w.vertex = static_cast<uint32_t>(v0 - 1 - dv);
    }
    w.face = st.face_count_ + created++;
    edges.used.push_back(w.vertex);
    c.part = kTriangleBits;
    const int guess = orientation_guess(st, v1, w.vertex, taken);
    const int expected = guess == 2;
    const int follows = c.bit(st.tri_follows[guess != 0], w.v1_follows_v0() != expected) ^ expected;
    int slot = c.bit(st.tri_slot[0], w.v0_slot() != 0);
    if (slot) slot += c.bit(st.tri_slot[1], w.v0_slot() == 2);
    if (!kDecode && slot != w.v0_slot()) return at_split(i, "a triangle wing has slot 3");
    w.flags =
        static_cast<uint8_t>(SplitWing::kWasTriangle | (follows ? SplitWing::kV1FollowsV0 : 0) |
                             (slot << SplitWing::kSlotShift));
  }
  return {};
}

// The faces each vertex has, after split i was applied to st.faces_.
void update_vertex_faces(RecordModels& st, const ProgressiveMesh& mesh, uint32_t i) {
  const uint32_t v0 = mesh.base_vertex_count + i, v1 = mesh.parent[i];
  ListPool& fans = st.vertex_faces_;  // v0's list is made by assign()
  const auto moved =
      std::span(mesh.moved_faces)
          .subspan(mesh.moved_start[i], mesh.moved_start[i + 1] - mesh.moved_start[i]);
  fans.assign(v0, moved);
  fans.erase_if(v1, [&](uint32_t f) { return std::binary_search(moved.begin(), moved.end(), f); });
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
    const SplitWing& w = mesh.wings[k];
    fans.push_back(v0, w.face);
    if (!w.was_triangle()) continue;
    fans.push_back(v1, w.face);  // the newest face: the lists stay ascending
    fans.push_back(w.vertex, w.face);
  }
  std::sort(fans.of(v0).begin(), fans.of(v0).end());
}

// The attributes of split i's vertex and of the faces it created, against the mesh after it.
template <bool kDecode>
std::string code_attributes(Coder<kDecode>& c, RecordModels& st, ProgressiveMesh& mesh,
                            uint32_t i) {
  const uint32_t v0 = mesh.base_vertex_count + i, v1 = mesh.parent[i];
  // The original index by its rank among the free ones, from the parent's (neighbours in the
  // mesh are often neighbours in the input's order); the node id moves with it.
  c.part = kVertexIndex;
  const int64_t index_guess = mesh.vertex_original_index[v1];
  const int64_t node_guess = mesh.node_ids[v1];
  FreeIndices& free = st.free_vertices_;
  const int64_t rank_guess = free.below(static_cast<uint32_t>(index_guess));
  int64_t index = 0, node = 0, rank = 0;
  if constexpr (!kDecode) {
    index = mesh.vertex_original_index[v0], node = mesh.node_ids[v0];
    if (!free.is_free(static_cast<uint32_t>(index)))
      return at_split(i, "a vertex's original index is given twice");
    rank = free.below(static_cast<uint32_t>(index));
  }
  rank = rank_guess + c.s(st.vertex_index, rank - rank_guess);
  if (rank < 0 || rank >= free.count())
    return at_split(i, "a vertex's original index is out of range");
  index = free.nth(static_cast<uint32_t>(rank));
  free.take(static_cast<uint32_t>(index));
  c.part = kNodeId;
  node = node_guess + (index - index_guess) +
         c.s(st.node_id, node - node_guess - (index - index_guess));
  if (!id_fits(node)) return at_split(i, kIdOutOfRange);
  if constexpr (kDecode) {
    mesh.vertex_original_index.push_back(static_cast<uint32_t>(index));
    mesh.node_ids.push_back(node);
  }

  // Created faces: like their neighbour (the quad wing, else the first moved face, else a
  // face v1 had before).
  uint32_t created = 0;
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
    created += mesh.wings[k].was_triangle();
  const uint32_t first_created = st.face_count_ - created;
  uint32_t like = kNoIndex;
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1] && like == kNoIndex; ++k)
    if (!mesh.wings[k].was_triangle()) like = mesh.wings[k].face;
  if (like == kNoIndex && mesh.moved_start[i + 1] > mesh.moved_start[i])
    like = mesh.moved_faces[mesh.moved_start[i]];
  if (like == kNoIndex && !st.vertex_faces_.empty(v1) && st.vertex_faces_.of(v1)[0] < first_created)
    like = st.vertex_faces_.of(v1)[0];
  const int64_t part_guess = like == kNoIndex ? 0 : mesh.part_ids[like];
  const int64_t face_guess = like == kNoIndex ? 0 : mesh.face_original_index[like];
  const int64_t element_guess = like == kNoIndex ? 0 : mesh.element_ids[like];
  FreeIndices& free_faces = st.free_faces_;
  const int64_t rank_guess_face = free_faces.below(static_cast<uint32_t>(face_guess));
  for (uint32_t g = first_created; g < st.face_count_; ++g) {
    int64_t part = part_guess, face = 0, element = 0, face_rank = 0;
    if constexpr (!kDecode) {
      part = mesh.part_ids[g], face = mesh.face_original_index[g], element = mesh.element_ids[g];
      if (!free_faces.is_free(static_cast<uint32_t>(face)))
        return at_split(i, "a face's original index is given twice");
      face_rank = free_faces.below(static_cast<uint32_t>(face));
    }
    c.part = kFacePart;
    if (c.bit(st.same_part, part != part_guess))
      part = part_guess + c.s(st.part, part - part_guess);
    c.part = kFaceIndex;
    face_rank = rank_guess_face + c.s(st.face_index, face_rank - rank_guess_face);
    if (face_rank < 0 || face_rank >= free_faces.count())
      return at_split(i, "a face's original index is out of range");
    face = free_faces.nth(static_cast<uint32_t>(face_rank));
    free_faces.take(static_cast<uint32_t>(face));
    const int64_t step = face - face_guess;
    c.part = kElementId;
    element = element_guess + step + c.s(st.element_id, element - element_guess - step);
    if constexpr (kDecode) {
      if (part < INT32_MIN || part > INT32_MAX) return at_split(i, "a part id is out of range");
      if (!id_fits(element)) return at_split(i, kIdOutOfRange);
      mesh.part_ids.push_back(static_cast<int32_t>(part));
      mesh.face_original_index.push_back(static_cast<uint32_t>(face));
      mesh.element_ids.push_back(element);
    }
  }
  return {};
}

// Applies split i to the coding's mesh (checked) and updates each vertex's faces.
std::string apply(RecordModels& st, const ProgressiveMesh& mesh, uint32_t i) {
  std::string problem;
  uint32_t created = 0;
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
    created += mesh.wings[k].was_triangle();
  if (uint64_t{st.face_count_} + created > mesh.full_face_count)
    return at_split(i, "the splits create more faces than the header says");
  st.faces_.resize(std::max<size_t>(st.faces_.size(), st.face_count_ + created));
  if (!apply_split(mesh, i, st.faces_, st.face_count_, &problem)) return problem;
  update_vertex_faces(st, mesh, i);
  return {};
}

}  // namespace

RecordModels::RecordModels(const ProgressiveMesh& base, Room room)
    : faces_(base.base_faces),
      face_count_(base.base_face_count),
      // A face is on at most 4 lists; lists that grow move, which twice as much room covers.
      vertex_faces_(room == Room::kFull ? base.full_vertex_count : base.base_vertex_count,
                    size_t{room == Room::kFull ? base.full_face_count : base.base_face_count} * 8),
      free_vertices_(base.full_vertex_count),
      free_faces_(base.full_face_count),
      error_reference_(error_reference(base.base_error)),
      error_code_(error_code_at_least(base.base_error, error_reference_)) {
  for (uint32_t v = 0; v < base.base_vertex_count && v < base.vertex_original_index.size(); ++v)
    if (free_vertices_.is_free(base.vertex_original_index[v]))
      free_vertices_.take(base.vertex_original_index[v]);
  for (uint32_t f = 0; f < face_count_ && f < base.face_original_index.size(); ++f)
    if (free_faces_.is_free(base.face_original_index[f]))
      free_faces_.take(base.face_original_index[f]);
  for (uint32_t f = 0; f < face_count_; ++f)
    for (uint32_t v : faces_[f].v)
      if (v != kNoVertex && v < vertex_faces_.lists()) vertex_faces_.push_back(v, f);
  if (room == Room::kFull) faces_.reserve(base.full_face_count);
}

namespace {

Result<std::array<std::string, kRecordParts>> encode_parts(const ProgressiveMesh& mesh,
                                                           uint32_t first, uint32_t last,
                                                           RecordModels& st, bool per_part,
                                                           const AfterSplit& after_split,
                                                           SplitSections sections) {
  std::array<RangeEncoder, kRecordParts> encoders;
  Coder<false> records, attributes;
  for (int p = 0; p < kRecordParts; ++p) {
    records.out[p] = &encoders[per_part ? p : 0];
    attributes.out[p] = &encoders[per_part ? p : 1];
  }
  ProgressiveMesh& m = const_cast<ProgressiveMesh&>(mesh);  // the encoder only reads it
  Record r;
  for (uint32_t i = first; i < last; ++i) {
    st.prefetch_fans_ahead(mesh, i, last);
    std::string problem;
    if (sections != SplitSections::kAttributes) {
      record_of(mesh, i, r);
      problem = code_record(records, st, i, mesh.base_vertex_count + i, r);
    }
    if (problem.empty()) problem = apply(st, mesh, i);
    if (problem.empty() && sections != SplitSections::kRecords)
      problem = code_attributes(attributes, st, m, i);
    if (!problem.empty()) return Status::error("cannot code " + problem);
    if (after_split) after_split(i);
  }
  std::array<std::string, kRecordParts> out;
  for (int p = 0; p < kRecordParts; ++p) out[p] = encoders[p].finish();
  return out;
}

}  // namespace

Result<std::pair<std::string, std::string>> encode_split_records(const ProgressiveMesh& mesh,
                                                                 uint32_t first, uint32_t last,
                                                                 RecordModels& models,
                                                                 const AfterSplit& after_split,
                                                                 SplitSections sections) {
  auto parts = encode_parts(mesh, first, last, models, false, after_split, sections);
  if (!parts.ok()) return parts.status();
  std::pair<std::string, std::string> out{std::move((*parts)[0]), std::move((*parts)[1])};
  if (sections == SplitSections::kAttributes) out.first.clear();  // an empty coder's bytes
  if (sections == SplitSections::kRecords) out.second.clear();
  return out;
}

Result<std::array<size_t, kRecordParts>> split_record_part_bytes(const ProgressiveMesh& mesh) {
  RecordModels models(mesh);
  auto parts = encode_parts(mesh, 0, mesh.split_count(), models, true, {}, SplitSections::kBoth);
  if (!parts.ok()) return parts.status();
  std::array<size_t, kRecordParts> bytes{};
  for (int p = 0; p < kRecordParts; ++p) bytes[p] = (*parts)[p].size();
  return bytes;
}

std::optional<PayloadError> decode_split_records(std::string_view records,
                                                 std::string_view attributes, uint32_t first,
                                                 uint32_t count, ProgressiveMesh& mesh,
                                                 RecordModels& st, const AfterSplit& after_split) {
  RangeDecoder rd(records), ad(attributes);
  Coder<true> rc, ac;
  rc.in = &rd, ac.in = &ad;
  auto problem = [](std::string what) { return PayloadError{std::move(what), 0}; };
  Record r;
  for (uint32_t i = first; i < first + count; ++i) {
    r.wing_count = 0, r.wings = {};
    std::string what = code_record(rc, st, i, mesh.base_vertex_count + i, r);
    if (!rd.ok()) return problem("the split records section is cut short or damaged");
    if (!what.empty()) return problem(what);
    mesh.parent.push_back(r.parent);
    mesh.error.push_back(r.error);
    mesh.wings.insert(mesh.wings.end(), r.wings.begin(), r.wings.begin() + r.wing_count);
    mesh.wing_start.push_back(static_cast<uint32_t>(mesh.wings.size()));
    mesh.moved_faces.insert(mesh.moved_faces.end(), r.moved.begin(), r.moved.end());
    mesh.moved_start.push_back(static_cast<uint32_t>(mesh.moved_faces.size()));
    what = apply(st, mesh, i);
    if (!what.empty()) return problem(what);
    what = code_attributes(ac, st, mesh, i);
    if (!ad.ok()) return problem("the split attributes section is cut short or damaged");
    if (!what.empty()) return problem(what);
    if (after_split) after_split(i);
  }
  if (first + count == mesh.full_split_count && st.face_count_ != mesh.full_face_count)
    return problem("the splits create fewer faces than the header says");
  if (!rd.exhausted()) return problem("bytes left over after the split records");
  if (!ad.exhausted()) return problem("bytes left over after the split attributes");
  return std::nullopt;
}

}  // namespace dynpm::progressive
