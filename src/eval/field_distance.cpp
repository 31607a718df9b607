// Field values on a surface's triangles, for the field error (field_distance.h).
#include "field_distance.h"

#include <cmath>
#include <string>

namespace dynpm {

CornerValues corner_values(const Topology& topology, const SurfaceField& field) {
  CornerValues corners;
  corners.reserve(topology.faces.size() + 3 * topology.quad_count());
  const bool per_face = field.location == FieldLocation::kElement;
  for (uint32_t f = 0; f < topology.faces.size(); ++f) {
    const Face& face = topology.faces[f];
    const int degree = face.degree();
    if (degree != 3 && degree != 4) continue;  // as surface_triangles()
    if (per_face) {
      const float value = field.values[f];
      for (int i = 0; i < (degree == 3 ? 1 : 4); ++i) corners.push_back({value, value, value});
    } else if (degree == 3) {
      corners.push_back(
          {field.values[face.v[0]], field.values[face.v[1]], field.values[face.v[2]]});
    } else {
      std::array<float, 4> corner;
      for (int i = 0; i < 4; ++i) corner[i] = field.values[face.v[i]];
      const float centroid =
          static_cast<float>((double(corner[0]) + corner[1] + corner[2] + corner[3]) * 0.25);
      for (int i = 0; i < 4; ++i) corners.push_back({corner[i], corner[(i + 1) % 4], centroid});
    }
  }
  return corners;
}

Status check_field(const char* name, const Topology& topology, const SurfaceField& field) {
  const bool per_face = field.location == FieldLocation::kElement;
  const size_t wanted = per_face ? topology.faces.size() : size_t{topology.vertex_count};
  if (field.values.size() != wanted)
    return Status::error(std::string(name) + ": " + std::to_string(field.values.size()) +
                         " field values for " + std::to_string(wanted) +
                         (per_face ? " faces" : " vertices"));
  for (size_t i = 0; i < field.values.size(); ++i)
    if (!std::isfinite(field.values[i]))
      return Status::error(std::string(name) + ": the field value of " +
                           (per_face ? "face " : "vertex ") + std::to_string(i) + " is not finite");
  return {};
}

}  // namespace dynpm
