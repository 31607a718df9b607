#include "index_sets.h"

#include <bit>

namespace dynpm::progressive {

FreeIndices::FreeIndices(uint32_t n)
    : n_(n), count_(n), words_((size_t{n} + 63) / 64, ~uint64_t{0}), tree_(words_.size() + 1) {
  if (n % 64) words_.back() = (uint64_t{1} << (n % 64)) - 1;  // no index past n
  for (size_t w = 0; w < words_.size(); ++w) {
    tree_[w + 1] += static_cast<uint32_t>(std::popcount(words_[w]));
    const size_t up = (w + 1) + ((w + 1) & (0 - (w + 1)));
    if (up < tree_.size()) tree_[up] += tree_[w + 1];
  }
  top_ = words_.empty() ? 0 : std::bit_floor(static_cast<uint32_t>(words_.size()));
}

uint32_t FreeIndices::below(uint32_t v) const {
  if (v > n_) v = n_;
  const uint32_t w = v >> 6;
  uint32_t sum = 0;
  for (uint32_t k = w; k > 0; k &= k - 1) sum += tree_[k];  // the words before w
  if (v & 63)
    sum += static_cast<uint32_t>(std::popcount(words_[w] & ((uint64_t{1} << (v & 63)) - 1)));
  return sum;
}

uint32_t FreeIndices::nth(uint32_t r) const {
  uint32_t w = 0;  // the words [0, w) hold r or fewer free indices
  for (uint32_t step = top_; step > 0; step >>= 1)
    if (w + step < tree_.size() && tree_[w + step] <= r) w += step, r -= tree_[w];
  uint64_t bits = words_[w];  // the r-th free index (0-based) of word w
  for (; r > 0; --r) bits &= bits - 1;
  return w * 64 + static_cast<uint32_t>(std::countr_zero(bits));
}

void FreeIndices::take(uint32_t v) {
  words_[v >> 6] &= ~(uint64_t{1} << (v & 63));
  --count_;
  for (size_t k = size_t{v >> 6} + 1; k < tree_.size(); k += k & (0 - k)) --tree_[k];
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
