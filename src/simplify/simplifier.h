// The simplifier (simplifier.cpp: the queue loop; islands.cpp: the islands' rounds and the cut),
// internal to dynpm_simplify: simplify() in include/dynpm/simplify.h is its entry.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "collapse_mesh.h"
#include "dynpm/simplify.h"
#include "islands.h"
#include "legality.h"
#include "monotone_queue.h"
#include "quadrics.h"
#include "regions.h"
#include "spares.h"

namespace dynpm::simplification {

// Scratch space for one island's loop.
struct Scratch {
  std::vector<uint32_t> neighbours;
  std::vector<Vec3> placement;  // per key step, for the collapse under test
  VertexMarks marks;
  KeyStepQuadrics::MergeScratch merge;
};

class Simplifier {
 public:
  Simplifier(const Topology& topology, const SimplifyOptions& options, CollapseListener* listener)
      : input_(topology), options_(options), listener_(listener), mesh_(topology) {}

  Status load_key_steps(const FrameSource& frames);
  Result<SimplifyResult> run(Adjacency adjacency);

 private:
  size_t key_count() const { return quadrics_.key_count(); }
  bool optimal() const { return options_.placement == Placement::kOptimal; }
  double cost(uint32_t v0, uint32_t v1, Scratch& s) const;

  struct Entry;
  struct Lane;
  bool stale(const Entry& e) const;
  void rate_edges_of(uint32_t v, Scratch& s, std::vector<Entry>& out, uint32_t time,
                     bool larger_only = false) const;
  void rate_all_edges();
  void rate_island(Lane& lane);
  void drop_stale_entries(Lane& lane);
  // kPaused: the next collapse's key lies in a bucket past the ceiling (regions, in key order);
  // its entry stays queued.
  enum class Next { kCollapsed, kMaxError, kExhausted, kPaused };
  Status advance(Lane& lane, Next& next, uint32_t ceiling = CutBound::kBuckets);
  Status collapse(Lane& lane, uint32_t v0, uint32_t v1, double error);
  bool use_islands(size_t vertices) const;
  bool use_regions(size_t vertices) const;
  bool has_count_target() const { return simplification::has_count_target(options_); }
  bool has_stop() const { return simplification::has_stop(options_); }
  void stop_islands_past_the_cut();
  Status run_islands(SimplifyResult& result);
  // Regions (regions.h): cuts the mesh, runs the regions up to their bound and hands their mesh
  // to one queue.
  void cut_into_regions();
  // Collapses and removed faces that surely keep the mesh above a vertex or face target.
  std::pair<size_t, size_t> left_to_target() const;
  Status run_regions();
  void open_island(Lane& lane);
  // Up to `quota` collapses, until the island is exhausted, one more collapse could take its
  // removed faces past `face_limit`, or its key's bucket passes `ceiling` (it goes on in a later
  // round); the first error.
  Status collapse_island(Lane& lane, size_t quota, size_t face_limit = SIZE_MAX,
                         uint32_t ceiling = CutBound::kBuckets);
  void close_island(Lane& lane);
  size_t collapses() const;
  double max_error_done() const;
  Status check_mesh(size_t collapse_index) const;
  bool stop_reached(uint32_t live_vertices, size_t live_faces, std::string& reason) const;
  void report(std::string_view phase, size_t done, size_t total) const {
    if (options_.progress) options_.progress(phase, done, total);
  }
  // The collapses so far, never as the phase's end (done == total), which run() tells once:
  // islands run past a vertex target before the cut is made, and each round said "done" again.
  void report_collapses(size_t done) const {
    report("collapsing", std::min(done, collapse_goal_ - std::min<size_t>(collapse_goal_, 1)),
           collapse_goal_);
  }
  // Progress is told every this many collapses: often enough for a live line, rare enough to
  // cost nothing next to the collapses.
  static constexpr size_t kCollapsesPerReport = 4096;

  const Topology& input_;
  const SimplifyOptions& options_;
  CollapseListener* listener_;
  CollapseMesh mesh_;

  std::vector<size_t> key_steps_;
  KeyStepQuadrics quadrics_;
  CollapseRules rules_{input_, options_, mesh_, quadrics_};
  TopologyStats initial_stats_;

  // The queue (see the top of this file). A lane's time counts its collapses; changed_[v] is
  // the time v's quadric last changed; an entry rated before that time is stale. One entry per
  // edge, for its cheaper direction v0 → v1; when that is illegal, the other direction is queued
  // at its own cost (one_way marks an entry whose other direction is not allowed or already
  // queued).
  struct Entry {
    float error;
    uint32_t v0, v1;
    uint32_t time : 31;
    uint32_t one_way : 1;
    float key() const { return error; }
  };
  // One island's loop: the whole mesh's, or with islands each island's (mesh_.island_of()).
  struct Lane {
    MonotoneQueue<Entry> queue;
    size_t queue_size_after_cleanup = 0;
    std::vector<Entry> fresh;
    std::vector<uint32_t> moved, ring;
    Scratch scratch;
    uint32_t time = 1;
    bool rated_again = false;  // every edge was re-rated since the last collapse
    bool open = false;         // with islands: its quadrics made, its edges rated
    bool exhausted = false;
    bool over_max_error = false;  // its next collapse would exceed the maximum error
    size_t collapses = 0;
    size_t faces_removed = 0;  // with islands or regions and a vertex or face target
    double max_error_done = 0;
    uint32_t paused_at = 0;  // regions: the key bucket its next collapse waits in
    IslandLog log;           // with islands, until every island is done
    CutBound cut_bound;      // with islands and a vertex or face target
  };
  std::vector<Lane> lanes_;
  // Regions: 1 per vertex that no collapse may move or keep while they run (empty otherwise);
  // what the regions did, once one queue has taken over.
  std::vector<uint8_t> frozen_;
  bool frozen(uint32_t v) const { return !frozen_.empty() && frozen_[v] != 0; }
  size_t regions_ = 0, region_collapses_ = 0;
  double region_max_error_ = 0;
  Spares<MonotoneQueue<Entry>> spare_queues_;  // closed islands' queues (emptied), for the next
  // Per vertex: the time it last changed (31 bits) and, in the top bit, whether an entry of it was
  // dropped as illegal. In one word, because islands write their vertices' at once (a vector of
  // bits would share words between them).
  std::vector<uint32_t> changed_;
  static constexpr uint32_t kRejected = 1u << 31;
  uint32_t changed(uint32_t v) const { return changed_[v] & ~kRejected; }
  void set_changed(uint32_t v, uint32_t time) { changed_[v] = (changed_[v] & kRejected) | time; }
  bool rejected(uint32_t v) const { return (changed_[v] & kRejected) != 0; }
  void set_rejected(uint32_t v, bool r) { changed_[v] = changed(v) | (r ? kRejected : 0); }

  // Independent rounds (SimplifyOptions::independent_rounds): round_of_[v] is the round whose
  // collapse last changed a face of v; an entry touching such a vertex waits in deferred_ for
  // the next round.
  bool rounds() const { return options_.independent_rounds > 0; }
  bool locked(const Entry& e) const {
    return round_of_[e.v0] == round_ || round_of_[e.v1] == round_;
  }
  void lock_around(uint32_t v1);
  bool end_round();
  std::vector<uint32_t> round_of_;
  std::vector<Entry> deferred_;
  uint32_t round_ = 1;
  size_t round_quota_ = 0;

  uint32_t target_vertices_ = 0;
  size_t collapse_goal_ = 0;  // vertices to remove to reach the target (progress only)
};

}  // namespace dynpm::simplification
