// Outer faces of solid cells: every cell face keyed by its sorted corners; a key seen once is on
// the boundary.
#include "solid_surface.h"

#include <algorithm>
#include <numeric>

namespace dynpm::io {
namespace {

struct FaceTable {
  int count;
  std::array<std::array<int8_t, 4>, 6> corners;  // -1 in slot 3 for a triangle
};

// Outward faces (counter-clockwise seen from outside) for the corner order in the header.
const FaceTable& face_table(SolidKind kind) {
  static const FaceTable kTet{4, {{{0, 2, 1, -1}, {0, 1, 3, -1}, {1, 2, 3, -1}, {2, 0, 3, -1}}}};
  static const FaceTable kPyramid{
      5, {{{0, 3, 2, 1}, {0, 1, 4, -1}, {1, 2, 4, -1}, {2, 3, 4, -1}, {3, 0, 4, -1}}}};
  static const FaceTable kWedge{
      5, {{{0, 2, 1, -1}, {3, 4, 5, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}}};
  static const FaceTable kHex{
      6, {{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}}};
  switch (kind) {
    case SolidKind::kTet: return kTet;
    case SolidKind::kPyramid: return kPyramid;
    case SolidKind::kWedge: return kWedge;
    case SolidKind::kHex: return kHex;
  }
  return kHex;
}

}  // namespace

int corner_count(SolidKind kind) {
  switch (kind) {
    case SolidKind::kTet: return 4;
    case SolidKind::kPyramid: return 5;
    case SolidKind::kWedge: return 6;
    case SolidKind::kHex: return 8;
  }
  return 8;
}

void SolidSurface::add_cell(SolidKind kind, std::span<const uint32_t> corners, int32_t part,
                            int64_t element_id) {
  assert(corners.size() == static_cast<size_t>(corner_count(kind)));
  const FaceTable& table = face_table(kind);
  const uint32_t cell = static_cast<uint32_t>(cell_part_.size());
  cell_part_.push_back(part);
  cell_element_.push_back(element_id);
  for (int f = 0; f < table.count; ++f) {
    // Corners of the face with repeats removed (a degenerate hex's collapsed edges).
    std::array<uint32_t, 4> v{kNoVertex, kNoVertex, kNoVertex, kNoVertex};
    int n = 0;
    for (int8_t c : table.corners[f]) {
      if (c < 0) break;
      const uint32_t vertex = corners[static_cast<size_t>(c)];
      if (std::find(v.begin(), v.begin() + n, vertex) == v.begin() + n) v[n++] = vertex;
    }
    if (n < 3) continue;
    CellFace face;
    face.face.v = v;
    face.key = v;
    std::sort(face.key.begin(), face.key.end());  // the unused corners (kNoVertex) sort last
    face.cell = cell;
    faces_.push_back(face);
  }
}

size_t SolidSurface::append_outer_faces(Topology& topology, std::vector<uint32_t>* cells) const {
  std::vector<uint32_t> order(faces_.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return faces_[a].key != faces_[b].key ? faces_[a].key < faces_[b].key : a < b;
  });
  std::vector<uint8_t> outer(faces_.size(), 0);
  for (size_t i = 0; i < order.size();) {
    size_t j = i + 1;
    while (j < order.size() && faces_[order[j]].key == faces_[order[i]].key) ++j;
    if (j - i == 1) outer[order[i]] = 1;
    i = j;
  }
  size_t added = 0;
  for (size_t i = 0; i < faces_.size(); ++i) {
    if (!outer[i]) continue;
    const uint32_t cell = faces_[i].cell;
    topology.add_face(faces_[i].face, cell_part_[cell], cell_element_[cell]);
    if (cells) cells->push_back(cell);
    ++added;
  }
  return added;
}

std::vector<uint32_t> drop_unused_vertices(Topology& topology) {
  std::vector<uint32_t> new_index(topology.vertex_count, kNoVertex);
  for (const Face& f : topology.faces)
    for (uint32_t c : f.v)
      if (c != kNoVertex && c < topology.vertex_count) new_index[c] = 0;
  std::vector<uint32_t> kept;
  for (uint32_t v = 0; v < topology.vertex_count; ++v)
    if (new_index[v] == 0) {
      new_index[v] = static_cast<uint32_t>(kept.size());
      kept.push_back(v);
    }
  if (kept.size() == topology.vertex_count) return {};
  for (Face& f : topology.faces)
    for (uint32_t& c : f.v)
      if (c != kNoVertex) c = new_index[c];
  if (topology.node_ids.size() == topology.vertex_count) {
    std::vector<int64_t> ids(kept.size());
    for (size_t i = 0; i < kept.size(); ++i) ids[i] = topology.node_ids[kept[i]];
    topology.node_ids = std::move(ids);
  }
  topology.vertex_count = static_cast<uint32_t>(kept.size());
  return kept;
}

}  // namespace dynpm::io
