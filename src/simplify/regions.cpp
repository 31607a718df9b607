// Why a collapse v0 → v1 of region A, neither end frozen, touches nothing another region touches:
// - A face changes only when it holds v0. v0 is not frozen, so all its faces lie in A; faces
//   that cross a cut never change, and every face a region changes stays inside it (v0 → v1
//   within A).
// - Face lists change for v0, v1 and the corners of v0's faces: vertices of A. A frozen vertex of
//   A is a corner of crossing faces too, but those never change, so no other region writes its
//   list.
// - The rules (legality.cpp) read the face lists of v0 and v1 and their faces; re-rating reads
//   the faces of v1 and of the corners of v1's faces: lists of A's vertices, faces in A or
//   crossing. Entries with a frozen end are never queued, so quadrics change (v1's), marks are
//   set and change times written only for A's unfrozen vertices.
// - (P3) counts the component's live vertices: every region writes that count (atomically), but
//   the frozen vertices never go while the regions run, so the test cannot fail then.
#include "regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/parallel.h"
#include "simplifier.h"

namespace dynpm::simplification {

std::vector<uint16_t> spatial_regions(const Topology& input, const float* xyz, size_t stride,
                                      unsigned levels) {
  std::vector<uint8_t> in_face(input.vertex_count, 0);
  for (const Face& f : input.faces)
    for (uint32_t c : f.v)
      if (c != kNoVertex) in_face[c] = 1;
  std::vector<uint32_t> order;
  for (uint32_t v = 0; v < input.vertex_count; ++v)
    if (in_face[v]) order.push_back(v);
  // Each level halves every part at the median of its longest side (ties by vertex number, so
  // the cut is the same wherever it runs).
  std::vector<size_t> bounds = {0, order.size()};
  for (unsigned level = 0; level < levels; ++level) {
    std::vector<size_t> next = {0};
    for (size_t p = 0; p + 1 < bounds.size(); ++p) {
      const auto begin = order.begin() + static_cast<std::ptrdiff_t>(bounds[p]);
      const auto end = order.begin() + static_cast<std::ptrdiff_t>(bounds[p + 1]);
      std::array<float, 3> low{}, high{};
      for (auto it = begin; it != end; ++it) {
        const float* at = xyz + *it * stride;
        for (int c = 0; c < 3; ++c) {
          low[c] = it == begin ? at[c] : std::min(low[c], at[c]);
          high[c] = it == begin ? at[c] : std::max(high[c], at[c]);
        }
      }
      int axis = 0;  // the longest side, the first of equals
      for (int c = 1; c < 3; ++c)
        if (high[c] - low[c] > high[axis] - low[axis]) axis = c;
      const auto middle = begin + (end - begin) / 2;
      // A strict order even where a library caller's positions hold NaN (as +∞): nth_element
      // needs one.
      const auto coordinate = [&](uint32_t v) {
        const float c = xyz[v * stride + axis];
        return std::isnan(c) ? std::numeric_limits<float>::infinity() : c;
      };
      std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) {
        const float pa = coordinate(a), pb = coordinate(b);
        return pa < pb || (pa == pb && a < b);
      });
      next.push_back(static_cast<size_t>(middle - order.begin()));
      next.push_back(bounds[p + 1]);
    }
    bounds = std::move(next);
  }
  std::vector<uint16_t> region_of(input.vertex_count, 0);
  for (size_t p = 0; p + 1 < bounds.size(); ++p)
    for (size_t i = bounds[p]; i < bounds[p + 1]; ++i)
      region_of[order[i]] = static_cast<uint16_t>(p);
  return region_of;
}

std::vector<uint8_t> frozen_borders(const Topology& input, std::span<const uint16_t> region_of,
                                    std::span<const uint32_t> component_of, size_t components) {
  std::vector<uint8_t> frozen(input.vertex_count, 0);
  for (const Face& f : input.faces) {
    bool crosses = false;
    for (int c = 1; c < f.degree(); ++c) crosses |= region_of[f.v[c]] != region_of[f.v[0]];
    if (!crosses) continue;
    for (int c = 0; c < f.degree(); ++c) frozen[f.v[c]] = 1;
  }
  // A component across a cut with fewer than five frozen vertices is frozen whole: regions count
  // its live vertices at once, and (P3) must not depend on which of them went first.
  std::vector<uint32_t> frozen_in(components, 0);
  for (uint32_t v = 0; v < input.vertex_count; ++v) frozen_in[component_of[v]] += frozen[v];
  for (uint32_t v = 0; v < input.vertex_count; ++v) {
    const uint32_t in = frozen_in[component_of[v]];
    if (in > 0 && in < 5) frozen[v] = 1;
  }
  return frozen;
}

// The simplifier's regions (simplifier.h): when, their rounds, and the hand-over.

// Where one component holds a quarter of the vertices or more: islands of whole components would
// leave it to one thread. With optimal placement v1 moves, within its region (its faces are the
// region's): allowed without a listener, as the regions' logs keep no positions.
bool regions_allowed(const SimplifyOptions& options, bool listener, size_t referenced,
                     size_t largest) {
  return has_stop(options) && !(options.placement == Placement::kOptimal && listener) &&
         options.independent_rounds <= 0 && referenced >= options.region_min_vertices &&
         largest >= referenced / 4;
}

