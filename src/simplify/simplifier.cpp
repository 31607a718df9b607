// The simplifier's queue loop: mixed triangle/quad half-edge collapse over key steps.
//
//   S. Wundrak, T. Henn, A. Stork. Dynamic Progressive Triangle-Quadrilateral Meshes. WSCG 2006.
//     §2 collapse on mixed meshes, (P1*) second-order neighbours, planes of skew quads;
//     §3 one quadric per vertex per animation step, cost = max over steps (method 1*).
//   M. Garland, P. Heckbert. Surface Simplification Using Quadric Error Metrics. SIGGRAPH 1997.
//   H. Hoppe. Progressive Meshes. SIGGRAPH 1996. (P2), (P3), vertex splits.
//   P. Cignoni. Mesh simplification (lecture): lazy heap with temporal marks, boundary quadrics.
//
// Roles kept apart: cost (quadrics.h, on quadric.h), legality (legality.h: CollapseRules::
// allows()), the mesh being changed (collapse_mesh.h), the queue (this file, monotone_queue.h),
// and the listener (CollapseListener). The loop is written as pseudocode at the top of
// include/dynpm/simplify.h; run() follows it line for line. Read top to bottom: key steps,
// rating, one collapse, the loop, the public entry (the class is in simplifier.h).
//
// The queue is the lecture's lazy heap with temporal marks: every edge the vertex classes allow
// to collapse in some direction is queued once, for its cheaper direction v0 → v1, with that
// cost and the time (collapse count) it was rated. A collapse changes the quadric of v1 only,
// so only v1's edges are re-rated; entries of v0 and v1 rated before that time are stale and
// skipped when popped. Legality is checked when an entry is popped, on the mesh as it is then;
// an illegal entry is dropped (its other direction queued at its own cost), and its vertex is
// marked so that its edges are re-rated as soon as its neighbourhood changes. When the queue
// runs dry before the target, every edge is rated again once: only if that finds no legal
// collapse does the simplifier report that none remains. The queue itself is a radix heap
// (monotone_queue.h); quadrics are kept in floats around their own vertex (quadrics.h).
//
// Islands (islands.h): a large mesh of several connected components is cut into islands of whole
// components, and each runs this loop to its end with a queue, time, scratch and quadrics of its
// own, in rounds on whatever thread is free, a few islands at a time; the collapses are told
// afterwards in key order, up to the stop condition (islands.cpp: Simplifier::run_islands()).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/pages.h"
#include "core/parallel.h"
#include "simplifier.h"

