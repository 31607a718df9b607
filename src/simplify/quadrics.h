// The cost of a collapse (paper §3, method (1*)): one quadric per vertex per key step, built in
// named phases, and the largest error over the key steps. The quadric algebra itself is
// quadric.h; this file knows the mesh.
//
// Building, per vertex v and key step t, gathered per vertex (one thread writes one quadric):
//   1. constrained_edges()   which edges of each face carry a constraint plane (boundary or
//                            feature edges), once for the whole run
//   2. per face of v, in v's face order:
//      face_shape()           the face's unit normal (a triangle's own, a skew quad's
//                             quad_plane(), core/face_geometry.h) and area; the plane through
//                             the face's centroid (a triangle: its first corner) around v,
//                             weighted by the area (an island's faces' shapes are made once a
//                             key step, before its vertices' quadrics)
//      add_constraint_planes() through v's constrained edges in the face, perpendicular to it,
//                             weighted boundary_weight · |edge|²
//   3. add_regularizer()      an isotropic quadric weighted regularize × the area of v's faces
//                             (the shape term, docs/simplify.md), not counted in the weight w
// The phases alternate per face, not one after the other over all faces: the sums stay in the
// order that makes every output byte-identical to what it was.
//
// The field term is field_term.h; how it combines with the geometric error is Worst below.
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <span>
#include <vector>

#include "collapse_mesh.h"
#include "core/prefetch.h"
#include "dynpm/simplify.h"
#include "field_term.h"
#include "legality.h"
#include "quadric.h"
#include "spares.h"

namespace dynpm::simplification {

// Paper method (1*): a collapse costs the largest of its errors over the key steps. Each step
// offers its geometric weighted mean squared distance and its field term (both squared
// lengths) — for every direction rated at once, kDirections of them — to worst[d].offer().
// FieldCombine::kAdd: the root of the largest sum; kScale: the largest geometric error (at
// least kFieldGeometryFloor) times 1 + the largest field term f, both in diagonals, plus f's
// part beyond kFieldJumpAllowance as a length. Without cost fields both are the geometric error
// alone.
struct Worst {
  double squared = 0, geometric = 0, field = 0;
  void offer(double geometric_squared, double field_squared) {
    squared = std::max(squared, geometric_squared + field_squared);
    geometric = std::max(geometric, geometric_squared);
    field = std::max(field, field_squared);
  }
  double error(double diagonal, FieldCombine combine, bool fields) const {
    if (!fields || combine == FieldCombine::kAdd) return std::sqrt(squared) / diagonal;
    const double f = std::sqrt(field) / diagonal;
    const double jump = std::max(0.0, f - kFieldJumpAllowance) * kFieldJumpLength;
    return std::max(std::sqrt(geometric) / diagonal, kFieldGeometryFloor) * (1 + f) + jump;
  }
};
template <size_t kDirections, class PerStep>
std::array<double, kDirections> worst_over_key_steps(size_t key_count, double diagonal,
                                                     FieldCombine combine, bool fields,
                                                     PerStep&& per_step) {
  std::array<Worst, kDirections> worst{};
  for (size_t k = 0; k < key_count; ++k) per_step(k, worst);
  std::array<double, kDirections> error{};
  for (size_t d = 0; d < kDirections; ++d) error[d] = worst[d].error(diagonal, combine, fields);
  return error;
}

// Which edges of each face carry a constraint plane: bit c is the edge from corner c to the
// next corner, set when that edge is a boundary or feature edge.
std::vector<uint8_t> constrained_edges(const Topology& input, const Adjacency& adjacency,
                                       const FeatureEdges& features);

// Positions and quadrics of every vertex in every key step, vertex-major (one vertex's steps
// together: rating an edge reads two short runs of memory): a row per vertex. Rows of removed
// vertices are never read again; once a sixteenth of the rows are such, drop_removed() moves the
// live rows to the front (in vertex order) and gives the rest back to the system, and a vertex
// finds its row through row_ from then on. The collapse log grows while the rows shrink.
class KeyStepQuadrics {
 public:
  // Reads the key steps' positions (up to `threads` at once) and, in the same pass, the cost
  // fields' values; the diagonal is that of the positions' common bounding box. Reports
  // "reading key steps".
  Status load_key_steps(const FrameSource& frames, const Topology& input,
                        std::span<const size_t> key_steps, std::span<const CostField> fields,
                        FieldForm form, FieldCombine combine, unsigned threads,
                        const ProgressCallback& progress);
  // The quadrics of the input mesh (phases at the top of this file), and the field term's. With
  // islands (mesh.island_count() > 1) the field term's alone: an island's quadrics are made when
  // it opens and given back when it closes, so that only the islands at work hold theirs (with
  // every key step they are most of the simplifier's memory; docs/simplify.md "Islands").
  void build(const Topology& input, const CollapseMesh& mesh, std::vector<uint8_t> constrained,
             double boundary_weight, double regularize, unsigned threads);
  // With islands: the quadrics of island i's vertices, made on the calling thread (islands open
  // on several at once), and given back: the block is kept for the next island to open, until
  // drop_spare_blocks() once every island is done.
  void open_island(size_t i, const CollapseMesh& mesh);
  void close_island(size_t i, const CollapseMesh& mesh);
  void drop_spare_blocks();
  // The most vertices whose quadrics were held at once (SimplifyResult::quadric_vertices_held).
  size_t most_held() const {
    return island_rows_.empty() ? size_t{input_->vertex_count} : most_held_.load();
  }

