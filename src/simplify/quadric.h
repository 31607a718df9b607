// Garland & Heckbert 1997 quadric error metric, in double precision. A quadric is the sum of
// weighted squared distances to a set of planes n·p + d = 0; Q(p) = pᵀAp + 2bᵀp + c with A
// symmetric 3×3. The plane weights are kept too (w), so Q(p) / w is a weighted mean squared
// distance: an error in length units, comparable across meshes (meshoptimizer does the same).
#pragma once

#include <cmath>
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

// A quadric as the simplifier keeps it, one per vertex and key step: single precision, with
// the origin at the vertex's own position in that step. Near its origin the coefficients are
// of the size of the local errors, so floats keep a collapse's cost as exact as doubles keep
// it in world coordinates, in half the memory (44 B instead of 88 B per vertex and step).
// Evaluated at its own vertex it is just c; at a neighbour, at the short edge vector.
struct LocalQuadric {
  float xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  float bx = 0, by = 0, bz = 0, c = 0;
  float w = 0;

  static LocalQuadric narrow(const Quadric& q) {
    auto f = [](double x) { return static_cast<float>(x); };
    return {f(q.xx), f(q.xy), f(q.xz), f(q.yy), f(q.yz), f(q.zz),
            f(q.bx), f(q.by), f(q.bz), f(q.c),  f(q.w)};
  }
  Quadric widen() const { return {xx, xy, xz, yy, yz, zz, bx, by, bz, c, w}; }
};

}  // namespace dynpm::simplification
