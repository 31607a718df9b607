// The geometry of one face, said once for every module (validate, simplify, progressive and
// the tests): the vector type, a face's doubled vector area, the plane of a skew quad (paper
// §2), quad convexity, and where a vertex sits among a face's corners. Internal to the
// library: modules include it as "core/face_geometry.h".
#pragma once

#include <cmath>
#include <cstdint>

#include "dynpm/core.h"

namespace dynpm {

// A point or vector in double precision; positions are stored as floats and widened by load().
struct Vec3 {
  double x = 0, y = 0, z = 0;
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(Vec3 a) {
  const double l = length(a);
  return l > 0 ? a * (1.0 / l) : Vec3{};
}
inline Vec3 load(const float* p) { return {p[0], p[1], p[2]}; }

// Corner slot of v in the face, or -1.
inline int corner_of(const Face& face, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    if (face.v[i] == v) return i;
  return -1;
}

// Vector area × 2 of a face whose corners are given (3 or 4); for a quad the cross product of
// its diagonals, which is also what a skew quad's "area" means.
inline Vec3 doubled_vector_area(const Vec3* p, int degree) {
  return degree == 3 ? cross(p[1] - p[0], p[2] - p[0]) : cross(p[2] - p[0], p[3] - p[1]);
}

// The (unnormalized) normal of a quad's corner i: the turn from its next to its previous corner.
inline Vec3 corner_normal(const Vec3* quad, int i) {
  return cross(quad[(i + 1) % 4] - quad[i], quad[(i + 3) % 4] - quad[i]);
}

// A quad is convex (and not self-intersecting) when every corner turns the same way as the
// face.
inline bool quad_is_convex(const Vec3* quad, Vec3 normal) {
  for (int i = 0; i < 4; ++i)
    if (dot(corner_normal(quad, i), normal) <= 0) return false;
  return true;
}

// The plane normal · p + offset = 0, normal of unit length (or zero for a face without area).
struct Plane {
  Vec3 normal;
  double offset = 0;
};

// The plane of a skew quad (paper §2): the mean of its unit corner normals, through its
// centroid. Where the corner normals cancel, the normal of its doubled vector area.
inline Plane quad_plane(const Vec3* quad) {
  Vec3 sum{};
  for (int c = 0; c < 4; ++c) sum = sum + normalized(corner_normal(quad, c));
  const Vec3 normal = length(sum) > 0 ? normalized(sum) : normalized(doubled_vector_area(quad, 4));
  const Vec3 centroid = (quad[0] + quad[1] + quad[2] + quad[3]) * 0.25;
  return {normal, -dot(normal, centroid)};
}

// A face's plane: a triangle's own, a quad's quad_plane().
inline Plane face_plane(const Vec3* p, int degree) {
  if (degree == 4) return quad_plane(p);
  const Vec3 normal = normalized(doubled_vector_area(p, 3));
  return {normal, -dot(normal, p[0])};
}

}  // namespace dynpm
