// Meshes built in code, readable as drawings (pmp-library's habit). Vertex numbers in the
// drawings are the indices; faces are counter-clockwise seen from +z.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "dynpm/core.h"

namespace dynpm::test {

// A mesh with one step of positions.
struct Mesh {
  Topology topology;
  std::vector<float> positions;

  Animation animation() const {
    Animation a;
    a.topology = topology;
    a.frames.set_vertex_count(topology.vertex_count);
    a.frames.add_step(positions, 0.0);
    return a;
  }
};

// nx × ny unit quads in the plane z = 0:
//   (ny)  +---+---+
//         | 2 | 3 |       vertex (i, j) = j·(nx+1) + i
//         +---+---+
//         | 0 | 1 |
//   (0)   +---+---+  (nx)
inline Mesh quad_grid(uint32_t nx, uint32_t ny, int32_t part = 0) {
  Mesh m;
  m.topology = Topology::with_vertices((nx + 1) * (ny + 1));
  for (uint32_t j = 0; j <= ny; ++j)
    for (uint32_t i = 0; i <= nx; ++i)
      m.positions.insert(m.positions.end(), {float(i), float(j), 0.f});
  auto id = [&](uint32_t i, uint32_t j) { return j * (nx + 1) + i; };
  for (uint32_t j = 0; j < ny; ++j)
    for (uint32_t i = 0; i < nx; ++i)
      m.topology.add_quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1), part);
  return m;
}

// Two copies of the plate `m` (at z = 0) 0.01 apart, as at a crash fold's contact: the lower at
// z = −shift carrying the value 0, the upper 0.01 higher carrying 1 — facing down when
// `upper_faces_down` (a sheet folded onto itself), else facing the lower's way (two sheets
// stacked). `shift` moves both down (a copy within `shift` of the original, as a bound allows).
inline Mesh two_sheets(Mesh m, float shift, bool upper_faces_down, std::vector<float>& values) {
  const uint32_t n = m.topology.vertex_count;
  const size_t faces = m.topology.faces.size();
  m.positions.resize(6 * size_t{n});
  for (uint32_t v = 0; v < n; ++v) {
    std::copy_n(&m.positions[3 * v], 3, &m.positions[3 * (n + v)]);
    m.positions[3 * v + 2] = -shift, m.positions[3 * (n + v) + 2] = 0.01f - shift;
  }
  for (size_t f = 0; f < faces; ++f) {
    Face upper = m.topology.faces[f];
    if (upper_faces_down) std::reverse(upper.v.begin(), upper.v.begin() + upper.degree());
    for (uint32_t& c : upper.v)
      if (c != kNoVertex) c += n;
    m.topology.faces.push_back(upper);
    m.topology.part_ids.push_back(m.topology.part_ids[f]);
  }
  m.topology.vertex_count = 2 * n;
  m.topology.node_ids.clear(), m.topology.element_ids.clear();
  values.assign(n, 0.f), values.resize(2 * size_t{n}, 1.f);
  return m;
}

// Two quads and two triangles in a row, the mixed case of the paper's Figure 3:
//   3---4---5---6
//   |   |   | \ |
//   0---1---2---7     faces: quad 0-1-4-3, quad 1-2-5-4, tri 2-7-6, tri 2-6-5
inline Mesh tri_quad_strip() {
  Mesh m;
  m.topology = Topology::with_vertices(8);
  m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 3, 1, 0, 3, 0, 0};
  m.topology.add_quad(0, 1, 4, 3);
  m.topology.add_quad(1, 2, 5, 4);
  m.topology.add_triangle(2, 7, 6);
  m.topology.add_triangle(2, 6, 5);
  return m;
}

// Three shells meeting along the line x = 1 (vertices 1, 4): a T-joint, as where a rib is
// welded onto a panel. Part 1 is the panel (two quads in z = 0), part 2 the rib (one quad in
// the plane x = 1, standing up in +z). Edge (1, 4) has three faces.
//   panel: 0---1---2        rib: 1---6 (z = 1)
//          |   |   |             |   |
//          3---4---5             4---7
inline Mesh t_joint() {
  Mesh m;
  m.topology = Topology::with_vertices(8);
  m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 1, 0, 1, 1, 1, 1};
  m.topology.add_quad(0, 3, 4, 1, 1);
  m.topology.add_quad(1, 4, 5, 2, 1);
  m.topology.add_quad(1, 6, 7, 4, 2);
  return m;
}

// Two triangles touching in vertex 2 only: a bow-tie, a non-manifold vertex.
//   0       3
//   | \   / |
//   |   2   |
//   | /   \ |
//   1       4
inline Mesh bow_tie() {
  Mesh m;
  m.topology = Topology::with_vertices(5);
  m.positions = {0, 1, 0, 0, -1, 0, 1, 0, 0, 2, 1, 0, 2, -1, 0};
  m.topology.add_triangle(0, 1, 2);
  m.topology.add_triangle(2, 4, 3);
  return m;
}

// An inner vertex of valence 2, the result of the paper's Figure 5 collapse: two quads that
// share the two edges (v, a) and (v, b) around v = 0. This breaks (M2).
//        1 (a)
//       / \ .
//      3 0 4      quad (0, 1, 3, 2) and quad (0, 2, 4, 1)
//       \ /
//        2 (b)
inline Mesh valence_two_quads() {
  Mesh m;
  m.topology = Topology::with_vertices(5);
  m.positions = {0, 0, 0, 0, 1, 0, 0, -1, 0, -1, 0, 0, 1, 0, 0};
  m.topology.add_quad(0, 1, 3, 2);
  m.topology.add_quad(0, 2, 4, 1);
  return m;
}

// A fresh, empty folder under the system temp dir, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "dynpm-test-XXXXXX").string();
    path_ = ::mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string source_dir() { return DYNPM_SOURCE_DIR; }
inline std::string sample_dir() { return DYNPM_SAMPLE_DIR; }
inline std::string shared_data() { return DYNPM_SHARED_DATA; }

}  // namespace dynpm::test
