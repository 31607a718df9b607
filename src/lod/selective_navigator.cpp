// The selective navigator: any dependency-closed set of splits, applied out of stream order by
// the same apply_split()/undo_split() as the Navigator, with each split's re-created faces at
// their progressive ids (docs/selective.md "The selective navigator").
#include <algorithm>
#include <cassert>
#include <cmath>

#include "dynpm/lod.h"
#include "shown_merge.h"

namespace dynpm {

SelectiveNavigator::SelectiveNavigator(const ProgressiveMesh& mesh, const SplitDependencies& deps)
    : mesh_(&mesh),
      deps_(&deps),
      faces_(mesh.base_faces),
      split_active_(mesh.split_count(), 0),
      face_active_(deps.faces_after.back(), 0),
      active_faces_(mesh.base_face_count) {
  assert(deps.split_count() == mesh.split_count());
  faces_.resize(deps.faces_after.back());
  std::fill_n(face_active_.begin(), mesh.base_face_count, uint8_t{1});
}

void SelectiveNavigator::apply(uint32_t i) {
  // Out of order, a split's re-created faces still take the ids they have in the stream.
  uint32_t next = deps_->faces_after[i];
  apply_split(*mesh_, i, faces_, next);
  for (uint32_t f = deps_->faces_after[i]; f < next; ++f) face_active_[f] = 1;
  active_faces_ += next - deps_->faces_after[i];
  split_active_[i] = 1;
  ++active_splits_;
}

void SelectiveNavigator::undo(uint32_t i) {
  uint32_t end = deps_->faces_after[i + 1];
  undo_split(*mesh_, i, faces_, end);
  for (uint32_t f = end; f < deps_->faces_after[i + 1]; ++f) face_active_[f] = 0;
  active_faces_ -= deps_->faces_after[i + 1] - end;
  split_active_[i] = 0;
  --active_splits_;
}

void SelectiveNavigator::set_active(std::span<const uint8_t> wanted) {
  const uint32_t n = mesh_->split_count();
  assert(wanted.size() >= n);
#ifndef NDEBUG
  for (uint32_t i = 0; i < n; ++i)
    if (wanted[i])
      for (uint32_t d : deps_->of(i)) assert(wanted[d] && "the wanted splits are not closed");
#endif
  // Dependants have larger indices than what they depend on: undo from the top, apply from the
  // bottom, and every split finds the faces it reads as the stream left them.
  last_applied_ = last_undone_ = 0;
  for (uint32_t i = n; i-- > 0;)
    if (split_active_[i] && !wanted[i]) {
      undo(i);
      ++last_undone_;
    }
  for (uint32_t i = 0; i < n; ++i)
    if (!split_active_[i] && wanted[i]) {
      apply(i);
      ++last_applied_;
    }
}

SelectiveMesh SelectiveNavigator::active_mesh() const {
  const ProgressiveMesh& m = *mesh_;
  SelectiveMesh out;
  std::vector<uint32_t> compact(m.vertex_count(), kNoVertex);
  for (uint32_t v = 0; v < m.vertex_count(); ++v)
    if (vertex_exists(v)) {
      compact[v] = static_cast<uint32_t>(out.vertices.size());
      out.vertices.push_back(v);
    }
  Topology& t = out.topology;
  t.vertex_count = static_cast<uint32_t>(out.vertices.size());
  for (uint32_t f = 0; f < faces_.size(); ++f) {
    if (!face_active_[f]) continue;
    out.faces.push_back(f);
    Face face = faces_[f];
    for (uint32_t& c : face.v)
      if (c != kNoVertex) c = compact[c];
    t.faces.push_back(face);
    t.part_ids.push_back(m.part_ids[f]);
    t.element_ids.push_back(m.element_ids[f]);
  }
  for (uint32_t v : out.vertices) t.node_ids.push_back(m.node_ids[v]);
  t.part_names = m.part_names;
  return out;
}

std::vector<float> SelectiveNavigator::field_values(size_t field, size_t t,
                                                    const SelectiveMesh& shown,
                                                    FieldAggregate aggregate) const {
  const bool per_face = mesh_->fields[field].info.location == FieldLocation::kElement;
  ShownMerge merged(mesh_->fields[field].values[t], aggregate);
  // FORMAT.md's pass over the missing splits only, from the last down: a missing vertex (the
  // faces a missing split creates) merges into its parent (their heirs), which may be missing
  // too and merge further on.
  for (uint32_t i = mesh_->split_count(); i-- > 0;)
    if (!split_active_[i])
      merge_undone_split(*mesh_, i, per_face, deps_->faces_after[i + 1], merged);
  const std::vector<uint32_t>& ids = per_face ? shown.faces : shown.vertices;
  std::vector<float> out(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) out[k] = merged.shown(ids[k]);
  return out;
}

}  // namespace dynpm
