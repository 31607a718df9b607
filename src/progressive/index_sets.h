// Sets of indices the split-record coding keeps (split_records_coding.h). Both answer in about
// one cache miss on meshes of millions: the coding asks them for every split.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynpm::progressive {

// The original indices (of vertices, or of faces) not yet given, in [0, n), so that an index is
// coded by its rank among the free ones (docs/FORMAT.md "Split attributes"). One bit per index,
// and a Fenwick tree of the free counts of each 64-bit word: the tree is small enough to stay
// in cache, the word holding an index is the only miss.
class FreeIndices {
 public:
  explicit FreeIndices(uint32_t n);
  uint32_t count() const { return count_; }
  bool is_free(uint32_t v) const { return v < n_ && (words_[v >> 6] >> (v & 63) & 1); }
  // Free indices below v (v ≤ n).
  uint32_t below(uint32_t v) const;
  // The free index with r free ones below it (r < count()).
  uint32_t nth(uint32_t r) const;
  void take(uint32_t v);  // v is free

 private:
  uint32_t n_ = 0, count_ = 0;
  std::vector<uint64_t> words_;  // bit v % 64 of word v / 64: v is free
  std::vector<uint32_t> tree_;   // 1-based Fenwick sums of the words' free counts
  uint32_t top_ = 0;             // the largest power of two ≤ the word count (0: none)
};

// A few vertices, asked about often: "is v a corner of a face this split moved?". A small
// open-addressing table emptied per split; it grows for a hub's fan.
class VertexMarks {
 public:
  VertexMarks() : slots_(64, kEmpty) {}
  bool contains(uint32_t v) const;
  void insert(uint32_t v);
  void clear();

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;
  size_t slot_of(uint32_t v) const;
  std::vector<uint32_t> slots_;
  std::vector<uint32_t> used_;  // the slots filled, to empty them
};

}  // namespace dynpm::progressive
