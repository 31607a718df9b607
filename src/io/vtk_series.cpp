// VTK inputs beyond one polydata file: what the legacy and XML readers share (cells to faces,
// cell and point data to ids and fields), and .pvd collections opened as step sequences.
#include <algorithm>
#include <cctype>
#include <cmath>

#include "file_bytes.h"
#include "vtk_read.h"

namespace dynpm::io {
namespace vtk {
namespace {

// Lower case, without '_', '-' and blanks: "Part_ID" and "partid" name the same array.
std::string loose_name(const std::string& name) {
  std::string out;
  for (unsigned char c : name)
    if (c != '_' && c != ' ' && c != '-') out += static_cast<char>(std::tolower(c));
  return out;
}

bool is_integral(double v, double lo, double hi) {
  return std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi;
}

bool all_integral(const std::vector<double>& values, double lo, double hi) {
  return std::all_of(values.begin(), values.end(),
                     [&](double v) { return is_integral(v, lo, hi); });
}

bool is_solid(int type) {
  switch (type) {
    case 10:
    case 11:
    case 12:
    case 13:
    case 14:
    case 15:
    case 16:  // linear solids
    case 24:
    case 25:
    case 26:
    case 27:
    case 29:
    case 31:
    case 32:
    case 33:  // quadratic
    case 42:  // polyhedron
    case 71:
    case 72:
    case 73:
    case 74:  // Lagrange
      return true;
    default: return false;
  }
}

}  // namespace

std::string number_text(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9e15)
    return std::to_string(static_cast<int64_t>(v));
  return std::to_string(v);
}

Status CellSink::corner(double index, uint64_t cell, uint32_t& out) const {
  if (!is_integral(index, 0, double(point_count_) - 1))
    return Status::error(path_ + ": cell " + std::to_string(cell) + " refers to point " +
                         number_text(index) + ", but there are " + std::to_string(point_count_) +
                         " points");
  out = static_cast<uint32_t>(index);
  return {};
}

Status CellSink::add_corners(std::span<const uint32_t> corners, uint64_t cell, uint32_t place) {
  if (corners.size() == 3 || corners.size() == 4) {  // the common case, without a message
    Face f;
    std::copy(corners.begin(), corners.end(), f.v.begin());
    mesh_.topology.add_face(f, 0, int64_t(cell) + 1);
    mesh_.face_places.push_back(place);
    cell_of_face.push_back(cell);
    return {};
  }
  const std::string where = path_ + ": cell " + std::to_string(cell);
  DYNPM_RETURN_IF_ERROR(
      add_polygon(corners, 0, int64_t(cell) + 1, place, where, options_, mesh_, split_));
  cell_of_face.resize(mesh_.topology.faces.size(), cell);
  return {};
}

Status CellSink::add(double type_value, std::span<const double> points, uint64_t cell,
                     uint32_t place) {
  if (!is_integral(type_value, 0, 255))
    return Status::error(path_ + ": cell " + std::to_string(cell) + " has the cell type " +
                         number_text(type_value) + " (VTK types are 0 to 255)");
  const int type = static_cast<int>(type_value);
  // Corner counts and, for higher-order cells, how many leading points are the corners.
  size_t need = 0, corners = 0;
  switch (type) {
    case 5: need = corners = 3; break;
    case 9:
    case 8: need = corners = 4; break;
    case 7: need = corners = points.size(); break;
    case 6: need = 3, corners = points.size(); break;
    case 22: need = 6, corners = 3; break;
    case 23: need = 8, corners = 4; break;
    case 28: need = 9, corners = 4; break;
    case 30: need = 7, corners = 3; break;
    case 69: need = 3, corners = 3; break;  // Lagrange: corners first, then edge/face points
    case 70: need = 4, corners = 4; break;
    case 1:
    case 2:
    case 3:
    case 4:
    case 21:
    case 35:
    case 68: ++lines_; return {};
    default:
      if (is_solid(type))
        ++solids_;
      else
        ++unknown_;
      return {};
  }
  if (points.size() < need || (type != 7 && type != 6 && type < 69 && points.size() != need))
    return Status::error(path_ + ": cell " + std::to_string(cell) + " (VTK type " +
                         std::to_string(type) + ") has " + std::to_string(points.size()) +
                         " points, expected " + std::to_string(need));
  if (corners != points.size()) ++reduced_;
  corners_.resize(type == 6 ? points.size() : corners);
  for (size_t i = 0; i < corners_.size(); ++i)
    DYNPM_RETURN_IF_ERROR(corner(points[i], cell, corners_[i]));
  if (type == 8) std::swap(corners_[2], corners_[3]);  // a pixel's corners run 0 1 3 2
  if (type == 6) {
    // A strip: triangle i is (i, i+1, i+2), every other one flipped to keep the orientation.
    for (size_t i = 0; i + 2 < corners_.size(); ++i) {
      const uint32_t tri[3] = {corners_[i], corners_[i + 1 + (i & 1)], corners_[i + 2 - (i & 1)]};
      DYNPM_RETURN_IF_ERROR(add_corners(tri, cell, place));
    }
    return {};
  }
  if (type == 7 && corners_.size() < 3)
    return Status::error(path_ + ": cell " + std::to_string(cell) + ": a polygon with " +
                         std::to_string(corners_.size()) + " points");
  return add_corners(corners_, cell, place);
}

void CellSink::finish() {
  if (!options_.warn) return;
  if (reduced_)
    options_.warn(path_ + ": " + std::to_string(reduced_) +
                  " quadratic (or higher-order) cells reduced to their corner points");
  if (solids_)
    options_.warn(path_ + ": skipped " + std::to_string(solids_) +
                  " solid cells (dynpm reads surface cells: triangles, quads, polygons)");
  if (lines_)
    options_.warn(path_ + ": skipped " + std::to_string(lines_) + " vertex and line cells");
  if (unknown_)
    options_.warn(path_ + ": skipped " + std::to_string(unknown_) + " cells of unknown VTK types");
  if (split_)
    options_.warn(path_ + ": " + std::to_string(split_) +
                  " faces with more than 4 corners split into triangle fans");
}

void apply_cell_data(const std::vector<Array>& arrays, uint64_t cell_count,
                     const std::vector<uint64_t>& cell_of_face, const std::string& path,
                     const ReadOptions& options, ParsedMesh& mesh) {
  Topology& topology = mesh.topology;
  bool have_part = false, have_element = false;
  std::string ignored;
  for (const Array& a : arrays) {
    if (a.values.size() != cell_count * a.components) continue;
    const std::string name = loose_name(a.name);
    const bool part = name == "part" || name == "partid" || name == "partids" || name == "pid" ||
                      name == "geometryids" || name == "gmsh:physical";
    const bool element = name == "elementid" || name == "elementids";
    if (a.components != 1) {
      ignored += (ignored.empty() ? "" : ", ") + quoted_bytes(a.name);
      continue;
    }
    // Any other array is an element field: a face takes its cell's value (the faces of a split
    // polygon repeat it; skipped cells drop theirs). gmsh's entity numbers are no result.
    if (!part && !element) {
      if (name == "gmsh:geometrical") continue;
      MeshField field{a.name, std::vector<float>(cell_of_face.size()), FieldLocation::kElement};
      for (size_t f = 0; f < cell_of_face.size(); ++f)
        field.values[f] = static_cast<float>(a.values[cell_of_face[f]]);
      mesh.fields.push_back(std::move(field));
      continue;
    }
    if ((part && have_part) || (element && have_element)) continue;
    const double lo = part ? INT32_MIN : -9.007199254740992e15;
    const double hi = part ? INT32_MAX : 9.007199254740992e15;
    if (!all_integral(a.values, lo, hi)) {
      if (options.warn)
        options.warn(path + ": cell data " + quoted_bytes(a.name) +
                     " holds non-integer values; not used as " +
                     (part ? "part ids" : "element numbers"));
      continue;
    }
    for (size_t f = 0; f < cell_of_face.size(); ++f) {
      const double v = a.values[cell_of_face[f]];
      if (part)
        topology.part_ids[f] = static_cast<int32_t>(v);
      else
        topology.element_ids[f] = static_cast<int64_t>(v);
    }
    (part ? have_part : have_element) = true;
  }
  if (!ignored.empty() && options.warn)
    options.warn(
        path +
        ": cell data with several components not read (dynpm keeps scalar fields): " + ignored);
}

void apply_point_data(std::vector<Array>& arrays, const std::string& path,
                      const ReadOptions& options, ParsedMesh& mesh) {
  const size_t n = mesh.topology.vertex_count;
  std::string ignored;
  bool have_ids = false;
  for (Array& a : arrays) {
    if (a.values.size() != n * a.components) continue;
    const std::string name = loose_name(a.name);
    if (a.components == 1 && !have_ids && (name == "nodeid" || name == "nodeids") &&
        all_integral(a.values, -9.007199254740992e15, 9.007199254740992e15)) {
      for (size_t v = 0; v < n; ++v) mesh.topology.node_ids[v] = static_cast<int64_t>(a.values[v]);
      have_ids = true;
      continue;
    }
    if (a.components != 1) {
      ignored += (ignored.empty() ? "" : ", ") + quoted_bytes(a.name);
      continue;
    }
    MeshField field;
    field.name = a.name;
    field.values.resize(n);
    std::transform(a.values.begin(), a.values.end(), field.values.begin(),
                   [](double v) { return static_cast<float>(v); });
    mesh.fields.push_back(std::move(field));
    std::vector<double>().swap(a.values);
  }
  if (!ignored.empty() && options.warn)
    options.warn(path +
                 ": point data with several components not read (dynpm keeps scalar "
                 "fields): " +
                 ignored);
}

}  // namespace vtk

Result<AnimationStream> open_vtk_series(const std::string& path, const ReadOptions& options) {
  auto format = detect_format(path);
  if (!format) return format.status();
  if (*format != FileFormat::kPvd) {
    const std::string paths[] = {path};
    return open_animation(paths, options);
  }
  auto bytes = read_file(path);
  if (!bytes) return bytes.status();
  auto steps = parse_pvd(*bytes, path);
  if (!steps) return steps.status();
  std::vector<std::string> paths;
  std::vector<double> times;
  for (const PvdStep& s : *steps) {
    paths.push_back(s.path);
    times.push_back(s.time);
  }
  return open_file_sequence(paths, times, options);
}

}  // namespace dynpm::io
