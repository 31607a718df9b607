// Which collapses are legal: the vertex classes as data (the habit of meshoptimizer's
// kCanCollapse table), then every rule of one collapse in CollapseRules::allows() (the habit of
// pmp-library's is_collapse_legal), one comment per rule, cheapest first.
//
// Every vertex has a class, fixed for the whole run because collapses never change it:
//   interior  all its edges have two faces of one part
//   boundary  exactly two boundary edges (one face each)
//   feature   exactly two feature edges: non-manifold (3+ faces, a T-joint of shells), between
//             two parts (when part boundaries are kept), or given by the user; no boundary edge
//   locked    user-locked, or where features meet: more than two boundary or feature edges,
//             boundary and feature edges together, a pinched (several-fan) vertex
// and kCanCollapse[class(v0)][class(v1)] says along which edges v0 may move onto v1. So a
// boundary vertex only slides along its boundary ((P2) holds by construction), a feature vertex
// only along its feature line, and a locked vertex never moves.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>

namespace dynpm::simplification {

enum class VertexClass : uint8_t { kInterior = 0, kBoundary = 1, kFeature = 2, kLocked = 3 };

enum class Along : uint8_t {
  kNever,         // v0 may not collapse into v1
  kAnyEdge,       // along any edge
  kBoundaryEdge,  // only along an edge with one face
  kFeatureEdge,   // only along a feature edge
};

// kCanCollapse[v0][v1]
// clang-format off
inline constexpr Along kCanCollapse[4][4] = {
  //        v1: interior        boundary             feature              locked
  /* interior */ {Along::kAnyEdge, Along::kAnyEdge,      Along::kAnyEdge,      Along::kAnyEdge},
  /* boundary */ {Along::kNever,   Along::kBoundaryEdge, Along::kBoundaryEdge, Along::kBoundaryEdge},
  /* feature  */ {Along::kNever,   Along::kNever,        Along::kFeatureEdge,  Along::kFeatureEdge},
  /* locked   */ {Along::kNever,   Along::kNever,        Along::kNever,        Along::kNever},
};
// clang-format on

inline Along can_collapse(VertexClass v0, VertexClass v1) {
  return kCanCollapse[static_cast<int>(v0)][static_cast<int>(v1)];
}

}  // namespace dynpm::simplification

#include <span>
#include <unordered_set>
#include <vector>

#include "collapse_mesh.h"

namespace dynpm::simplification {

class KeyStepQuadrics;  // quadrics.h

// Stamps on the few vertices one legality test marks (a few dozen), reused across tests: an
// open-addressed table that grows with the most one test marks, where a stamp per vertex of the
// mesh took 4 B per vertex at the simplifier's peak. A test takes two fresh stamps (begin());
// a slot with an older stamp counts as empty.
class VertexMarks {
 public:
  // A test begins: the first of its two stamps, above every stamp before (when they run out,
  // the table is emptied and they start again).
  uint32_t begin() {
    if (stamp_ > UINT32_MAX - 4) {
      std::fill(slots_.begin(), slots_.end(), Slot{});
      stamp_ = 0;
    }
    used_ = 0;
    return stamp_ += 2;
  }
  // The stamp of v in this test: `since` or later, else 0. Stamps of one test are ≥ since.
  uint32_t get(uint32_t v, uint32_t since) const {
    for (size_t i = slot_of(v);; i = (i + 1) & mask()) {
      if (slots_[i].stamp < since) return 0;
      if (slots_[i].vertex == v) return slots_[i].stamp;
    }
  }
  void set(uint32_t v, uint32_t value, uint32_t since) {
    if (2 * (used_ + 1) > slots_.size()) grow(since);
    for (size_t i = slot_of(v);; i = (i + 1) & mask()) {
      if (slots_[i].stamp < since) {
        slots_[i] = {v, value};
        ++used_;
        return;
      }
      if (slots_[i].vertex == v) {
        slots_[i].stamp = value;
        return;
      }
    }
  }

