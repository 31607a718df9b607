// Islands (docs/simplify.md "Islands"): sets of whole connected components that the simplifier
// collapses on separate threads, each with a queue of its own. A collapse in one island never
// reads what another writes, so each island does the same whatever runs beside it; what is kept
// per island until the end, and the order in which its collapses are then told, are here.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <memory>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#include "collapse_mesh.h"
#include "dynpm/simplify.h"
#include "legality.h"

namespace dynpm::simplification {

// Whether the options ask for a vertex or face count, and whether for any stop (a count or an
// error): the islands' cut, the regions and the Simplifier ask alike.
inline bool has_count_target(const SimplifyOptions& options) {
  return options.target_vertices || options.target_ratio || options.target_faces;
}
inline bool has_stop(const SimplifyOptions& options) {
  return has_count_target(options) || options.max_error;
}

// Whether the options allow islands on a mesh of `vertices` vertices in faces (of several
// components): not with optimal placement, where v1 moves, nor with independent rounds, which
// span the mesh.
bool islands_allowed(const SimplifyOptions& options, size_t vertices);
// How many islands run, and hold their quadrics, at once.
unsigned islands_at_once(const SimplifyOptions& options);
// Each component's island: the components in order (`live` gives each one's live vertices),
// gathered until an island holds at least `least` live vertices (the last may hold fewer);
// `count` gets the number of islands (at most 65,536).
std::vector<uint16_t> gather_islands(std::span<const uint32_t> live, uint32_t least, size_t& count);
// Each vertex's island: gather_islands() over the components in the order of their first vertex.
std::vector<uint16_t> form_islands(const CollapseRules& rules, const CollapseMesh& mesh,
                                   uint32_t least, size_t& count);
// The least vertices an island gathers (the last may have fewer): about a 64th of the mesh, so
// that there is work for many cores and each island's queue and rows stay in the caches.
inline uint32_t least_island_vertices(size_t vertices) {
  return std::max<uint32_t>(1, static_cast<uint32_t>(vertices / 64));
}

// An array that grows in chunks (no copy as it grows) and is read once from the front, giving
// back each chunk as the reading passes it: while the collapses are told, the listener's own log
// grows as these shrink. The first chunk is 64 KB and each next one twice the one before, up to
// 2 MB: an island's three logs take a few pages until it grows, not 6 MB of address space each
// (which a `ulimit -v` counts). Chunks of 2 MB go to the system when freed (glibc maps them apart;
// the mmap threshold is pinned at 1 MB, core/pages.h) and cost only the pages written.
template <class T>
class ChunkedArray {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  void push_back(const T& item) {
    const auto [c, at] = locate(size_);
    // Raw memory: T's default member initializers would write (and so take) the whole chunk.
    if (at == 0) chunks_.emplace_back(static_cast<T*>(::operator new(items_in(c) * sizeof(T))));
    chunks_[c].get()[at] = item;
    ++size_;
  }
  size_t size() const { return size_; }
  const T& operator[](size_t i) const {
    const auto [c, at] = locate(i);
    return chunks_[c].get()[at];
  }
  // Items before `i` are never read again.
  void release_before(size_t i) {
    const size_t before = locate(i).first;
    for (size_t c = released_; c < before; ++c) chunks_[c].reset();
    released_ = std::max(released_, before);
  }

