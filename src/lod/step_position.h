// A vertex's position at a fractional step, as Navigator::positions() blends it: the requests'
// one reading of positions (refine_targets.cpp, view_target.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "dynpm/progressive.h"

namespace dynpm {

inline std::array<double, 3> position_at(const ProgressiveMesh& m, uint32_t v, double t) {
  const size_t last = m.positions.size() - 1;
  t = std::clamp(t, 0.0, double(last));
  const size_t t0 = static_cast<size_t>(std::floor(t)), t1 = std::min(t0 + 1, last);
  const double a = t - double(t0);
  std::array<double, 3> p;
  // Steps after a fractional t are not read (DpmReadLimits::last_step) when t is whole.
  for (int c = 0; c < 3; ++c) {
    const double p0 = m.positions[t0][size_t{v} * 3 + c];
    p[c] = a == 0 ? p0 : p0 + a * (m.positions[t1][size_t{v} * 3 + c] - p0);
  }
  return p;
}

}  // namespace dynpm
