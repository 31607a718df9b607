#include "islands.h"

#include <algorithm>
#include <atomic>
#include <functional>
#include <mutex>
#include <numeric>
#include <queue>
#include <utility>

#include "core/components.h"
#include "core/parallel.h"
#include "regions.h"
#include "simplifier.h"

namespace dynpm::simplification {

std::vector<uint16_t> gather_islands(std::span<const uint32_t> live, uint32_t least,
                                     size_t& count) {
  std::vector<uint16_t> island_of_component(live.size());
  count = 0;
  uint32_t open = 0;  // live vertices of the last island so far
  for (size_t c = 0; c < live.size(); ++c) {
    if (count == 0 || (open >= least && count < 65536)) ++count, open = 0;
    island_of_component[c] = static_cast<uint16_t>(count - 1);
    open += live[c];
  }
  return island_of_component;
}

std::vector<uint16_t> form_islands(const CollapseRules& rules, const CollapseMesh& mesh,
                                   uint32_t least, size_t& count) {
  std::vector<uint32_t> live(rules.component_count());
  for (uint32_t c = 0; c < live.size(); ++c) live[c] = rules.component_live(c);
  const std::vector<uint16_t> island_of_component = gather_islands(live, least, count);
  std::vector<uint16_t> island_of(mesh.vertex_count());
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    island_of[v] = island_of_component[rules.component_of(v)];
  return island_of;
}

uint32_t CutBound::first_reaching(const std::vector<const CutBound*>& islands, size_t collapses,
                                  size_t faces) {
  size_t logged = 0, removed = 0;
  for (uint32_t b = 0; b < kBuckets; ++b) {
    for (const CutBound* island : islands)
      if (!island->counts_.empty()) {
        logged += island->counts_[b].collapses;
        removed += island->counts_[b].faces;
      }
    if (logged >= collapses || removed >= faces) return b;
  }
  return kBuckets;
}

void IslandLog::add(const CollapseRecord& record) {
  entries_.push_back({record.v0, record.v1, static_cast<uint32_t>(record.moved_faces.size()),
                      record.wing_count, record.error});
  for (uint8_t w = 0; w < record.wing_count; ++w) wings_.push_back(record.wings[w]);
  for (uint32_t f : record.moved_faces) moved_faces_.push_back(f);
}

bool IslandLog::tell_next(CollapseListener& listener, CollapseRecord& record,
                          std::vector<uint32_t>& moved) {
  const Entry& e = entries_[next_];
  record.v0 = e.v0;
  record.v1 = e.v1;
  record.error = e.error;
  record.wing_count = e.wing_count;
  for (uint8_t w = 0; w < e.wing_count; ++w) record.wings[w] = wings_[next_wing_++];
  moved.clear();
  for (uint32_t m = 0; m < e.moved_count; ++m) moved.push_back(moved_faces_[next_moved_++]);
  record.moved_faces = moved;
  listener.on_collapse(record);
  ++next_;
  entries_.release_before(next_);
  wings_.release_before(next_wing_);
  moved_faces_.release_before(next_moved_);
  if (next_ < entries_.size()) return true;
  *this = IslandLog{};
  return false;
}

void IslandLog::tell_in_key_order(std::vector<IslandLog*> logs, CollapseListener& listener,
                                  const std::function<bool()>& stop) {
  using Head = std::pair<float, uint32_t>;  // an island's key so far, and the island
  std::priority_queue<Head, std::vector<Head>, std::greater<Head>> heads;
  for (uint32_t i = 0; i < logs.size(); ++i)
    if (logs[i]->size() > 0) heads.push({logs[i]->next_key(), i});
  CollapseRecord record;
  std::vector<uint32_t> moved;
  while (!heads.empty() && !(stop && stop())) {
    const auto [key, i] = heads.top();
    heads.pop();
    if (logs[i]->tell_next(listener, record, moved))
      heads.push({std::max(key, logs[i]->next_key()), i});
  }
}

// The simplifier's islands (simplifier.h): when, their rounds, and the cut.

unsigned islands_at_once(const SimplifyOptions& options) {
  return options.islands_at_once > 0 ? options.islands_at_once : 2 * thread_count(options.threads);
}

bool islands_allowed(const SimplifyOptions& options, size_t vertices) {
  return options.placement != Placement::kOptimal && options.independent_rounds <= 0 &&
         vertices >= options.island_min_vertices;
}

// Islands where the options allow them, on a mesh of several components.
bool Simplifier::use_islands(size_t vertices) const {
  return islands_allowed(options_, vertices) && rules_.component_count() > 1;
}

// An island whose key has passed the bucket where the vertex or face target will cut makes no
// collapse the cut keeps: it stops (without this, at 50 % every island ran twice as far as told).
// The told collapses are the same, so is the result.
void Simplifier::stop_islands_past_the_cut() {
  const size_t referenced = initial_stats_.referenced_vertices;
  const size_t collapses = options_.target_vertices || options_.target_ratio
                               ? referenced - std::min<size_t>(target_vertices_, referenced)
                               : SIZE_MAX;
  const size_t faces = input_.faces.size();
  const size_t removed =
      options_.target_faces ? faces - std::min<size_t>(*options_.target_faces, faces) : SIZE_MAX;
  std::vector<const CutBound*> bounds;
  for (const Lane& lane : lanes_) bounds.push_back(&lane.cut_bound);
  const uint32_t cut = CutBound::first_reaching(bounds, collapses, removed);
  if (cut == CutBound::kBuckets) return;
  for (Lane& lane : lanes_)
    if (CutBound::bucket(static_cast<float>(lane.max_error_done)) > cut) lane.exhausted = true;
}

// An island's quadrics are made, and its edges rated in vertex order, when it first takes part
// in a round; both go when it is done. Each island thus does what it would with every island open.
// (Regions read the whole mesh's quadrics.)
void Simplifier::open_island(Lane& lane) {
  if (regions_ == 0) quadrics_.open_island(static_cast<size_t>(&lane - lanes_.data()), mesh_);
  lane.queue = spare_queues_.take();
  rate_island(lane);
  ++lane.time;
  lane.open = true;
}

Status Simplifier::collapse_island(Lane& lane, size_t quota, size_t face_limit, uint32_t ceiling) {
  Status status;
  // A collapse removes at most four faces, one per wing.
  for (size_t done = 0; done < quota && !lane.exhausted && lane.faces_removed + 4 <= face_limit;
       ++done) {
    Next next = Next::kCollapsed;
    status = advance(lane, next, ceiling);
    if (status.ok() && next == Next::kPaused) break;
    lane.exhausted = !status.ok() || next != Next::kCollapsed;
    lane.over_max_error = next == Next::kMaxError;
  }
  return status;
}

void Simplifier::close_island(Lane& lane) {
  if (regions_ == 0) quadrics_.close_island(static_cast<size_t>(&lane - lanes_.data()), mesh_);
  lane.queue.clear();  // its blocks stay, for the next island to fill
  spare_queues_.give(std::exchange(lane.queue, {}));
  std::vector<Entry>().swap(lane.fresh);  // freed: `= {}` keeps the capacity
  lane.scratch = Scratch();
  lane.open = false;
}

// Every island to its end (or to its first collapse over the maximum error, or past the cut of a
// vertex or face target). With a vertex or face target, or in test mode, in rounds: in each, the
// first islands_at_once() not yet done take up to a 32nd of their live vertices in collapses (at
// least 16) on whichever thread is free; between rounds the cut is looked for, progress is told
// and in test mode the mesh is checked. Otherwise each island runs to its end on the next free
// thread. Only the islands at work hold quadrics (with every key step most of the memory), and
// an island that is done gives its back and its place to the next. Where a round ends, and which
// thread runs an island, changes nothing an island does. Then the collapses are told in key
// order, up to a stop condition: the islands' mesh went past it, so the result is then the input's
// faces with the told collapses replayed on them.
Status Simplifier::run_islands(SimplifyResult& result) {
  const unsigned threads = thread_count(options_.threads);
  const size_t window = islands_at_once(options_);
  std::vector<Status> failed(lanes_.size());
  // Without a cut to find or a mesh to check between rounds, each island runs to its end on the
  // next free thread, at most `window` at once: rounds waited for their slowest island (1.7 of
  // 2 cores busy on the tiled crash box).
  const bool rounds = has_count_target() || options_.check_every_collapse;
  if (!rounds) {
    std::atomic<size_t> next_island{0};
    std::mutex told;
    size_t collapsed = 0;  // by every island so far (under `told`)
    const size_t workers = std::min<size_t>(threads, window);
    parallel_for(workers, workers, static_cast<unsigned>(workers), [&](size_t, size_t, size_t) {
      for (size_t i = next_island++; i < lanes_.size(); i = next_island++) {
        Lane& lane = lanes_[i];
        open_island(lane);
        // Told as it goes: one large part can be most of a mesh.
        for (size_t before = 0; !lane.exhausted; before = lane.collapses) {
          failed[i] = collapse_island(lane, kCollapsesPerReport);
          const std::lock_guard<std::mutex> lock(told);
          collapsed += lane.collapses - before;
          report_collapses(collapsed);
        }
        close_island(lane);
      }
    });
    for (const Status& status : failed) DYNPM_RETURN_IF_ERROR(status);
  }
  std::vector<size_t> round;
  bool all_done = !rounds;
  while (!all_done) {
    round.clear();
    for (size_t i = 0; i < lanes_.size() && round.size() < window; ++i)
      if (!lanes_[i].exhausted) round.push_back(i);
    parallel_for(round.size(), round.size(), threads, [&](size_t begin, size_t end, size_t) {
      for (size_t r = begin; r < end; ++r) {
        const size_t i = round[r];
        Lane& lane = lanes_[i];
        if (!lane.open) open_island(lane);
        const size_t quota = std::max<size_t>(16, (mesh_.island_live_vertices(i) + 31) / 32);
        failed[i] = collapse_island(lane, quota);
      }
    });
    for (const Status& status : failed) DYNPM_RETURN_IF_ERROR(status);
    if (has_count_target()) stop_islands_past_the_cut();
    for (Lane& lane : lanes_)
      if (lane.open && lane.exhausted) close_island(lane);
    report_collapses(collapses());
    if (options_.check_every_collapse) DYNPM_RETURN_IF_ERROR(check_mesh(collapses()));
    all_done = std::all_of(lanes_.begin(), lanes_.end(), [](const Lane& l) { return l.exhausted; });
  }
  std::vector<IslandLog*> logs;
  for (Lane& lane : lanes_) {
    lane.queue = {};  // its blocks back before the log is told
    logs.push_back(&lane.log);
  }
  spare_queues_.clear();
  quadrics_.drop_spare_blocks();
  if (!has_stop()) {  // the islands' mesh is the result
    if (listener_) IslandLog::tell_in_key_order(logs, *listener_);
    return {};
  }
  // A stop condition: the islands ran to their ends or past the cut, which is made in key order.
  CutReplay replay(input_, static_cast<uint32_t>(initial_stats_.referenced_vertices), listener_);
  IslandLog::tell_in_key_order(logs, replay, [&] {
    return stop_reached(replay.live_vertices, replay.live_faces, result.stop_reason);
  });
  if (result.stop_reason.empty() &&
      std::any_of(lanes_.begin(), lanes_.end(), [](const Lane& l) { return l.over_max_error; }))
    result.stop_reason = "the next collapse would exceed the maximum error";
  result.topology = live_topology(input_, replay.faces, result.original_vertex);
  result.collapses = replay.collapses;
  result.max_error = replay.max_error;
  if (!options_.check_every_collapse) return {};
  return check_simplified(result.topology, initial_stats_, options_.keep_part_boundaries,
                          "at the cut: ");
}

}  // namespace dynpm::simplification

