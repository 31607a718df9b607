// ListPool: a short list of indices per key (the faces at each vertex, as a replay of the
// splits goes) in one array. A list that outgrows its room moves to the array's end with room to
// spare; its old block is left unused. A million small std::vectors cost a heap block and a
// header each (about 60 B per vertex) and their allocations, moves and frees were a fifth of a
// replay's time. Internal: modules include it as "core/list_pool.h".
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "core/prefetch.h"

namespace dynpm {

class ListPool {
 public:
  // `lists` empty lists; `expected` values in all is a hint for the array's first size.
  ListPool(uint32_t lists, size_t expected)
      : start_(lists, 0), size_(lists, 0), capacity_(lists, 0) {
    pool_.reserve(expected);
  }

  uint32_t lists() const { return static_cast<uint32_t>(start_.size()); }

  bool empty(uint32_t k) const { return size_[k] == 0; }
  std::span<const uint32_t> of(uint32_t k) const { return {pool_.data() + start_[k], size_[k]}; }
  std::span<uint32_t> of(uint32_t k) { return {pool_.data() + start_[k], size_[k]}; }
  // For a replay that visits list keys[j] at its step j, in no spatial order: at step i, asks for
  // the place of keys[i + 2·ahead]'s list, for keys[i + ahead]'s values, and hands each value of
  // keys[i + ahead / 2] to values_ahead() (to ask for what it names), so that the misses overlap
  // instead of stalling the replay one by one. A key without a list yet is passed over; a list
  // that changes before its step only wastes a load.
  template <class ValuesAhead>
  void prefetch_ahead(std::span<const uint32_t> keys, size_t i, size_t ahead,
                      ValuesAhead&& values_ahead) const {
    const auto listed = [&](size_t j) { return j < keys.size() && keys[j] < lists(); };
    if (listed(i + 2 * ahead)) {
      prefetch(&start_[keys[i + 2 * ahead]]);
      prefetch(&size_[keys[i + 2 * ahead]]);
    }
    if (listed(i + ahead)) prefetch(of(keys[i + ahead]).data());
    if (listed(i + ahead / 2))
      for (uint32_t value : of(keys[i + ahead / 2])) values_ahead(value);
  }

  void push_back(uint32_t k, uint32_t value) {
    if (size_[k] == capacity_[k]) make_room(k, size_[k] + 1);
    pool_[start_[k] + size_[k]++] = value;
  }
  // List k's values; a list past the last is made, with any before it (a replay's new vertex).
  void assign(uint32_t k, std::span<const uint32_t> values) {
    ensure_lists(k + 1);
    size_[k] = 0;
    if (values.size() > capacity_[k]) make_room(k, static_cast<uint32_t>(values.size()));
    std::copy(values.begin(), values.end(), pool_.begin() + start_[k]);
    size_[k] = static_cast<uint32_t>(values.size());
  }
  // Removes the values pred() holds for, keeping the others' order.
  template <class Pred>
  void erase_if(uint32_t k, Pred&& pred) {
    const std::span<uint32_t> list = of(k);
    const auto end = std::remove_if(list.begin(), list.end(), pred);
    size_[k] = static_cast<uint32_t>(end - list.begin());
  }
  // Removes one occurrence of `value`, if any, moving the last value into its place.
  void erase_unordered(uint32_t k, uint32_t value) {
    const std::span<uint32_t> list = of(k);
    const auto it = std::find(list.begin(), list.end(), value);
    if (it == list.end()) return;
    *it = list.back();
    --size_[k];
  }

 private:
  // At least `count` lists, the new ones empty (amortized: the arrays grow by doubling).
  void ensure_lists(uint32_t count) {
    if (count <= start_.size()) return;
    for (auto* array : {&start_, &size_, &capacity_}) {
      if (count > array->capacity()) array->reserve(std::max<size_t>(count, array->size() * 2));
      array->resize(count, 0);
    }
  }
  // List k moves to the end with room for `needed` values and as many again (at least 4).
  void make_room(uint32_t k, uint32_t needed) {
    const uint32_t capacity = std::max<uint32_t>(needed * 2, 4);
    const size_t start = pool_.size();
    pool_.resize(start + capacity);
    std::copy_n(pool_.begin() + start_[k], size_[k], pool_.begin() + start);
    start_[k] = static_cast<uint32_t>(start);
    capacity_[k] = capacity;
  }

  std::vector<uint32_t> pool_;
  std::vector<uint32_t> start_, size_, capacity_;
};

}  // namespace dynpm
