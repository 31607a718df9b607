// Field values on a surface's triangles, for the field error (field_distance.h).
#include "field_distance.h"

#include <cmath>
#include <string>
#include <tuple>

#include "core/face_geometry.h"

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

std::vector<Point3> vertex_normals(const Topology& topology, std::span<const float> positions) {
  std::vector<Point3> normals(topology.vertex_count, Point3{0, 0, 0});
  for (const Face& face : topology.faces) {
    const int degree = face.degree();
    if (degree != 3 && degree != 4) continue;
    Vec3 corners[4];
    for (int i = 0; i < degree; ++i) corners[i] = load(&positions[3 * size_t{face.v[i]}]);
    const Vec3 n = doubled_vector_area(corners, degree);
    for (int i = 0; i < degree; ++i) {
      Point3& to = normals[face.v[i]];
      to[0] += n.x, to[1] += n.y, to[2] += n.z;
    }
  }
  return normals;
}

Point3 triangle_normal(const SurfaceTriangle& t) {
  const Vec3 a = load(t.a.data());
  const Vec3 n = cross(load(t.b.data()) - a, load(t.c.data()) - a);
  return {n.x, n.y, n.z};
}

FieldTally::FieldTally(size_t fields)
    : facing(fields, -1),
      nearest(fields, -1),
      facing_at(fields),
      nearest_at(fields),
      area_sum(fields, 0) {}

void FieldTally::merge(const FieldTally& t) {
  for (auto [max, at, other, other_at] :
       {std::tuple{&facing, &facing_at, &t.facing, &t.facing_at},
        std::tuple{&nearest, &nearest_at, &t.nearest, &t.nearest_at}}) {
    max->resize(other->size(), -1), at->resize(other->size());
    for (size_t k = 0; k < other->size(); ++k)
      if ((*other)[k] > (*max)[k]) (*max)[k] = (*other)[k], (*at)[k] = (*other_at)[k];
  }
  area_sum.resize(t.area_sum.size(), 0);
  for (size_t k = 0; k < t.area_sum.size(); ++k) area_sum[k] += t.area_sum[k];
  area_samples += t.area_samples;
}

FieldSampler::FieldSampler(const Surface& to, std::span<const FieldSides> fields, double tolerance,
                           double facing_reach)
    : to_(to), fields_(fields), tolerance_(tolerance), facing_reach_(facing_reach) {}

namespace {

double dot3(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

double FieldSampler::smallest_difference(size_t k, double value, double start, double radius2,
                                         bool facing) {
  if (radius2 != near_radius2_) {
    near_.clear();
    to_.bvh.within(p_, radius2, near_);
    near_radius2_ = radius2;
  }
  const CornerValues& to = *fields_[k].to_corners;
  for (const TriangleBvh::Hit& other : near_) {
    if (facing && dot3(triangle_normal(to_.triangles[other.triangle]), normal_) <= 0) continue;
    start = std::min(start, std::abs(value - interpolate(to[other.triangle], other.weights)));
  }
  return start;
}

void FieldSampler::measure(const Point3& p, const Point3& normal, const TriangleBvh::Hit& hit,
                           std::span<const double> values, bool area_sample, FieldTally& tally) {
  p_ = p, normal_ = normal, near_radius2_ = -1;
  const double distance = std::sqrt(hit.squared_distance);
  auto square = [](double x) { return x * x; };
  const bool oriented = dot3(normal, normal) > 0;
  auto faces = [&](uint32_t triangle) {
    return !oriented || dot3(triangle_normal(to_.triangles[triangle]), normal) > 0;
  };
  // The facing match, found when first needed: the closest point if it faces p's way, else the
  // closest facing point within the reach, else (none) the closest point.
  TriangleBvh::Hit match = hit;
  bool match_known = facing_reach_ <= 0 || faces(hit.triangle), match_faces = match_known;
  if (area_sample) ++tally.area_samples;
  for (size_t k = 0; k < fields_.size(); ++k) {
    const double value = values[k];
    if (std::isnan(value)) continue;
    const CornerValues& to = *fields_[k].to_corners;
    const double at_hit = std::abs(value - interpolate(to[hit.triangle], hit.weights));
    // The closest point, or any point within the tolerance of it (a lossy model's contact).
    // Only a sample that would raise the maximum pays for the search.
    if (at_hit > tally.nearest[k]) {
      const double d = tolerance_ > 0 ? smallest_difference(k, value, at_hit,
                                                            square(distance + tolerance_), false)
                                      : at_hit;
      if (d > tally.nearest[k]) tally.nearest[k] = d, tally.nearest_at[k] = p;
    }
    if (facing_reach_ <= 0) {
      if (area_sample) tally.area_sum[k] += at_hit;
      continue;
    }
    if (!match_known) {
      const double reach2 = square(distance + facing_reach_);
      if (reach2 != near_radius2_) {
        near_.clear();
        to_.bvh.within(p, reach2, near_);
        near_radius2_ = reach2;
      }
      for (const TriangleBvh::Hit& other : near_)
        if (faces(other.triangle) &&
            (!match_faces || other.squared_distance < match.squared_distance))
          match = other, match_faces = true;
      match_known = true;
    }
    double at_match = match.triangle == hit.triangle
                          ? at_hit
                          : std::abs(value - interpolate(to[match.triangle], match.weights));
    if (area_sample) tally.area_sum[k] += at_match;
    if (at_match > tally.facing[k] && tolerance_ > 0)
      at_match = smallest_difference(
          k, value, at_match, square(std::sqrt(match.squared_distance) + tolerance_), match_faces);
    if (at_match > tally.facing[k]) tally.facing[k] = at_match, tally.facing_at[k] = p;
  }
}

}  // namespace dynpm
