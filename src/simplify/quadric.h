// Garland & Heckbert 1997 quadric error metric, in double precision. A quadric is the sum of
// weighted squared distances to a set of planes n·p + d = 0; Q(p) = pᵀAp + 2bᵀp + c with A
// symmetric 3×3. The plane weights are kept too (w), so Q(p) / w is a weighted mean squared
// distance: an error in length units, comparable across meshes (meshoptimizer does the same).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include "core/face_geometry.h"

namespace dynpm::simplification {

struct Quadric {
  // Upper triangle of A (xx xy xz yy yz zz), b (x y z), c, and the total plane weight.
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  double bx = 0, by = 0, bz = 0, c = 0;
  double w = 0;

  // Adds weight · (n·p + d)² for a unit normal n.
  void add_plane(Vec3 n, double d, double weight) {
    xx += weight * n.x * n.x, xy += weight * n.x * n.y, xz += weight * n.x * n.z;
    yy += weight * n.y * n.y, yz += weight * n.y * n.z, zz += weight * n.z * n.z;
    bx += weight * n.x * d, by += weight * n.y * d, bz += weight * n.z * d;
    c += weight * d * d;
    w += weight;
  }

  // Adds weight · |p|² (distance to the origin in every direction) without adding to w: the
  // shape regularizer (quadrics.h), which must not dilute the planes' mean squared distance.
  void add_isotropic(double weight) { xx += weight, yy += weight, zz += weight; }

  Quadric& operator+=(const Quadric& q) {
    xx += q.xx, xy += q.xy, xz += q.xz, yy += q.yy, yz += q.yz, zz += q.zz;
    bx += q.bx, by += q.by, bz += q.bz, c += q.c, w += q.w;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

  // Σ weight · distance², never negative.
  double evaluate(Vec3 p) const {
    const double v =
        p.x * (xx * p.x + xy * p.y + xz * p.z) + p.y * (xy * p.x + yy * p.y + yz * p.z) +
        p.z * (xz * p.x + yz * p.y + zz * p.z) + 2 * (bx * p.x + by * p.y + bz * p.z) + c;
    return v > 0 ? v : 0;
  }
  // Weighted mean squared distance.
  double mean_squared(Vec3 p) const { return w > 0 ? evaluate(p) / w : 0; }

  // The same planes seen from an origin moved to d: Q'(y) = Q(y + d).
  Quadric translated(Vec3 d) const {
    Quadric q = *this;
    q.bx = xx * d.x + xy * d.y + xz * d.z + bx;
    q.by = xy * d.x + yy * d.y + yz * d.z + by;
    q.bz = xz * d.x + yz * d.y + zz * d.z + bz;
    q.c = evaluate(d);
    return q;
  }

  // The point minimising Q (A p = −b), if A is well-conditioned enough to trust it.
  std::optional<Vec3> minimiser() const {
    // Cofactors of the symmetric A.
    const double c00 = yy * zz - yz * yz, c01 = xz * yz - xy * zz, c02 = xy * yz - xz * yy;
    const double det = xx * c00 + xy * c01 + xz * c02;
    const double scale = xx + yy + zz;  // trace: the size of A's eigenvalues
    if (!(std::fabs(det) > 1e-9 * scale * scale * scale) || scale <= 0) return std::nullopt;
    const double c11 = xx * zz - xz * xz, c12 = xy * xz - xx * yz, c22 = xx * yy - xy * xy;
    const double inv = -1.0 / det;
    return Vec3{inv * (c00 * bx + c01 * by + c02 * bz), inv * (c01 * bx + c11 * by + c12 * bz),
                inv * (c02 * bx + c12 * by + c22 * bz)};
  }
};

// IEEE 754 half precision, converted by hand: without F16C (not assumed on x86-64) the
// compiler's _Float16 conversions are library calls, too slow for the cost's inner loop.
inline float half_to_float(uint16_t h) {
  // A half's exponent and mantissa shifted into a float's are the value times 2^-112, for
  // normal and subnormal halves alike; the multiplication restores it.
  const float magnitude = std::bit_cast<float>(uint32_t{h & 0x7fffu} << 13) * 0x1p112f;
  return std::bit_cast<float>(std::bit_cast<uint32_t>(magnitude) | (uint32_t{h & 0x8000u} << 16));
}
// Rounds to the nearest half (ties to even); beyond the largest half (65504) it saturates.
inline uint16_t float_to_half(float f) {
  const uint32_t x = std::bit_cast<uint32_t>(f);
  const auto sign = static_cast<uint16_t>((x >> 16) & 0x8000u);
  const uint32_t magnitude = x & 0x7fffffffu;
  if (magnitude >= 0x477ff000u) return static_cast<uint16_t>(sign | 0x7bffu);  // ≥ 65520, NaN
  if (magnitude < 0x38800000u)  // below 2^-14: a subnormal half
    return static_cast<uint16_t>(
        sign | static_cast<uint16_t>(std::lrint(std::bit_cast<float>(magnitude) * 0x1p24f)));
  uint32_t r = magnitude - ((127u - 15u) << 23);  // the exponent's bias from a float's to a half's
  r += 0xfffu + ((r >> 13) & 1u);                 // round the 13 dropped bits, ties to even
  return static_cast<uint16_t>(sign | (r >> 13));
}

// A quadric as the simplifier keeps it, one per vertex and key step, in 38 bytes, with the
// origin at the vertex's own position in that step (near its origin the coefficients are of
// the size of the local errors). Per stored part:
//   A / w   fixed point in steps of Scales::a (31 bits): a weighted mean of the planes' nn^T (plus
//           the shape term), so each entry lies in ±(1 + regularize), and a merge (a weighted
//           mean again) never leaves that range
//   b / w   half precision in units of Scales::b (a length: the planes' mean offset from the
//           vertex, at most about the diagonal): relative precision where b is small
//   c, w    single precision: the error at the vertex itself and the plane weight, which every
//           cost divides by, as exact as before
// Evaluated at its own vertex it is just c; at a neighbour, at the short edge vector.
struct CompactQuadric {
  // A / w in 31-bit steps: 16-bit steps (tried) blur the near-zero costs of flat regions
  // enough to reorder their collapses (+2 to +15 % file size, fewer quads kept).
  static constexpr double kASteps = 1073741823;
  struct Scales {
    double a = 1.0 / kASteps;  // one step of A / w: (1 + regularize) / kASteps
    double b = 1;              // the unit of b / w: the key steps' diagonal / 4096
  };
  uint16_t a[12];       // xx xy xz yy yz zz, 32-bit integers as halves of their bits
  uint16_t b[3];        // x y z, half precision
  uint16_t c[2], w[2];  // floats, as halves of their bits: the struct stays 2-byte aligned

