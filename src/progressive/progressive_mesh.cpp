// The vertex split and its inverse on a face array, and position quantization.
#include <algorithm>
#include <cmath>

#include "core/face_geometry.h"
#include "dpm_format.h"
#include "dynpm/progressive.h"

namespace dynpm {
namespace {

// Whether split i fits the faces as they are: indices in range, moved faces hold the parent,
// quad wings are triangles holding the parent and the wing vertex side by side.
bool check_split(const ProgressiveMesh& mesh, uint32_t i, std::span<const Face> faces,
                 uint32_t face_count, std::string& problem) {
  const uint32_t v0 = mesh.base_vertex_count + i;
  const uint32_t v1 = mesh.parent[i];
  const std::string where = "split " + std::to_string(i) + ": ";
  if (v1 >= v0)
    return problem = where + "parent " + std::to_string(v1) + " does not exist yet", false;
  uint32_t created = face_count;
  for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m) {
    const uint32_t f = mesh.moved_faces[m];
    if (f >= face_count)
      return problem = where + "moved face " + std::to_string(f) + " does not exist", false;
    if (corner_of(faces[f], v1) < 0)
      return problem = where + "moved face " + std::to_string(f) + " does not hold the parent",
             false;
  }
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
    const SplitWing& w = mesh.wings[k];
    if (w.vertex >= v0 || w.vertex == v1)
      return problem = where + "wing vertex " + std::to_string(w.vertex) + " is not valid", false;
    if (w.was_triangle()) {
      if (w.face != created || created >= faces.size())
        return problem = where + "re-created face " + std::to_string(w.face) + " is out of order",
               false;
      if (w.v0_slot() > 2) return problem = where + "a triangle has no corner slot 3", false;
      ++created;
      continue;
    }
    if (w.face >= face_count)
      return problem = where + "wing face " + std::to_string(w.face) + " does not exist", false;
    const Face& face = faces[w.face];
    const int a = corner_of(face, v1), b = corner_of(face, w.vertex);
    if (!face.is_triangle() || a < 0 || b < 0)
      return problem = where + "wing face " + std::to_string(w.face) +
                       " is not a triangle holding the parent and the wing vertex",
             false;
  }
  return true;
}

// After a checked split: every face it touched has distinct corners (a face named twice, or
// both moved and a wing, would not).
bool touched_faces_valid(const ProgressiveMesh& mesh, uint32_t i, std::span<const Face> faces,
                         std::string& problem) {
  auto distinct = [&](uint32_t f) {
    const Face& face = faces[f];
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (face.v[a] != kNoVertex && face.v[a] == face.v[b]) return false;
    return face.degree() >= 3;
  };
  for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
    if (!distinct(mesh.moved_faces[m]))
      return problem = "split " + std::to_string(i) + ": face " +
                       std::to_string(mesh.moved_faces[m]) + " is named twice",
             false;
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
    if (!distinct(mesh.wings[k].face))
      return problem = "split " + std::to_string(i) + ": face " +
                       std::to_string(mesh.wings[k].face) + " is named twice",
             false;
  return true;
}

// The corner holding `from` takes `to`, without a branch on which slot it is: the face was
// just read from memory, and a branch on its contents would stall the next face's load until
// this one arrived (the navigator's time goes to these cache misses).
inline void replace_corner(Face& face, uint32_t from, uint32_t to) {
  for (uint32_t& c : face.v) c = c == from ? to : c;
}

}  // namespace

uint32_t ProgressiveMesh::face_count_after(uint32_t k) const {
  uint32_t n = base_face_count;
  for (uint32_t i = 0; i < k; ++i)
    for (uint32_t w = wing_start[i]; w < wing_start[i + 1]; ++w) n += wings[w].was_triangle();
  return n;
}

double ProgressiveMesh::diagonal() const {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (bbox_max[k] - bbox_min[k]) * (bbox_max[k] - bbox_min[k]);
  return std::sqrt(d2);
}