 private:
  static constexpr size_t kFirst = std::max<size_t>(1, (size_t{64} << 10) / sizeof(T));
  static constexpr size_t kDoublings = 5;  // 64 KB · 2⁵ = 2 MB
  static constexpr size_t kGrown = kFirst * ((size_t{1} << kDoublings) - 1);  // before chunk 5
  static size_t items_in(size_t c) { return kFirst << std::min(c, kDoublings); }
  // Item i's chunk and its place in it.
  static std::pair<size_t, size_t> locate(size_t i) {
    if (i < kGrown) {
      const size_t c = std::bit_width(i / kFirst + 1) - 1;
      return {c, i - kFirst * ((size_t{1} << c) - 1)};
    }
    const size_t big = kFirst << kDoublings;
    return {kDoublings + (i - kGrown) / big, (i - kGrown) % big};
  }
  struct Free {
    void operator()(T* chunk) const { ::operator delete(chunk); }
  };
  std::vector<std::unique_ptr<T, Free>> chunks_;
  size_t size_ = 0, released_ = 0;
};

// One island's collapses in the order it made them. Each is told under a key: the largest error
// (as the queue's float) of the island's collapses so far, so that keys never fall within an
// island, as the queue orders them. 24 B a collapse plus 12 B a wing and 4 B a moved face.
class IslandLog {
 public:
  void add(const CollapseRecord& record);
  size_t size() const { return entries_.size(); }

  // Tells every island's collapses to `listener`: the smallest key first, the lower island on a
  // tie, each island's in its own order, until stop() holds before one. The logs are emptied as
  // they are told.
  static void tell_in_key_order(std::vector<IslandLog*> logs, CollapseListener& listener,
                                const std::function<bool()>& stop = {});

 private:
  struct Entry {
    uint32_t v0, v1, moved_count;
    uint8_t wing_count;
    double error;
  };
  // Tells the next collapse; false when none is left.
  bool tell_next(CollapseListener& listener, CollapseRecord& record, std::vector<uint32_t>& moved);
  float next_key() const { return static_cast<float>(entries_[next_].error); }

  ChunkedArray<Entry> entries_;
  ChunkedArray<SplitWing> wings_;
  ChunkedArray<uint32_t> moved_faces_;
  size_t next_ = 0, next_wing_ = 0, next_moved_ = 0;  // the reading's
};

// Where a vertex or face target will cut the told order, bounded while the islands run: each
// island counts its collapses, and the faces they remove, under its key's bucket (the key's float
// bits with 4 of the mantissa: 16 buckets an octave). Summed over the islands, the first bucket by
// which enough are logged bounds the cut, since collapses logged later can only move it earlier.
// An island whose key has passed that bucket makes no collapse the cut keeps, and may stop.
class CutBound {
 public:
  static constexpr uint32_t kBuckets = 1u << 12;  // keys are ≥ 0: the sign bit is 0
  static uint32_t bucket(float key) {
    return std::min(std::bit_cast<uint32_t>(key) >> 19, kBuckets - 1);
  }
  void add(float key, uint32_t faces_removed) {
    if (counts_.empty()) counts_.resize(kBuckets);
    Count& c = counts_[bucket(key)];
    ++c.collapses;
    c.faces += faces_removed;
  }
  // The first bucket by which the islands have logged `collapses` collapses, or collapses that
  // remove `faces` faces; kBuckets when none has.
  static uint32_t first_reaching(const std::vector<const CutBound*>& islands, size_t collapses,
                                 size_t faces);

 private:
  struct Count {
    uint32_t collapses = 0, faces = 0;
  };
  std::vector<Count> counts_;  // per bucket, made at the first collapse
};

// The islands ran to their ends; a stop condition cuts their collapses in key order. This
// listener replays the told ones on the input's faces (collapse_faces()), counts what is left
// and passes each on: the mesh at the cut, where the islands' own mesh went past it.
class CutReplay final : public CollapseListener {
 public:
  CutReplay(const Topology& input, uint32_t vertices, CollapseListener* next)
      : faces(input.faces), live_vertices(vertices), live_faces(input.faces.size()), next_(next) {}
  void on_collapse(const CollapseRecord& record) override {
    collapse_faces(faces, record);
    --live_vertices;
    for (uint8_t w = 0; w < record.wing_count; ++w) live_faces -= record.wings[w].was_triangle();
    ++collapses;
    max_error = std::max(max_error, record.error);
    if (next_) next_->on_collapse(record);
  }

  std::vector<Face> faces;
  uint32_t live_vertices;
  size_t live_faces, collapses = 0;
  double max_error = 0;

 private:
  CollapseListener* next_;
};

}  // namespace dynpm::simplification