namespace dynpm {
namespace simplification {

// ---------------------------------------------------------------------------------------------
// Key steps and rating

Status Simplifier::load_key_steps(const FrameSource& frames) {
  const size_t steps = frames.step_count();
  if (steps == 0) return Status::error("the animation has no time step");
  if (options_.key_steps.empty()) {
    key_steps_.resize(steps);
    std::iota(key_steps_.begin(), key_steps_.end(), size_t{0});
  } else {
    key_steps_ = options_.key_steps;
    std::sort(key_steps_.begin(), key_steps_.end());
    key_steps_.erase(std::unique(key_steps_.begin(), key_steps_.end()), key_steps_.end());
    for (size_t t : key_steps_)
      if (t >= steps)
        return Status::error("key step " + std::to_string(t) +
                             " does not exist (the animation has " + std::to_string(steps) +
                             " steps)");
  }
  if (optimal() && key_steps_.size() != steps)
    return Status::error(
        "optimal placement moves vertices in every step, so every step must be a "
        "key step (use --key-steps all or half-edge placement)");

  auto fields = cost_fields(options_, frames);
  if (!fields) return fields.status();
  return quadrics_.load_key_steps(frames, input_, key_steps_, *fields, options_.field_form,
                                  options_.field_combine, thread_count(options_.threads),
                                  options_.progress);
}

double Simplifier::cost(uint32_t v0, uint32_t v1, Scratch& s) const {
  return optimal() ? quadrics_.collapse_error(v0, v1, rules_.vertex_class(v1), s.placement)
                   : quadrics_.half_edge_error(v0, v1);
}

bool Simplifier::stale(const Entry& e) const {
  return changed(e.v0) > e.time || changed(e.v1) > e.time;
}

// Every edge at v (with larger_only, those to a larger vertex) that the vertex classes allow in
// some direction, queued for its cheaper allowed direction.
void Simplifier::rate_edges_of(uint32_t v, Scratch& s, std::vector<Entry>& out, uint32_t time,
                               bool larger_only) const {
  if (frozen(v)) return;  // regions: frozen vertices neither move nor stay while they run
  mesh_.neighbours(v, s.neighbours);
  // The neighbours' quadrics and positions are scattered in memory: ask for all of them before
  // the first is needed, so the cache misses overlap instead of following one another.
  quadrics_.prefetch(s.neighbours);
  for (uint32_t w : s.neighbours) {
    if ((larger_only && w < v) || frozen(w)) continue;
    const VertexClass cv = rules_.vertex_class(v), cw = rules_.vertex_class(w);
    const bool forward = can_collapse(cv, cw) != Along::kNever;
    const bool backward = can_collapse(cw, cv) != Along::kNever;
    if (!forward && !backward) continue;
    if (forward && backward) {
      const auto [there, back] =
          optimal() ? std::pair{cost(v, w, s), cost(w, v, s)} : quadrics_.half_edge_errors(v, w);
      out.push_back(there <= back ? Entry{static_cast<float>(there), v, w, time, 0}
                                  : Entry{static_cast<float>(back), w, v, time, 0});
    } else {
      const uint32_t a = forward ? v : w, b = forward ? w : v;
      out.push_back({static_cast<float>(cost(a, b, s)), a, b, time, 1});
    }
  }
}

// Every edge once, in parallel, into the one queue (without islands): at the start, and when the
// queue runs dry. In rounds of vertices, each queued before the next is rated, so that the
// entries wait beside the queue a round at a time, not all of them (that was 16 B per edge at the
// simplifier's peak); queued in vertex order all the same.
void Simplifier::rate_all_edges() {
  const uint32_t n = input_.vertex_count;
  const unsigned threads = thread_count(options_.threads);
  constexpr uint32_t kRoundVertices = 1u << 16;
  std::vector<std::vector<Entry>> parts(threads);
  std::vector<Scratch> scratch(threads);
  Lane& lane = lanes_[0];
  lane.queue.clear();
  for (uint32_t first = 0; first < n; first += std::min(kRoundVertices, n - first)) {
    const uint32_t count = std::min(kRoundVertices, n - first);
    parallel_for_chunks(count, threads, [&](size_t begin, size_t end, size_t t) {
      for (size_t i = begin; i < end; ++i) {
        const auto v = static_cast<uint32_t>(first + i);
        if (mesh_.vertex_alive(v)) rate_edges_of(v, scratch[t], parts[t], lane.time, true);
      }
    });
    for (auto& part : parts) {
      for (const Entry& e : part) lane.queue.push(e);
      part.clear();
    }
  }
  lane.queue_size_after_cleanup = lane.queue.size();
  for (uint32_t v = 0; v < n; ++v) set_rejected(v, false);
}

// An island's edges in vertex order, on its own thread: when it opens, and when its queue ran dry.
void Simplifier::rate_island(Lane& lane) {
  lane.queue.clear();
  mesh_.for_each_island_vertex(static_cast<size_t>(&lane - lanes_.data()), [&](uint32_t v) {
    set_rejected(v, false);
    if (!mesh_.vertex_alive(v)) return;
    lane.fresh.clear();
    rate_edges_of(v, lane.scratch, lane.fresh, lane.time, true);
    for (const Entry& e : lane.fresh) lane.queue.push(e);
  });
  lane.queue_size_after_cleanup = lane.queue.size();
}

// Stale entries are dropped when the queue has doubled since the last time.
void Simplifier::drop_stale_entries(Lane& lane) {
  if (lane.queue.size() <= 2 * lane.queue_size_after_cleanup + 1024) return;
  lane.queue.remove_if([&](const Entry& e) { return stale(e); });
  lane.queue_size_after_cleanup = lane.queue.size();
}

// ---------------------------------------------------------------------------------------------
// The loop

Status Simplifier::collapse(Lane& lane, uint32_t v0, uint32_t v1, double error) {
  Scratch& s = lane.scratch;
  CollapseRecord record;
  record.error = error;
  record.round = rounds() ? round_ : 0;
  mesh_.collapse(v0, v1, record, lane.moved);
  rules_.collapsed(v0);
  // Optimal placement: s.placement holds v1's new positions, computed with `error`.
  const std::span<const float> v1_positions =
      quadrics_.merge(v0, v1, optimal() ? &s.placement : nullptr, s.merge);
  if (optimal()) record.v1_new_positions = v1_positions;
  ++lane.time;  // v0's and v1's queued entries are now stale
  set_changed(v0, lane.time);
  set_changed(v1, lane.time);
  ++lane.collapses;
  lane.max_error_done = std::max(lane.max_error_done, error);
  if (lanes_.size() > 1) {  // islands: told in key order at the end, rows dropped between rounds
    if (listener_ || (has_stop() && regions_ == 0)) lane.log.add(record);
    if (has_count_target()) {
      uint32_t removed = 0;
      for (uint8_t w = 0; w < record.wing_count; ++w) removed += record.wings[w].was_triangle();
      if (regions_ == 0) lane.cut_bound.add(static_cast<float>(lane.max_error_done), removed);
      lane.faces_removed += removed;
    }
  } else {
    if (lane.collapses % kCollapsesPerReport == 0) report_collapses(collapses());
    if (listener_) listener_->on_collapse(record);
    quadrics_.drop_removed(mesh_);  // after the listener: v1_positions may move
    if (options_.check_every_collapse) DYNPM_RETURN_IF_ERROR(check_mesh(collapses()));
  }

  // v1's quadric changed: re-rate its edges. Neighbours with a dropped entry get another
  // chance, since their surroundings changed.
  lane.fresh.clear();
  rate_edges_of(v1, s, lane.fresh, lane.time);
  mesh_.second_order_neighbours(v1, lane.ring);
  for (uint32_t w : lane.ring) {
    if (!rejected(w)) continue;
    set_rejected(w, false);
    rate_edges_of(w, s, lane.fresh, lane.time);
  }
  for (const Entry& e : lane.fresh) lane.queue.push(e);
  drop_stale_entries(lane);
  return {};
}

// Takes the lane's entries until one collapses, the next would exceed the maximum error, or no
// legal collapse remains (once the queue ran dry, every edge is rated again once: edges dropped
// as illegal may have become legal).
Status Simplifier::advance(Lane& lane, Next& next, uint32_t ceiling) {
  while (true) {
    if (lane.queue.empty()) {
      if (rounds() && end_round()) continue;
      if (!lane.rated_again) {
        if (lanes_.size() > 1)
          rate_island(lane);
        else
          rate_all_edges();
        ++lane.time;
        lane.rated_again = true;
        continue;
      }
      next = Next::kExhausted;
      return {};
    }
    const Entry entry = lane.queue.pop();
    if (stale(entry)) continue;
    if (rounds() && locked(entry)) {
      deferred_.push_back(entry);
      continue;
    }
    if (options_.max_error && entry.error > *options_.max_error) {
      next = Next::kMaxError;
      return {};
    }
    if (const uint32_t bucket = CutBound::bucket(entry.error); bucket > ceiling) {
      lane.queue.push(entry);  // no lower than the last popped: taken first next time
      lane.paused_at = bucket;
      next = Next::kPaused;
      return {};
    }
    Scratch& s = lane.scratch;
    if (!rules_.allows(entry.v0, entry.v1, s.marks, s.placement)) {
      set_rejected(entry.v0, true);
      if (!entry.one_way) {
        lane.queue.push(
            {static_cast<float>(cost(entry.v1, entry.v0, s)), entry.v1, entry.v0, lane.time, 1});
      }
      continue;
    }
    // The cost exactly as rated (the heap keeps it as float), and with optimal placement the
    // positions collapse() moves v1 to.
    const double error = cost(entry.v0, entry.v1, s);
    DYNPM_RETURN_IF_ERROR(collapse(lane, entry.v0, entry.v1, error));
    if (rounds()) lock_around(entry.v1);
    lane.rated_again = false;
    next = Next::kCollapsed;
    return {};
  }
}

// The corners of v1's faces after a collapse: this round's later collapses keep off them.
void Simplifier::lock_around(uint32_t v1) {
  for (uint32_t f : mesh_.faces_of(v1)) {
    const Face& face = mesh_.face(f);
    for (int k = 0; k < face.degree(); ++k) round_of_[face.v[k]] = round_;
  }
  if (round_quota_ > 0) --round_quota_;
  if (round_quota_ == 0) end_round();
}

// Starts the next round: every vertex free again, the deferred entries back in the queue (those
// still fresh), cheapest first. False when nothing was deferred.
bool Simplifier::end_round() {
  ++round_;
  round_quota_ = std::max<size_t>(
      1, static_cast<size_t>(options_.independent_rounds * double(mesh_.live_vertices())));
  if (deferred_.empty()) return false;
  // The queue raises keys below its last one to it and takes them last-in first-out: pushed
  // dearest first, they come out cheapest first.
  std::sort(deferred_.begin(), deferred_.end(),
            [](const Entry& a, const Entry& b) { return a.error > b.error; });
  for (const Entry& e : deferred_)
    if (!stale(e)) lanes_[0].queue.push(e);  // no islands with rounds
  deferred_.clear();
  return true;
}

Status Simplifier::check_mesh(size_t collapse_index) const {
  std::vector<uint32_t> original;
  return check_simplified(mesh_.to_topology(input_, original), initial_stats_,
                          options_.keep_part_boundaries,
                          "after collapse " + std::to_string(collapse_index) + ": ");
}

bool Simplifier::stop_reached(uint32_t live_vertices, size_t live_faces,
                              std::string& reason) const {
  if (live_vertices <= target_vertices_) {
    reason = "reached " + std::to_string(live_vertices) + " vertices";
    return true;
  }
  if (options_.target_faces && live_faces <= *options_.target_faces) {
    reason = "reached " + std::to_string(live_faces) + " faces";
    return true;
  }
  return false;
}

// Takes the input's adjacency (validate() built it) and frees it once the vertex classes and
// constraint edges are known, before the quadrics and the queue take their memory.
Result<SimplifyResult> Simplifier::run(Adjacency adjacency) {
  std::vector<uint8_t> constrained;
  report("quadrics", 0, input_.vertex_count);
  // Both read the adjacency alone: on two threads at once.
  parallel_for(2, 2, thread_count(options_.threads), [&](size_t part, size_t, size_t) {
    if (part == 0)
      initial_stats_ = topology_stats(input_, adjacency);
    else
      rules_.classify_vertices(adjacency);
  });
  const size_t vertices = initial_stats_.referenced_vertices;
  constrained = constrained_edges(input_, adjacency, rules_.features());
  adjacency = {};
  const bool regions = use_regions(vertices);
  if (!regions && use_islands(vertices)) {
    size_t count = 0;
    auto island_of = form_islands(rules_, mesh_, least_island_vertices(vertices), count);
    if (count > 1)
      mesh_.split_into_islands(std::move(island_of), count, thread_count(options_.threads));
  }
  lanes_ = std::vector<Lane>(mesh_.island_count());
  quadrics_.build(input_, mesh_, std::move(constrained), options_.boundary_weight,
                  options_.regularize, thread_count(options_.threads));
  // Regions read every vertex's quadrics, as the one queue that takes over does.
  if (regions) cut_into_regions();
  release_free_heap();  // the adjacency's small arrays, before the queue

  target_vertices_ = options_.target_vertices.value_or(0);
  if (options_.target_ratio) {
    const auto by_ratio = static_cast<uint32_t>(
        std::ceil(*options_.target_ratio * double(initial_stats_.referenced_vertices)));
    target_vertices_ = std::max(target_vertices_, by_ratio);
  }

  changed_.assign(input_.vertex_count, 0);
  if (rounds()) round_of_.assign(input_.vertex_count, 0), end_round();
  if (lanes_.size() == 1) {  // islands rate theirs as they open (run_islands())
    rate_all_edges();
    ++lanes_[0].time;
  }
  report("quadrics", input_.vertex_count, input_.vertex_count);

  SimplifyResult result;
  collapse_goal_ = vertices - std::min<size_t>(target_vertices_, vertices);
  report("collapsing", 0, collapse_goal_);
  const bool cut = lanes_.size() > 1 && regions_ == 0 && has_stop();  // made by run_islands()
  if (lanes_.size() > 1 && regions_ == 0) {
    DYNPM_RETURN_IF_ERROR(run_islands(result));
  } else {
    if (regions_ > 0) DYNPM_RETURN_IF_ERROR(run_regions());
    while (!stop_reached(mesh_.live_vertices(), mesh_.live_faces(), result.stop_reason)) {
      Next next = Next::kCollapsed;
      DYNPM_RETURN_IF_ERROR(advance(lanes_[0], next));
      if (next == Next::kMaxError) {
        result.stop_reason = "the next collapse would exceed the maximum error";
        break;
      }
      if (next == Next::kExhausted) break;
    }
  }
  if (!cut) {
    result.topology = mesh_.to_topology(input_, result.original_vertex);
    result.collapses = collapses();
    result.max_error = max_error_done();
  }
  result.target_reached = !result.stop_reason.empty();
  if (!result.target_reached)
    result.stop_reason = "no legal collapse remains at " +
                         std::to_string(result.topology.vertex_count) + " vertices";
  report("collapsing", result.collapses, result.collapses);
  result.key_steps = key_steps_;
  result.key_step_box = quadrics_.box();
  result.islands = regions_ > 0 ? 1 : lanes_.size();
  result.regions = regions_;
  result.region_collapses = region_collapses_;
  result.quadric_vertices_held = quadrics_.most_held();
  result.collapses_made = collapses();
  if (optimal()) {
    for (size_t k = 0; k < key_count(); ++k)
      result.key_step_positions.push_back(quadrics_.positions_of(result.original_vertex, k));
  }
  return result;
}

size_t Simplifier::collapses() const {
  size_t total = region_collapses_;
  for (const Lane& lane : lanes_) total += lane.collapses;
  return total;
}

double Simplifier::max_error_done() const {
  double most = region_max_error_;
  for (const Lane& lane : lanes_) most = std::max(most, lane.max_error_done);
  return most;
}

}  // namespace simplification

Result<SimplifyResult> simplify(const Topology& topology, const FrameSource& frames,
                                const SimplifyOptions& options, CollapseListener* listener) {
  std::optional<Adjacency> adjacency;
  if (options.checked && options.checked->proves(topology)) {
    adjacency = options.checked->take_adjacency();  // the check's, when no one took it before
  } else {
    const size_t faces = topology.faces.size();
    if (options.progress) options.progress("checking the mesh", 0, faces);
    const ValidationReport report = validate(topology, adjacency);
    if (options.progress) options.progress("checking the mesh", faces, faces);
    for (const Problem& p : report.problems)
      if (p.severity == Severity::kError) return Status::error("invalid input mesh: " + p.message);
  }
  if (frames.vertex_count() != topology.vertex_count)
    return Status::error("the time steps hold " + std::to_string(frames.vertex_count()) +
                         " vertices, the faces use " + std::to_string(topology.vertex_count));
  if (options.target_ratio && !(*options.target_ratio > 0 && *options.target_ratio <= 1))
    return Status::error("the target ratio must be in (0, 1]");
  if (!(std::isfinite(options.regularize) && options.regularize >= 0))
    return Status::error("the regularize weight must be a number ≥ 0");
  simplification::Simplifier simplifier(topology, options, listener);
  DYNPM_RETURN_IF_ERROR(simplifier.load_key_steps(frames));
  if (!adjacency) adjacency = Adjacency::build(topology);
  return simplifier.run(std::move(*adjacency));
}

}  // namespace dynpm
