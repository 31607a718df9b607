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

}  // namespace dynpm
