// Sets of indices the split-record coding keeps (split_records_coding.h). Both answer in a cache
// miss or two on meshes of millions: the coding asks them for every split.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace dynpm::progressive {

// The original indices (of vertices, or of faces) not yet given, in [0, n), so that an index is
// coded by its rank among the free ones (docs/FORMAT.md "Split attributes"). n comes from a
// file's header, which is not trusted: memory follows the indices taken, not n. The indices are
// blocks of 2^16; a block with nothing taken is only its free count, in a Fenwick tree over the
// blocks (n / 2^16 entries: in cache). A block that has given an index holds one bit per index
// and a Fenwick tree of its 1024 words' free counts (12 KB), so a question costs about one miss
// more than the word holding the index.
class FreeIndices {
 public:
  explicit FreeIndices(uint32_t n);
  uint32_t count() const { return count_; }
  bool is_free(uint32_t v) const {
    if (v >= n_) return false;
    const Block* b = blocks_[v >> kBlockBits].get();
    return !b || (b->words[(v & kBlockMask) >> 6] >> (v & 63) & 1);
  }
  // Free indices below v (v ≤ n).
  uint32_t below(uint32_t v) const;
  // The free index with r free ones below it (r < count()).
  uint32_t nth(uint32_t r) const;
  void take(uint32_t v);  // v is free

 private:
  static constexpr uint32_t kBlockBits = 16, kBlockMask = (1u << kBlockBits) - 1;
  static constexpr uint32_t kWords = 1u << (kBlockBits - 6);
  struct Block {
    std::array<uint64_t, kWords> words;     // bit v % 64 of word v / 64: v is free
    std::array<uint32_t, kWords + 1> tree;  // 1-based Fenwick sums of the words' free counts
  };
  Block& block_of(uint32_t v);  // made on first use

  uint32_t n_ = 0, count_ = 0;
  std::vector<std::unique_ptr<Block>> blocks_;  // null: nothing taken in that block
  std::vector<uint32_t> tree_;                  // 1-based Fenwick sums of the blocks' free counts
  uint32_t top_ = 0;                            // the largest power of two ≤ the block count
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
