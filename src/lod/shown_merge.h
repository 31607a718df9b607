// What a vertex or face shows of the original ones merged into it (docs/FORMAT.md "Shown
// values"): the value of largest magnitude, or the mean. The Navigator and the
// SelectiveNavigator merge through this one definition.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm {

class ShownMerge {
 public:
  ShownMerge(std::span<const float> values, FieldAggregate aggregate)
      : aggregate_(aggregate), value_(values.begin(), values.end()) {
    if (aggregate == FieldAggregate::kMean) count_.assign(values.size(), 1);
  }

  // `from` is merged into `into` (merge_undone_split()'s callback).
  void operator()(uint32_t into, uint32_t from) {
    if (aggregate_ == FieldAggregate::kMean) {
      value_[into] += value_[from];
      count_[into] += count_[from];
      return;
    }
    // max |value| with its sign; of two with equal magnitude the larger: the max of a total
    // order, so the order of merging never changes the result.
    const double a = value_[into], b = value_[from];
    if (std::abs(b) > std::abs(a) || (std::abs(b) == std::abs(a) && b > a)) value_[into] = b;
  }

  float shown(uint32_t i) const {
    return static_cast<float>(aggregate_ == FieldAggregate::kMean ? value_[i] / count_[i]
                                                                  : value_[i]);
  }

 private:
  FieldAggregate aggregate_;
  std::vector<double> value_;
  std::vector<uint32_t> count_;
};

}  // namespace dynpm