bool Simplifier::use_regions(size_t vertices) const {
  uint32_t largest = 0;
  for (uint32_t c = 0; c < rules_.component_count(); ++c)
    largest = std::max(largest, rules_.component_live(c));
  return regions_allowed(options_, listener_ != nullptr, vertices, largest);
}

void Simplifier::cut_into_regions() {
  // Rows are still vertices before the first collapse.
  const float* first = std::as_const(quadrics_).position_data(0, 0);
  std::vector<uint16_t> region_of =
      spatial_regions(input_, first, quadrics_.key_count() * 3, kRegionLevels);
  std::vector<uint32_t> component_of(input_.vertex_count);
  for (uint32_t v = 0; v < input_.vertex_count; ++v) component_of[v] = rules_.component_of(v);
  frozen_ = frozen_borders(input_, region_of, component_of, rules_.component_count());
  regions_ = size_t{1} << kRegionLevels;
  mesh_.split_into_islands(std::move(region_of), regions_, thread_count(options_.threads));
  lanes_ = std::vector<Lane>(regions_);
}

std::pair<size_t, size_t> Simplifier::left_to_target() const {
  size_t collapses = SIZE_MAX, faces = SIZE_MAX;
  const uint32_t live = mesh_.live_vertices();
  if (options_.target_vertices || options_.target_ratio)
    collapses = live > target_vertices_ ? live - target_vertices_ : 0;
  const size_t live_faces = mesh_.live_faces();
  if (options_.target_faces)
    faces = live_faces > *options_.target_faces ? live_faces - *options_.target_faces : 0;
  return {collapses, faces};
}

// In rounds, in key order: in each, every region makes its collapses up to a common key bucket
// (CutBound::bucket(), 16 an octave), on whichever thread is free, so that the regions keep
// together in key as one queue would take them; the next round's bucket is the lowest a region
// has reached, one at least past this one. Between rounds progress is told and in test mode the
// mesh is checked. The regions stop, all at once, once they have made kRegionShare of the work a
// vertex or face target leaves to them (the frozen vertices' part is the one queue's), and never
// go past the target, with room left for the one queue to thin the borders; a region also stops
// at its first collapse over the maximum error. Then the regions' collapses are told in key order,
// the borders thaw, and one queue rates every edge of the mesh they left.
Status Simplifier::run_regions() {
  const unsigned threads = thread_count(options_.threads);
  const auto frozen_count = static_cast<size_t>(std::count(frozen_.begin(), frozen_.end(), 1));
  const auto [collapses_needed, faces_needed] = left_to_target();
  const double share = kRegionShare * (1 - double(frozen_count) / double(mesh_.live_vertices()));
  std::vector<Status> failed(lanes_.size());
  std::vector<size_t> round;
  uint32_t ceiling = 0;
  while (true) {
    round.clear();
    for (size_t i = 0; i < lanes_.size(); ++i)
      if (!lanes_[i].exhausted) round.push_back(i);
    const auto [collapses_left, faces_left] = left_to_target();
    if (round.empty() || collapses_needed - collapses_left >= share * double(collapses_needed) ||
        faces_needed - faces_left >= share * double(faces_needed))
      break;
    // A frozen vertex goes with a collapse and two faces at most.
    const size_t most = (collapses_left - std::min(collapses_left, frozen_count)) / round.size();
    const size_t most_faces = (faces_left - std::min(faces_left, 2 * frozen_count)) / round.size();
    if (most == 0 || most_faces < 4) break;
    parallel_for(round.size(), round.size(), threads, [&](size_t begin, size_t end, size_t) {
      for (size_t r = begin; r < end; ++r) {
        Lane& lane = lanes_[round[r]];
        if (!lane.open) open_island(lane);
        failed[round[r]] = collapse_island(
            lane, most, lane.faces_removed + std::min(most_faces, SIZE_MAX / 2), ceiling);
      }
    });
    for (const Status& status : failed) DYNPM_RETURN_IF_ERROR(status);
    // Where the next collapses wait: a paused region's next key, else no lower than its last.
    uint32_t lowest = CutBound::kBuckets;
    for (size_t i : round) {
      const Lane& lane = lanes_[i];
      if (lane.exhausted) continue;
      const uint32_t last = CutBound::bucket(static_cast<float>(lane.max_error_done));
      lowest = std::min(lowest, lane.paused_at > ceiling ? lane.paused_at : last);
    }
    ceiling = std::max(ceiling + 1, lowest);
    report_collapses(collapses());
    if (options_.check_every_collapse) DYNPM_RETURN_IF_ERROR(check_mesh(collapses()));
  }
  std::vector<IslandLog*> logs;
  uint32_t time = 0;
  for (Lane& lane : lanes_) {
    if (lane.open) close_island(lane);
    logs.push_back(&lane.log);
    time = std::max(time, lane.time);
  }
  spare_queues_.clear();
  if (listener_) IslandLog::tell_in_key_order(logs, *listener_);
  region_collapses_ = collapses();
  region_max_error_ = max_error_done();
  frozen_ = {};
  lanes_ = std::vector<Lane>(1);
  lanes_[0].time = time + 1;  // above every change time the regions wrote
  rate_all_edges();
  ++lanes_[0].time;
  return {};
}

}  // namespace dynpm::simplification
