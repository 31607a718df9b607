// dynpm/lod.h — the navigator: a progressive mesh at any resolution and any time step.
//
// It holds the current faces (a prefix of the face numbering) and applies or undoes the splits
// between the old and the new level in place, so changing resolution costs time proportional
// to the change. Positions need no work per level: half-edge collapses keep original positions,
// so vertex v has the same position at every level where it exists.
#pragma once

#include <span>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm {

// Shows a ProgressiveMesh at any resolution and time. Holds the current faces; resolution
// changes apply or undo only the splits between the old and the new level.
class Navigator {
 public:
  explicit Navigator(const ProgressiveMesh& mesh);  // starts at the base mesh

  const ProgressiveMesh& mesh() const { return *mesh_; }
  uint32_t level() const { return level_; }  // splits applied
  uint32_t vertex_count() const { return mesh_->base_vertex_count + level_; }
  uint32_t face_count() const { return face_count_; }
  double error() const { return mesh_->level_error(level_); }

  // Clamped to [base_vertex_count, mesh.vertex_count()].
  void set_vertex_count(uint32_t n);
  void set_level(uint32_t k);
  // The coarsest level whose error is ≤ e (absolute units).
  void set_error(double e);

  // Current faces: [0, face_count()).
  std::span<const Face> faces() const { return {faces_.data(), face_count_}; }
  // xyz of vertices [0, vertex_count()) at time step t; fractional t interpolates linearly
  // between the neighbouring steps. out.size() ≥ 3 · vertex_count().
  void positions(double t, std::span<float> out) const;
  // Geomorph towards this level from the coarser level `from`: vertices created after `from`
  // start at their ancestor's position at that level (alpha 0) and reach their own (alpha 1).
  void geomorph(uint32_t from, double alpha, double t, std::span<float> out) const;
  // The values of result field `field` at step t shown at this level (docs/FORMAT.md, "Shown
  // values"): each present vertex (node field) or face (element field) shows the aggregate of the
  // original values it stands for. out.size() ≥ vertex_count() or face_count().
  void field_values(size_t field, size_t t, std::span<float> out,
                    FieldAggregate aggregate = FieldAggregate::kMaxAbs) const;
  // The field error of this level, a fraction of the field's range (ProgressiveField::error).
  double field_error(size_t field) const;

  // The vertex that v is merged into at level k (v itself if it exists there).
  uint32_t ancestor(uint32_t v, uint32_t k) const;

  // The current mesh as a Topology over vertices [0, vertex_count()), with part and element
  // ids and node ids; faces in progressive order.
  Topology topology() const;

 private:
  const ProgressiveMesh* mesh_;
  std::vector<Face> faces_;  // every face the mesh holds; [0, face_count_) are current
  uint32_t level_ = 0;
  uint32_t face_count_ = 0;
};

// The fully refined mesh in the input's vertex and face order (what build read), with
// positions at step t: the round-trip check and "extract" at full resolution use it.
struct OriginalOrder {
  Topology topology;
  std::vector<uint32_t> vertex_of_original;  // input vertex index → progressive vertex
  std::vector<uint32_t> face_of_original;    // input face index → progressive face
};
Result<OriginalOrder> original_order(const Navigator& full);

}  // namespace dynpm
