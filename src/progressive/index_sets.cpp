#include "index_sets.h"

#include <algorithm>
#include <bit>

namespace dynpm::progressive {

namespace {

// Fenwick trees, 1-based: the sum of the entries before `end`, and the largest prefix whose sum
// is ≤ r (r then less that sum) found by descending from `top`.
template <class Tree>
uint32_t prefix_sum(const Tree& tree, uint32_t end) {
  uint32_t sum = 0;
  for (uint32_t k = end; k > 0; k &= k - 1) sum += tree[k];
  return sum;
}
template <class Tree>
uint32_t descend(const Tree& tree, size_t size, uint32_t top, uint32_t& r) {
  uint32_t at = 0;
  for (uint32_t step = top; step > 0; step >>= 1)
    if (at + step < size && tree[at + step] <= r) at += step, r -= tree[at];
  return at;
}
// Fills tree[1..] from the counts already in tree[1..] (each node adds itself to its parent).
template <class Tree>
void build_tree(Tree& tree, size_t size) {
  for (size_t k = 1; k < size; ++k)
    if (const size_t up = k + (k & (0 - k)); up < size) tree[up] += tree[k];
}

}  // namespace

FreeIndices::FreeIndices(uint32_t n)
    : n_(n), count_(n), blocks_((size_t{n} + kBlockMask) >> kBlockBits), tree_(blocks_.size() + 1) {
  for (size_t b = 0; b < blocks_.size(); ++b)
    tree_[b + 1] =
        static_cast<uint32_t>(std::min<size_t>(size_t{n} - (b << kBlockBits), kBlockMask + 1));
  build_tree(tree_, tree_.size());
  top_ = blocks_.empty() ? 0 : std::bit_floor(static_cast<uint32_t>(blocks_.size()));
}

uint32_t FreeIndices::below(uint32_t v) const {
  if (v > n_) v = n_;
  const uint32_t b = v >> kBlockBits, in = v & kBlockMask;
  uint32_t sum = prefix_sum(tree_, b);
  if (in == 0) return sum;
  const Block* block = blocks_[b].get();
  if (!block) return sum + in;  // all of the block below v is free
  const uint32_t w = in >> 6;
  sum += prefix_sum(block->tree, w);
  if (in & 63)
    sum += static_cast<uint32_t>(std::popcount(block->words[w] & ((uint64_t{1} << (in & 63)) - 1)));
  return sum;
}

uint32_t FreeIndices::nth(uint32_t r) const {
  const uint32_t b = descend(tree_, tree_.size(), top_, r);
  const Block* block = blocks_[b].get();
  if (!block) return (b << kBlockBits) + r;
  // The descent from half the words ends in the block's last word at the latest.
  const uint32_t w = descend(block->tree, block->tree.size(), kWords / 2, r);
  uint64_t bits = block->words[w];  // the r-th free index (0-based) of word w
  for (; r > 0; --r) bits &= bits - 1;
  return (b << kBlockBits) + w * 64 + static_cast<uint32_t>(std::countr_zero(bits));
}

FreeIndices::Block& FreeIndices::block_of(uint32_t v) {
  std::unique_ptr<Block>& block = blocks_[v >> kBlockBits];
  if (block) return *block;
  // Nothing taken yet: every index of the block below n is free.
  block = std::make_unique<Block>();  // zeros: tree[0] stays 0
  const uint32_t first = v & ~kBlockMask;
  const uint32_t size = static_cast<uint32_t>(std::min<size_t>(size_t{n_} - first, kBlockMask + 1));
  for (uint32_t w = 0; w < kWords; ++w) {
    const uint32_t free = std::min(64u, size > w * 64 ? size - w * 64 : 0u);
    block->words[w] = free == 64 ? ~uint64_t{0} : (uint64_t{1} << free) - 1;
    block->tree[w + 1] = free;
  }
  build_tree(block->tree, block->tree.size());
  return *block;
}

void FreeIndices::take(uint32_t v) {
  Block& block = block_of(v);
  const uint32_t w = (v & kBlockMask) >> 6;
  block.words[w] &= ~(uint64_t{1} << (v & 63));
  --count_;
  for (size_t k = size_t{w} + 1; k < block.tree.size(); k += k & (0 - k)) --block.tree[k];
  for (size_t k = size_t{v >> kBlockBits} + 1; k < tree_.size(); k += k & (0 - k)) --tree_[k];
}

size_t VertexMarks::slot_of(uint32_t v) const {
  const size_t mask = slots_.size() - 1;
  size_t s = (v * 2654435761u) & mask;  // Knuth's multiplicative hash
  while (slots_[s] != kEmpty && slots_[s] != v) s = (s + 1) & mask;
  return s;
}

bool VertexMarks::contains(uint32_t v) const { return v != kEmpty && slots_[slot_of(v)] == v; }

void VertexMarks::insert(uint32_t v) {
  const size_t s = slot_of(v);
  if (slots_[s] == v) return;
  slots_[s] = v;
  used_.push_back(static_cast<uint32_t>(s));
  if (used_.size() * 2 <= slots_.size()) return;
  std::vector<uint32_t> values;  // at most half full: twice the slots, filled again
  for (uint32_t u : used_) values.push_back(slots_[u]);
  slots_.assign(slots_.size() * 2, kEmpty);
  used_.clear();
  for (uint32_t value : values) insert(value);
}

void VertexMarks::clear() {
  for (uint32_t s : used_) slots_[s] = kEmpty;
  used_.clear();
}

}  // namespace dynpm::progressive