bool apply_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                 uint32_t& face_count, std::string* problem) {
  if (problem && !check_split(mesh, i, faces, face_count, *problem)) return false;
  const uint32_t v0 = mesh.base_vertex_count + i;
  const uint32_t v1 = mesh.parent[i];
  for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m) {
    Face& face = faces[mesh.moved_faces[m]];
    if (problem && corner_of(face, v1) < 0) {  // a face listed twice: check_split() lets it by
      *problem = "split " + std::to_string(i) + ": moved face named twice";
      return false;
    }
    replace_corner(face, v1, v0);
  }
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
    const SplitWing& w = mesh.wings[k];
    const int s = w.v0_slot();
    if (w.was_triangle()) {  // the triangle the collapse removed comes back
      Face& face = faces[face_count++];
      face.v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
      face.v[s] = v0;
      face.v[(s + 1) % 3] = w.v1_follows_v0() ? v1 : w.vertex;
      face.v[(s + 2) % 3] = w.v1_follows_v0() ? w.vertex : v1;
    } else {  // the triangle becomes the quad again: v0 back into its slot
      Face& face = faces[w.face];
      for (int c = 3; c > s; --c) face.v[c] = face.v[c - 1];
      face.v[s] = v0;
    }
  }
  return !problem || touched_faces_valid(mesh, i, faces, *problem);
}

void undo_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                uint32_t& face_count) {
  const uint32_t v0 = mesh.base_vertex_count + i;
  const uint32_t v1 = mesh.parent[i];
  for (uint32_t k = mesh.wing_start[i + 1]; k-- > mesh.wing_start[i];) {
    const SplitWing& w = mesh.wings[k];
    if (w.was_triangle()) {
      --face_count;
    } else {
      Face& face = faces[w.face];
      for (int c = w.v0_slot(); c < 3; ++c) face.v[c] = face.v[c + 1];
      face.v[3] = kNoVertex;
    }
  }
  for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
    replace_corner(faces[mesh.moved_faces[m]], v0, v1);
}

void quantize_positions(ProgressiveMesh& mesh) {
  set_position_grid(mesh);
  for (auto& xyz : mesh.positions) quantize_step(mesh, xyz);
}

void set_position_grid(ProgressiveMesh& mesh) {
  if (mesh.lossless) {
    mesh.quant_step = 0;
    mesh.max_error = 0;
    return;
  }
  // A grid finer than float32 can hold near the largest coordinate would not survive the round
  // trip through float: keep the spacing at least 4 ulps there (the bound grows to match).
  double largest = 0;
  for (int k = 0; k < 3; ++k)
    largest = std::max({largest, std::abs(mesh.bbox_min[k]), std::abs(mesh.bbox_max[k])});
  double step = 2 * mesh.max_error / std::sqrt(3.0);
  step = std::max(step, 4 * largest * std::ldexp(1.0, -23));
  if (!(step > 0)) step = 1.0;  // every position is the same point
  mesh.quant_step = step;
  mesh.max_error = step * std::sqrt(3.0) / 2;
}

void quantize_step(const ProgressiveMesh& mesh, std::span<float> xyz) {
  if (mesh.lossless) return;
  const progressive::Grid g = progressive::grid_of(mesh);
  for (size_t j = 0; j < xyz.size(); ++j) {
    const int c = static_cast<int>(j % 3);
    xyz[j] = g.p(g.nearest(xyz[j], c), c);
  }
}

void quantize_fields(ProgressiveMesh& mesh, double bound, bool lossless) {
  for (ProgressiveField& f : mesh.fields) {
    f.lossless = lossless;
    if (lossless) {
      f.quant_step = f.max_error = 0;
      continue;
    }
    // As for positions: no finer than float32 holds at the largest magnitude (4 ulps there).
    const double largest = std::max(std::abs(f.min), std::abs(f.max));
    double step = std::max(2 * bound * (f.max - f.min), 4 * largest * std::ldexp(1.0, -23));
    if (!(step > 0)) step = 1.0;  // every value is 0
    f.quant_step = step;
    f.max_error = step / 2;
    for (auto& values : f.values)
      for (float& x : values)
        x = static_cast<float>(f.min + std::nearbyint((x - f.min) / step) * step);
  }
}

}  // namespace dynpm