  static CompactQuadric narrow(const Quadric& q, const Scales& s) {
    CompactQuadric out{};
    const double inv_w = q.w > 0 ? 1 / q.w : 0;
    const double coefficients[6] = {q.xx, q.xy, q.xz, q.yy, q.yz, q.zz};
    for (int i = 0; i < 6; ++i) {
      const double steps = std::nearbyint(coefficients[i] * inv_w / s.a);
      const auto fixed = static_cast<int32_t>(std::clamp(steps, -kASteps, kASteps));
      std::memcpy(&out.a[2 * i], &fixed, 4);
    }
    const double b_scale = inv_w / s.b;
    out.b[0] = float_to_half(static_cast<float>(q.bx * b_scale));
    out.b[1] = float_to_half(static_cast<float>(q.by * b_scale));
    out.b[2] = float_to_half(static_cast<float>(q.bz * b_scale));
    const float c = static_cast<float>(q.c), w = static_cast<float>(q.w);
    std::memcpy(out.c, &c, 4);
    std::memcpy(out.w, &w, 4);
    return out;
  }
  double weight() const { return read_float(w); }
  double offset_error() const { return read_float(c); }  // Q at the vertex itself
  Quadric widen(const Scales& s) const {
    const double w_value = weight(), a_unit = w_value * s.a, b_unit = w_value * s.b;
    return {entry(0) * a_unit,
            entry(1) * a_unit,
            entry(2) * a_unit,
            entry(3) * a_unit,
            entry(4) * a_unit,
            entry(5) * a_unit,
            half_to_float(b[0]) * b_unit,
            half_to_float(b[1]) * b_unit,
            half_to_float(b[2]) * b_unit,
            offset_error(),
            w_value};
  }

 private:
  double entry(int i) const {
    int32_t fixed;
    std::memcpy(&fixed, &a[2 * i], 4);
    return fixed;
  }
  static double read_float(const uint16_t (&halves)[2]) {
    float f;
    std::memcpy(&f, halves, 4);
    return f;
  }
};
static_assert(sizeof(CompactQuadric) == 38);

}  // namespace dynpm::simplification
