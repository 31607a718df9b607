// Reordering the splits within error bands (split_order.h).
#include "split_order.h"

#include <cmath>
#include <queue>
#include <utility>

#include "dynpm/lod.h"

namespace dynpm {
namespace {

// How often the ordering of the bands tells its progress: every this many splits.
constexpr uint32_t kSplitsTold = 1 << 16;

// The band of an error: floor(log2(e) · bands per octave); zero errors share the lowest.
int64_t band_of(float e) {
  if (!(e > 0)) return INT64_MIN;
  return static_cast<int64_t>(std::floor(std::log2(double(e)) * kSplitOrderBandsPerOctave));
}

// A topological order of splits [first, last) (their dependencies on earlier splits are met),
// the one with the smallest parent (in the new numbering) first.
void order_band(const ProgressiveMesh& pm, const SplitDependencies& deps, uint32_t first,
                uint32_t last, std::vector<uint32_t>& new_position, std::vector<uint32_t>& order) {
  const uint32_t n = last - first, base = pm.base_vertex_count;
  std::vector<uint32_t> waiting(n, 0), next_start(n + 1, 0), next;
  for (uint32_t i = first; i < last; ++i)
    for (uint32_t d : deps.of(i))
      if (d >= first) ++waiting[i - first], ++next_start[d - first + 1];
  for (uint32_t k = 0; k < n; ++k) next_start[k + 1] += next_start[k];
  next.resize(next_start[n]);
  std::vector<uint32_t> fill(next_start.begin(), next_start.end() - 1);
  for (uint32_t i = first; i < last; ++i)
    for (uint32_t d : deps.of(i))
      if (d >= first) next[fill[d - first]++] = i;

  auto parent_now = [&](uint32_t i) {
    const uint32_t p = pm.parent[i];
    return p < base ? p : base + new_position[p - base];
  };
  // Sweeps of ascending parents: a split that becomes ready below the last parent taken waits
  // for the next sweep, so the parents descend once a sweep rather than at every such split.
  using Entry = std::pair<uint32_t, uint32_t>;  // parent in the new numbering, split
  using Heap = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;
  Heap sweep, next_sweep;
  for (uint32_t i = first; i < last; ++i)
    if (waiting[i - first] == 0) sweep.push({parent_now(i), i});
  while (!sweep.empty()) {
    const auto [parent, i] = sweep.top();
    sweep.pop();
    new_position[i] = static_cast<uint32_t>(order.size());
    order.push_back(i);
    for (uint32_t k = next_start[i - first]; k < next_start[i - first + 1]; ++k) {
      const uint32_t j = next[k];
      if (--waiting[j - first] != 0) continue;
      const uint32_t p = parent_now(j);
      (p >= parent ? sweep : next_sweep).push({p, j});
    }
    if (sweep.empty()) std::swap(sweep, next_sweep);
  }
}

}  // namespace

void order_splits_by_parent(ProgressiveMesh& pm, std::vector<uint32_t>& new_vertex,
                            std::vector<uint32_t>& new_face,
                            const std::function<void(double)>& progress, unsigned threads) {
  const uint32_t splits = pm.split_count(), base = pm.base_vertex_count;
  if (splits == 0) return;
  // Shares of the work, as timed at 1 M vertices: the dependencies 0.55, the bands 0.2.
  const auto told = [&](double share) {
    if (progress) progress(share);
  };
  SplitDependencies deps = derive_split_dependencies(pm, SplitReads::kFan, threads);
  told(0.55);
  std::vector<uint32_t> new_position(splits, 0), order;
  order.reserve(splits);
  for (uint32_t first = 0; first < splits;) {
    uint32_t last = first + 1;
    // Banded by the error each split undoes (at most the level's before it), so that the levels
    // inside a band may state the error before the band: whichever of its splits they lack.
    const int64_t band = band_of(static_cast<float>(pm.level_error(first)));
    while (last < splits && band_of(pm.error[last - 1]) == band) ++last;
    order_band(pm, deps, first, last, new_position, order);
    const auto before_band = static_cast<float>(pm.level_error(first));
    for (uint32_t i = first; i + 1 < last; ++i) pm.error[i] = before_band;
    if (first / kSplitsTold != last / kSplitsTold) told(0.55 + 0.2 * last / splits);
    first = last;
  }
  // Only the face counts are read from here on: the rest goes before the records are copied.
  std::vector<uint32_t> faces_after = std::move(deps.faces_after);
  deps = {};

  // The new numbering of the vertices and faces the splits create.
  auto vertex_now = [&](uint32_t v) { return v < base ? v : base + new_position[v - base]; };
  std::vector<uint32_t> created_face(pm.full_face_count, kNoIndex);  // old → new face
  for (uint32_t f = 0; f < pm.base_face_count; ++f) created_face[f] = f;
  uint32_t next_face = pm.base_face_count;
  for (uint32_t i : order) {
    const uint32_t old_first = faces_after[i];
    uint32_t made = 0;
    for (uint32_t k = pm.wing_start[i]; k < pm.wing_start[i + 1]; ++k)
      if (pm.wings[k].was_triangle()) created_face[old_first + made++] = next_face++;
  }

  std::vector<uint32_t>().swap(faces_after);  // freed: `= {}` keeps the capacity
  // The reordered records beside the old ones, each reserved to its size (grown, the copies of
  // the wings alone were 24 B per split more at the build's peak).
  ProgressiveMesh out;
  out.parent.reserve(splits);  // the errors stay by position: they are the levels'
  out.wings.reserve(pm.wings.size());
  out.wing_start.reserve(pm.wing_start.size());
  out.moved_faces.reserve(pm.moved_faces.size());
  out.moved_start.reserve(pm.moved_start.size());
  for (uint32_t i : order) {
    out.parent.push_back(vertex_now(pm.parent[i]));
    for (uint32_t k = pm.wing_start[i]; k < pm.wing_start[i + 1]; ++k) {
      const SplitWing& w = pm.wings[k];
      out.wings.push_back({created_face[w.face], vertex_now(w.vertex), w.flags});
    }
    out.wing_start.push_back(static_cast<uint32_t>(out.wings.size()));
    for (uint32_t k = pm.moved_start[i]; k < pm.moved_start[i + 1]; ++k)
      out.moved_faces.push_back(created_face[pm.moved_faces[k]]);
    out.moved_start.push_back(static_cast<uint32_t>(out.moved_faces.size()));
  }
  pm.parent = std::move(out.parent);
  pm.wings = std::move(out.wings), pm.wing_start = std::move(out.wing_start);
  pm.moved_faces = std::move(out.moved_faces), pm.moved_start = std::move(out.moved_start);

  auto permute = [](auto& values, auto&& now) {
    auto old = values;
    for (uint32_t k = 0; k < old.size(); ++k) values[now(k)] = old[k];
  };
  permute(pm.vertex_original_index, vertex_now);
  permute(pm.node_ids, vertex_now);
  auto face_now = [&](uint32_t f) { return created_face[f]; };
  permute(pm.face_original_index, face_now);
  permute(pm.part_ids, face_now);
  permute(pm.element_ids, face_now);
  for (uint32_t& v : new_vertex)
    if (v != kNoVertex) v = vertex_now(v);
  for (uint32_t& f : new_face)
    if (f != kNoIndex) f = created_face[f];
  told(1);
}

}  // namespace dynpm
