// What the legacy (.vtk) and XML (.vtu) VTK readers share: VTK cell types to dynpm faces, and
// cell and point data arrays to part ids, element ids, node ids and per-vertex fields.
#pragma once

#include <string>
#include <vector>

#include "formats.h"

namespace dynpm::io::vtk {

// A data array as read from the file, values widened to double (integers exact up to 2^53).
struct Array {
  std::string name;
  size_t components = 1;
  std::vector<double> values;  // tuples × components
};

// A value read as double, for messages: "7" rather than "7.000000" when it is an integer.
std::string number_text(double v);

// Turns VTK cells into faces: triangles (5), quads (9), pixels (8), polygons (7), triangle
// strips (6); quadratic and Lagrange triangles and quads (22, 23, 28, 30, 69, 70) keep their
// corner nodes. Solid cells and points/lines are skipped; finish() reports each kind once.
class CellSink {
 public:
  CellSink(ParsedMesh& mesh, uint64_t point_count, const std::string& path,
           const ReadOptions& options)
      : mesh_(mesh), point_count_(point_count), path_(path), options_(options) {}

  // Cell number `cell` (0-based, as CELL_DATA counts) of VTK type `type` over the point indices
  // `points`; `place` is stored as the faces' place (line or byte).
  Status add(double type, std::span<const double> points, uint64_t cell, uint32_t place);
  // The warnings about skipped and reduced cells.
  void finish();

  // Per face, the cell it came from (a split polygon or a strip gives several faces).
  std::vector<uint64_t> cell_of_face;

 private:
  Status corner(double index, uint64_t cell, uint32_t& out) const;
  Status add_corners(std::span<const uint32_t> corners, uint64_t cell, uint32_t place);

  ParsedMesh& mesh_;
  uint64_t point_count_;
  const std::string& path_;
  const ReadOptions& options_;
  size_t solids_ = 0, lines_ = 0, reduced_ = 0, split_ = 0, unknown_ = 0;
  std::vector<uint32_t> corners_;
};

// Cell data: the first one-component array named part / part_id / PartId / pid / GeometryIds /
// gmsh:physical (case and '_' ignored) gives the part ids, element_id the element numbers;
// without them parts are 0 and element numbers cell + 1. Every other one-component array
// (but gmsh:geometrical) becomes an element MeshField, one value per face.
void apply_cell_data(const std::vector<Array>& arrays, uint64_t cell_count,
                     const std::vector<uint64_t>& cell_of_face, const std::string& path,
                     const ReadOptions& options, ParsedMesh& mesh);
// Point data: node_id gives the node numbers (else 1..n); every other one-component numeric
// array becomes a node MeshField.
void apply_point_data(std::vector<Array>& arrays, const std::string& path,
                      const ReadOptions& options, ParsedMesh& mesh);

}  // namespace dynpm::io::vtk