  size_t key_count() const { return key_count_; }
  double diagonal() const { return diagonal_; }
  const BoundingBox& box() const { return box_; }  // of the key steps' positions
  Vec3 position(uint32_t v, size_t k) const { return load(position_data(v, k)); }
  const float* position_data(uint32_t v, size_t k) const {
    return &positions_[(row(v) * key_count_ + k) * 3];
  }
  const LocalQuadric& quadric(uint32_t v, size_t k) const {
    return island_rows_.empty() ? quadrics_[row(v) * key_count_ + k] : island_rows_[v][k];
  }
  // Asks for the quadrics and positions of `vertices` ahead of use (they are scattered across
  // neighbours): where their rows are first, once rows have moved or with islands.
  void prefetch(std::span<const uint32_t> vertices) const {
    if (!island_rows_.empty()) {
      for (uint32_t v : vertices) dynpm::prefetch(&island_rows_[v]);
      for (uint32_t v : vertices) {
        dynpm::prefetch(island_rows_[v]);
        dynpm::prefetch(&positions_[v * key_count_ * 3]);
      }
      return;
    }
    if (!row_.empty())
      for (uint32_t v : vertices) dynpm::prefetch(&row_[v]);
    for (uint32_t v : vertices) {
      dynpm::prefetch(&quadrics_[row(v) * key_count_]);
      dynpm::prefetch(&positions_[row(v) * key_count_ * 3]);
    }
  }
  // After a collapse, without islands: when a sixteenth of the rows belong to vertices `mesh` has
  // removed, the live rows move to the front and the memory of the others is released.
  void drop_removed(const CollapseMesh& mesh);

  // Q_t,v0 + Q_t,v1 with its origin at v1's position in key step k.
  Quadric merged_quadric(uint32_t v0, uint32_t v1, size_t k) const;

  // The cost of v0 → v1 with optimal placement: per key step the weighted RMS distance to the
  // planes of (Q_t,v0 + Q_t,v1) at their minimiser (v1 stays when locked; the better endpoint
  // when the system is ill-conditioned and v1 interior); `placement` gets v1's new positions.
  double collapse_error(uint32_t v0, uint32_t v1, VertexClass v1_class,
                        std::vector<Vec3>& placement) const;
  // The cost of v0 → v1 with half-edge placement: v1's own quadric is c at its position, v0's
  // is evaluated across the edge; never below v0's own RMS distance there (the cost floor).
  double half_edge_error(uint32_t v0, uint32_t v1) const;
  // half_edge_error() of a → b and of b → a at once: rating an edge needs both, and the
  // quadrics are loaded once.
  std::pair<double, double> half_edge_errors(uint32_t a, uint32_t b) const;

  // After the collapse v0 → v1: Q_t,v1 = Q_t,v0 + Q_t,v1, and with a placement v1 moved there
  // (its quadric re-centred on the new position); placement is null for half-edge collapses.
  // Returns v1's positions, xyz per key step. Collapses of different islands may merge at once,
  // each with a scratch of its own.
  struct MergeScratch {
    std::vector<Vec3> offsets, moves;  // per key step
  };
  std::span<const float> merge(uint32_t v0, uint32_t v1, const std::vector<Vec3>* placement,
                               MergeScratch& scratch);

  // Positions of the given vertices in key step k, xyz each.
  std::vector<float> positions_of(std::span<const uint32_t> vertices, size_t k) const;

 private:
  size_t row(uint32_t v) const { return row_.empty() ? v : row_[v]; }
  float* position_data(uint32_t v, size_t k) { return &positions_[(row(v) * key_count_ + k) * 3]; }
  LocalQuadric& quadric(uint32_t v, size_t k) {
    return island_rows_.empty() ? quadrics_[row(v) * key_count_ + k] : island_rows_[v][k];
  }
  size_t collapses_before_drop(const CollapseMesh& mesh) const;
  // The sum of v's faces' planes in key step k, around v's position; shape(f) gives face f's
  // unit normal and area (FaceShape, quadrics.cpp).
  template <class Shape>
  Quadric vertex_quadric(const CollapseMesh& mesh, uint32_t v, size_t k, Shape&& shape) const;

  size_t key_count_ = 0;
  std::vector<float> positions_;        // #V × #key steps × xyz
  std::vector<LocalQuadric> quadrics_;  // #V × #key steps, each around its own vertex
  std::vector<uint32_t> row_;           // vertex → row, once rows have moved (else row v)
  // With islands: each open island's quadrics (#its vertices × #key steps), and each vertex's
  // first one while its island is open. Rows never move then: positions stay in row v.
  std::vector<std::vector<LocalQuadric>> island_quadrics_;
  std::vector<LocalQuadric*> island_rows_;
  Spares<std::vector<LocalQuadric>> spare_blocks_;  // closed islands' blocks, for the next
  // Each face's place among its island's faces while the island opens (islands share no face,
  // so islands opening at once write apart).
  std::vector<uint32_t> island_face_slot_;
  std::atomic<size_t> held_{0}, most_held_{0};  // vertices of the open islands
  // What an island's quadrics are made of (build()'s arguments).
  const Topology* input_ = nullptr;
  std::vector<uint8_t> constrained_;
  double boundary_weight_ = 0, regularize_ = 0;
  double diagonal_ = 1;
  BoundingBox box_;
  FieldTerm fields_;
  FieldCombine combine_ = FieldCombine::kAdd;
};

}  // namespace dynpm::simplification
