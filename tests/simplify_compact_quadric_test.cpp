// The simplifier's compact quadric (quadric.h): the half-precision conversions and the error a
// stored quadric makes next to the double-precision one it was narrowed from.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "simplify/quadric.h"

namespace dynpm {
namespace {

using simplification::CompactQuadric;
using simplification::float_to_half;
using simplification::half_to_float;
using simplification::Quadric;

TEST(CompactQuadric, EveryFiniteHalfSurvivesTheRoundTrip) {
  for (uint32_t h = 0; h < 0x10000; ++h) {
    if ((h & 0x7c00u) == 0x7c00u) continue;  // infinities and NaNs are never stored
    const float f = half_to_float(static_cast<uint16_t>(h));
    ASSERT_EQ(float_to_half(f), h) << "half " << h << " = " << f;
  }
  EXPECT_EQ(half_to_float(0x3c00), 1.0f);
  EXPECT_EQ(half_to_float(0xc000), -2.0f);
  EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.0f, -24));  // the least subnormal
  EXPECT_EQ(half_to_float(0x7bff), 65504.0f);
}

TEST(CompactQuadric, FloatsRoundToTheNearestHalf) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
  std::uniform_int_distribution<int> exponent(-26, 15);
  for (int i = 0; i < 200000; ++i) {
    const float x = std::ldexp(mantissa(random), exponent(random)) * (i % 2 ? -1.0f : 1.0f);
    const uint16_t h = float_to_half(x);
    const double error = std::fabs(double{half_to_float(h)} - x);
    // No other half is nearer: compare with both neighbours (same sign, one step either way).
    for (int step : {-1, 1}) {
      const int other = (h & 0x7fff) + step;
      if (other < 0 || other > 0x7bff) continue;
      const float neighbour = half_to_float(static_cast<uint16_t>((h & 0x8000) | other));
      ASSERT_LE(error, std::fabs(double{neighbour} - x)) << x;
    }
  }
  EXPECT_EQ(half_to_float(float_to_half(1e9f)), 65504.0f);  // saturates
  EXPECT_EQ(half_to_float(float_to_half(-1e9f)), -65504.0f);
}

// A vertex's quadric as the simplifier makes it: planes of faces around a point of a curved
// sheet, weighted by area, then merged with a neighbour's (so b and c are not zero).
Quadric planes_around(Vec3 at, double curvature, double edge, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(-1, 1);
  Quadric q;
  for (int f = 0; f < 6; ++f) {
    const Vec3 p{at.x + edge * unit(random), at.y + edge * unit(random), 0};
    const double height = curvature * (p.x * p.x + p.y * p.y);
    const Vec3 n = normalized(Vec3{-2 * curvature * p.x, -2 * curvature * p.y, 1});
    const Vec3 on{p.x, p.y, height};
    q.add_plane(n, -dot(n, on), edge * edge * (0.5 + 0.5 * unit(random)));
  }
  return q;
}

TEST(CompactQuadric, AStoredQuadricEvaluatesWithinItsStepsOfTheExactOne) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  CompactQuadric::Scales scales;
  const double diagonal = 500;
  scales.b = diagonal / 4096;
  for (int i = 0; i < 2000; ++i) {
    const double edge = std::pow(10.0, 2 * unit(random));  // 0.01 … 100 of a 500 diagonal
    const double curvature = std::pow(10.0, 2 * unit(random) - 3);
    // Around the vertex at the origin, then translated as a merge does.
    Quadric q = planes_around({0, 0, 0}, curvature, edge, random) +
                planes_around({edge, 0, 0}, curvature, edge, random).translated({edge, 0, 0});
    const CompactQuadric stored = CompactQuadric::narrow(q, scales);
    const Quadric back = stored.widen(scales);
    EXPECT_EQ(back.w, static_cast<float>(q.w));
    EXPECT_EQ(back.c, static_cast<float>(q.c));
    const Vec3 d{edge * unit(random), edge * unit(random), edge * unit(random)};
    const double length_d = length(d);
    const double b_length = std::sqrt(q.bx * q.bx + q.by * q.by + q.bz * q.bz);
    // Half a fixed-point step on each of A's nine entries; half a half's ulp (2^-11 relative,
    // and the least subnormal step) on each of b's; c's float rounding.
    const double bound =
        q.w * 9 * 0.5 * scales.a * length_d * length_d +
        2 * (std::ldexp(b_length, -11) + 3 * q.w * scales.b * 0x1p-24) * length_d * std::sqrt(3.0) +
        std::ldexp(std::fabs(q.c), -23);
    ASSERT_NEAR(back.evaluate(d), q.evaluate(d), bound * 1.01 + 1e-300) << "quadric " << i;
  }
}

TEST(CompactQuadric, NoPlanesStayNoPlanes) {
  const CompactQuadric stored = CompactQuadric::narrow(Quadric{}, CompactQuadric::Scales{});
  const Quadric back = stored.widen(CompactQuadric::Scales{});
  EXPECT_EQ(back.w, 0);
  EXPECT_EQ(back.evaluate({1, 2, 3}), 0);
}

}  // namespace
}  // namespace dynpm