 private:
  struct Slot {
    uint32_t vertex = 0, stamp = 0;
  };
  size_t mask() const { return slots_.size() - 1; }
  size_t slot_of(uint32_t v) const { return (v * 0x9e3779b1u) >> shift_; }  // the high bits
  void grow(uint32_t since) {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    --shift_;
    used_ = 0;
    for (const Slot& s : old)
      if (s.stamp >= since) set(s.vertex, s.stamp, since);
  }
  std::vector<Slot> slots_ = std::vector<Slot>(64);
  size_t used_ = 0;
  uint32_t stamp_ = 0;
  int shift_ = 32 - 6;  // 2^6 slots
};

// (P1*) (paper §2): every vertex that shares a face with v0 and a face with v1 shares one face
// with both. `edge_faces` are the faces holding both v0 and v1.
bool second_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1,
                                std::span<const uint32_t> edge_faces, VertexMarks& marks);

// Hoppe's (P1), kept to show in tests where it is not enough (the paper's Figure 5): every
// vertex joined by an edge to both v0 and v1 shares a face with both.
bool first_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1);

// Feature edges: non-manifold (3+ faces, shells meeting in a T-joint), between two parts (when
// part boundaries are kept), or given by the user.
class FeatureEdges {
 public:
  FeatureEdges(const Topology& input, const SimplifyOptions& options);
  // `faces` are the faces holding the edge (a, b).
  bool is_feature_edge(uint32_t a, uint32_t b, std::span<const uint32_t> faces) const;
  bool has_user_edges() const { return !user_.empty(); }

 private:
  const std::vector<int32_t>& part_ids_;
  bool keep_part_boundaries_;
  std::unordered_set<uint64_t> user_;
};

// The rules of one collapse and the data they read: the vertex classes and, for (P3), the live
// vertices of each connected component.
class CollapseRules {
 public:
  CollapseRules(const Topology& input, const SimplifyOptions& options, const CollapseMesh& mesh,
                const KeyStepQuadrics& key_steps);

  // Classes from the input's edges (the table at the top of this file), and the components.
  void classify_vertices(const Adjacency& adjacency);
  VertexClass vertex_class(uint32_t v) const { return class_[v]; }
  const FeatureEdges& features() const { return features_; }

  // Whether v0 may collapse into v1 on the mesh as it is now. With optimal placement,
  // `placement` gets v1's new positions (the geometry rule tests them).
  bool allows(uint32_t v0, uint32_t v1, VertexMarks& marks, std::vector<Vec3>& placement) const;

  // After the collapse v0 → v1: v0's component has one vertex less. Atomic: regions of one
  // component collapse at once (regions.h).
  void collapsed(uint32_t v0) {
    std::atomic_ref<uint32_t>(component_live_[component_of(v0)])
        .fetch_sub(1, std::memory_order_relaxed);
  }

  // Connected components, numbered in the order of their first vertex; with their live vertices
  // at the start they size the islands (simplifier.cpp).
  uint32_t component_of(uint32_t v) const {
    return small_component_.empty() ? component_[v] : small_component_[v];
  }
  size_t component_count() const { return component_live_.size(); }
  uint32_t component_live(uint32_t c) const {
    // atomic_ref of a const object is C++26: the load writes nothing.
    return std::atomic_ref<uint32_t>(const_cast<uint32_t&>(component_live_[c]))
        .load(std::memory_order_relaxed);
  }

 private:
  struct EdgeFaces;
  EdgeFaces edge_faces(uint32_t v0, uint32_t v1) const;
  bool keeps_every_sheet(uint32_t v0, uint32_t v1, const EdgeFaces& edge) const;
  bool face_stays_sound(const Face& face, size_t k, uint32_t skip, uint32_t moved,
                        Vec3 target) const;
  bool no_face_folds(uint32_t v0, uint32_t v1, const std::vector<Vec3>& placement) const;
  bool optimal() const;

  const Topology& input_;
  const SimplifyOptions& options_;
  const CollapseMesh& mesh_;
  const KeyStepQuadrics& key_steps_;
  FeatureEdges features_;
  double cos_max_rotation_;
  std::vector<VertexClass> class_;
  // (P3) per connected component: each vertex's (in 16 bits when there are at most 65,536), and
  // the live vertices of each.
  std::vector<uint32_t> component_, component_live_;
  std::vector<uint16_t> small_component_;
};

}  // namespace dynpm::simplification
