// Where one step of a surface passes through itself (docs/eval.md, "Sheets through each other").
// Broad phase: each face's box against the BVH the surface already holds; narrow phase: two
// triangles cross when an edge of one pierces the other (signed volumes, in double). Faces that
// share a vertex are neighbours on the mesh and are not tested: they meet by construction.
#include <algorithm>
#include <cassert>

#include "dynpm/eval.h"

namespace dynpm {
namespace {

using Vec = std::array<double, 3>;

Vec to_vec(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Whether the closed segment pq meets triangle abc, p and q not both in its plane: they lie on
// different sides of (or one on) the plane, and the line through them passes inside the
// triangle (the three signed volumes about its edges agree in sign).
bool segment_pierces(const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c) {
  const Vec n = cross(sub(b, a), sub(c, a));
  const double dp = dot(sub(p, a), n), dq = dot(sub(q, a), n);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || (dp == 0 && dq == 0)) return false;
  const Vec d = sub(q, p);
  const double s1 = dot(d, cross(sub(a, p), sub(b, p)));
  const double s2 = dot(d, cross(sub(b, p), sub(c, p)));
  const double s3 = dot(d, cross(sub(c, p), sub(a, p)));
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

bool triangles_cross(const SurfaceTriangle& s, const SurfaceTriangle& t) {
  const std::array<Vec, 3> a{to_vec(s.a), to_vec(s.b), to_vec(s.c)};
  const std::array<Vec, 3> b{to_vec(t.a), to_vec(t.b), to_vec(t.c)};
  for (size_t i = 0; i < 3; ++i) {
    const size_t j = (i + 1) % 3;
    if (segment_pierces(a[i], a[j], b[0], b[1], b[2]) ||
        segment_pierces(b[i], b[j], a[0], a[1], a[2]))
      return true;
  }
  return false;
}

bool share_vertex(const Face& f, const Face& g) {
  for (uint32_t v : f.v)
    if (v != kNoVertex && g.contains(v)) return true;
  return false;
}

}  // namespace

void TriangleBvh::overlapping(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                              std::vector<uint32_t>& out) const {
  auto overlaps = [&](const Node& n) {
    for (size_t k = 0; k < 3; ++k)
      if (n.hi[k] < lo[k] || hi[k] < n.lo[k]) return false;
    return true;
  };
  std::array<uint32_t, kMaxDepth> stack;
  size_t top = 0;
  if (!nodes_.empty() && overlaps(nodes_[0])) stack[top++] = 0;
  while (top > 0) {  // depth first: at most one pending sibling per level
    const Node& n = nodes_[stack[--top]];
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) out.push_back(original_[i]);
      continue;
    }
    const uint32_t node = uint32_t(&n - nodes_.data());
    for (uint32_t child : {node + 1, n.first})
      if (overlaps(nodes_[child])) {
        assert(top < stack.size());
        stack[top++] = child;
      }
  }
}

std::vector<uint32_t> self_crossing_faces(const Surface& surface) {
  const std::vector<SurfaceTriangle>& triangles = surface.triangles;
  const Topology& topology = *surface.topology->topology;
  std::vector<uint8_t> crossing(topology.faces.size(), 0);
  std::vector<uint32_t> candidates;
  // A face's triangles are consecutive (surface_triangles()): one box query per face.
  for (size_t first = 0, end = 0; first < triangles.size(); first = end) {
    const uint32_t face = triangles[first].face;
    std::array<float, 3> lo = triangles[first].a, hi = lo;
    for (end = first; end < triangles.size() && triangles[end].face == face; ++end)
      for (const auto* p : {&triangles[end].a, &triangles[end].b, &triangles[end].c})
        for (size_t k = 0; k < 3; ++k)
          lo[k] = std::min(lo[k], (*p)[k]), hi[k] = std::max(hi[k], (*p)[k]);
    candidates.clear();
    surface.bvh.overlapping(lo, hi, candidates);
    for (uint32_t c : candidates) {
      const uint32_t other = triangles[c].face;
      if (other <= face || share_vertex(topology.faces[face], topology.faces[other])) continue;
      for (size_t i = first; i < end; ++i)
        if (triangles_cross(triangles[i], triangles[c])) {
          crossing[face] = crossing[other] = 1;
          break;
        }
    }
  }
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < crossing.size(); ++f)
    if (crossing[f]) faces.push_back(f);
  return faces;
}

}  // namespace dynpm
