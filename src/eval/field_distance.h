// The field half of the field error (issue 18): a scalar field's values on a surface's
// triangles, so that a sample and its closest point read the field where they are. The
// sampling and the closest points are hausdorff.cpp's, shared with the distance.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "dynpm/eval.h"

namespace dynpm {

// The field at the three corners of each triangle of surface_triangles(topology, …), in that
// order: a node field's vertex values (a quad's centroid: the mean of its four corners, so the
// field is linear over each of the quad's four triangles as the BVH splits it), an element
// field's face value at all three corners (constant per face).
using CornerValues = std::vector<std::array<float, 3>>;
CornerValues corner_values(const Topology& topology, const SurfaceField& field);

// An error if the field does not have one finite value per vertex (node) or per face
// (element) of the topology; the message starts with `name`.
Status check_field(const char* name, const Topology& topology, const SurfaceField& field);

// The field at barycentric weights w on a triangle with corner values c.
inline double interpolate(const std::array<float, 3>& c, const std::array<double, 3>& w) {
  return w[0] * c[0] + w[1] * c[1] + w[2] * c[2];
}

// Each vertex's normal at one step: the sum of its faces' doubled vector areas (zero for a
// vertex in no face). A vertex or edge sample faces this way.
std::vector<Point3> vertex_normals(const Topology& topology, std::span<const float> positions);
// A triangle's (unnormalized) normal.
Point3 triangle_normal(const SurfaceTriangle& t);

// A field seen from one direction: its values where the samples are and where they land.
struct FieldSides {
  SurfaceField from;  // per vertex or face of `from`, for vertex and edge samples
  const CornerValues* from_corners = nullptr;  // per triangle of `from`, for area samples
  const CornerValues* to_corners = nullptr;    // per triangle of `to`, at the closest points
};

// Per field, the largest difference one job found (-1: no sample yet) and where, under the
// facing correspondence and under the closest point alone.
struct FieldTally {
  std::vector<double> facing, nearest;
  std::vector<Point3> facing_at, nearest_at;
  std::vector<double> area_sum;  // of the area samples' differences at the facing match
  uint64_t area_samples = 0;
  explicit FieldTally(size_t fields = 0);
  void merge(const FieldTally& t);  // in job order, so ties keep the earlier sample
};

// The field half of one sample's measurement: the sample's own values against the other
// surface's at the corresponding point. One per job (it keeps its search memory).
class FieldSampler {
 public:
  // tolerance, facing_reach: HausdorffOptions::field_tolerance, field_facing_reach.
  FieldSampler(const Surface& to, std::span<const FieldSides> fields, double tolerance,
               double facing_reach);
  // p with its own normal (zero: unknown, any triangle faces it), `hit` its closest point on
  // `to` with weights, values[k] field k's value at p (NaN: none there).
  void measure(const Point3& p, const Point3& normal, const TriangleBvh::Hit& hit,
               std::span<const double> values, bool area_sample, FieldTally& tally);

 private:
  // The smallest |value − field k| over the hits closer to p than sqrt(radius2), only facing
  // ones if `facing`, and `start`.
  double smallest_difference(size_t k, double value, double start, double radius2, bool facing);

  const Surface& to_;
  std::span<const FieldSides> fields_;
  double tolerance_, facing_reach_;
  Point3 p_{0, 0, 0}, normal_{0, 0, 0};  // the sample being measured
  std::vector<TriangleBvh::Hit> near_;   // within(p_, near_radius2_), or empty
  double near_radius2_ = -1;
};

}  // namespace dynpm