namespace dynpm {

// The components as CollapseRules finds them, gathered as run() gathers them.
std::vector<size_t> island_vertex_counts(const Topology& topology, const SimplifyOptions& options) {
  const uint32_t n = topology.vertex_count;
  size_t components = 0;
  const std::vector<uint32_t> component = connected_components(topology, components);
  std::vector<uint8_t> in_face(n, 0);
  for (const Face& f : topology.faces)
    for (int c = 0; c < f.degree(); ++c) in_face[f.v[c]] = 1;
  std::vector<uint32_t> live(components, 0);  // per component, its vertices in faces
  size_t referenced = 0;
  for (uint32_t v = 0; v < n; ++v) {
    live[component[v]] += in_face[v];
    referenced += in_face[v];
  }
  const size_t largest = components ? *std::max_element(live.begin(), live.end()) : 0;
  if (!simplification::islands_allowed(options, referenced) || components < 2 ||
      simplification::regions_allowed(options, false, referenced, largest))
    return {};
  size_t count = 0;
  const std::vector<uint16_t> island_of = simplification::gather_islands(
      live, simplification::least_island_vertices(referenced), count);
  if (count < 2) return {};
  std::vector<size_t> size(count, 0);  // rows: every vertex of the island, as open_island() makes
  for (uint32_t v = 0; v < n; ++v) ++size[island_of[component[v]]];
  std::sort(size.begin(), size.end(), std::greater<>());
  return size;
}

size_t quadric_vertices_held(std::span<const size_t> island_vertex_counts,
                             const SimplifyOptions& options, uint32_t vertex_count) {
  if (island_vertex_counts.empty()) return vertex_count;
  const size_t window =
      std::min<size_t>(island_vertex_counts.size(), simplification::islands_at_once(options));
  return std::accumulate(island_vertex_counts.begin(), island_vertex_counts.begin() + window,
                         size_t{0});
}

size_t quadric_vertices_held(const Topology& topology, const SimplifyOptions& options) {
  return quadric_vertices_held(island_vertex_counts(topology, options), options,
                               topology.vertex_count);
}

}  // namespace dynpm
