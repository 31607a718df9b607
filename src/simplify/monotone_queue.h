// The simplifier's queue: a radix heap (Ahuja, Mehlhorn, Orlin, Tarjan 1990) over float keys.
// Entries sit in 33 buckets by the highest bit in which their key differs from the last key
// taken out; a push appends to a bucket, a pop takes from bucket 0 and, when that is empty,
// spreads the next bucket into the lower ones. Every step walks arrays in order, where a binary
// heap of millions of entries misses the cache on each level of every pop — and most of the
// simplifier's pops are stale entries that are thrown away at once.
//
// A radix heap needs keys that never go below the last one taken. A collapse can make a
// cheaper edge than the current one; its key is raised to the current key, so it is taken next
// (bucket 0 is a stack), just as a heap would take it next.
#pragma once

#include <array>
#include <bit>
#include <cassert>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace dynpm::simplification {

// T::key() returns a float ≥ 0 (not NaN): such floats order as their bit patterns. Buckets are
// stacks of 4 KB blocks from one pool: an emptied block goes back to the pool at once, so the
// queue's memory follows the number of entries, without the slack of 33 growing arrays. Blocks
// are made 512 at a time (2 MB): arrays that large go back to the system when the queue is
// freed, where 4 KB allocations stayed with the process as free heap (40 MB at 1 M vertices).
template <class T>
class MonotoneQueue {
 public:
  bool empty() const { return size_ == 0; }
  size_t size() const { return size_; }

  void push(const T& item) { push_to(bucket_of(bits(item)), item); }

  T pop() {
    assert(size_ > 0);
    if (head_[0] == kNone) refill();
    Block& block = block_at(head_[0]);
    const T item = block.items[--block.count];
    if (block.count == 0) head_[0] = release(head_[0]);
    --size_;
    return item;
  }

  // Drops every item for which drop(item) holds.
  template <class Drop>
  void remove_if(Drop&& drop) {
    for (size_t b = 0; b < kBuckets; ++b) {
      uint32_t chain = std::exchange(head_[b], kNone);
      while (chain != kNone) {
        const Block& block = block_at(chain);
        for (uint32_t i = 0; i < block.count; ++i) {
          --size_;
          if (!drop(block.items[i])) push_to(b, block.items[i]);
        }
        chain = release(chain);
      }
    }
  }

  // Empties the queue; keys start again from zero.
  void clear() {
    for (size_t b = 0; b < kBuckets; ++b)
      while (head_[b] != kNone) head_[b] = release(head_[b]);
    size_ = 0;
    last_ = 0;
  }

 private:
  static constexpr size_t kBuckets = 33;
  static constexpr uint32_t kNone = UINT32_MAX;
  static constexpr uint32_t kBlockItems = (4096 - 8) / sizeof(T);
  // count and next are set when a block is taken (push_to()): a new slab's pages are touched
  // only as its blocks come into use, not all 2 MB at once.
  struct Block {
    uint32_t count, next;
    T items[kBlockItems];
  };

  static uint32_t bits(const T& item) {
    const float key = item.key();
    assert(key >= 0 && "the queue takes keys ≥ 0 only");
    return std::bit_cast<uint32_t>(key);
  }
  size_t bucket_of(uint32_t key) const {
    return key <= last_ ? 0 : static_cast<size_t>(std::bit_width(key ^ last_));
  }

  void push_to(size_t b, const T& item) {
    if (head_[b] == kNone || block_at(head_[b]).count == kBlockItems) {
      uint32_t block;
      if (free_.empty()) {
        block = made_;
        if (made_++ % kSlabBlocks == 0)
          slabs_.push_back(std::make_unique_for_overwrite<Block[]>(kSlabBlocks));
      } else {
        block = free_.back();
        free_.pop_back();
      }
      block_at(block).count = 0;
      block_at(block).next = head_[b];
      head_[b] = block;
    }
    Block& block = block_at(head_[b]);
    block.items[block.count++] = item;
    ++size_;
  }
  // Returns the block to the pool; gives the next block of its chain.
  uint32_t release(uint32_t block) {
    free_.push_back(block);
    return block_at(block).next;
  }

  // Bucket 0 is empty: the smallest key of the first non-empty bucket becomes the last key, and
  // that bucket's items move to lower buckets (all differ from it below their old bucket's bit).
  void refill() {
    size_t b = 1;
    while (head_[b] == kNone) ++b;
    uint32_t least = UINT32_MAX;
    for (uint32_t chain = head_[b]; chain != kNone; chain = block_at(chain).next)
      for (uint32_t i = 0; i < block_at(chain).count; ++i)
        least = std::min(least, bits(block_at(chain).items[i]));
    last_ = least;
    uint32_t chain = std::exchange(head_[b], kNone);
    while (chain != kNone) {
      const Block& block = block_at(chain);
      size_ -= block.count;
      for (uint32_t i = 0; i < block.count; ++i)
        push_to(bucket_of(bits(block.items[i])), block.items[i]);
      chain = release(chain);
    }
  }

  static constexpr uint32_t kSlabBlocks = 512;
  Block& block_at(uint32_t i) { return slabs_[i / kSlabBlocks][i % kSlabBlocks]; }
  const Block& block_at(uint32_t i) const { return slabs_[i / kSlabBlocks][i % kSlabBlocks]; }

  std::vector<std::unique_ptr<Block[]>> slabs_;  // every block made; the pool lists the free ones
  uint32_t made_ = 0;
  std::vector<uint32_t> free_;
  std::array<uint32_t, kBuckets> head_ = filled(kNone);
  uint32_t last_ = 0;
  size_t size_ = 0;

  static std::array<uint32_t, kBuckets> filled(uint32_t value) {
    std::array<uint32_t, kBuckets> a;
    a.fill(value);
    return a;
  }
};

}  // namespace dynpm::simplification
