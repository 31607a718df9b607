// VTK legacy polydata (file version 3.0, readable by ParaView, VisIt and meshio): points,
// polygons (triangles and quads as they are), the part id, element id and node id of every
// face and vertex, and scalar fields per vertex (POINT_DATA) and per face (CELL_DATA). Binary data
// is big-endian, as the format says.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>

#include "formats.h"
#include "scalar_types.h"

namespace dynpm::io {
namespace {

class VtkOut {
 public:
  explicit VtkOut(bool binary) : binary_(binary) {}

  template <class T>
  void value(T v) {
    binary_ ? append_binary(out, v, std::endian::big) : append_text(out, v);
  }
  void end_row() {
    if (!binary_) out += '\n';
  }
  void line(const std::string& text) {
    if (!out.empty() && out.back() != '\n') out += '\n';
    out += text;
    out += '\n';
  }

  // 64-bit ids as int when every one fits, else as double (exact up to 2^53).
  void ids(const std::string& name, std::span<const int64_t> values) {
    const bool fits = std::all_of(values.begin(), values.end(),
                                  [](int64_t v) { return v >= INT32_MIN && v <= INT32_MAX; });
    line("SCALARS " + name + (fits ? " int 1" : " double 1"));
    line("LOOKUP_TABLE default");
    for (int64_t v : values) fits ? value(static_cast<int32_t>(v)) : value(static_cast<double>(v));
    end_row();
  }

  void floats(const std::string& name, std::span<const float> values) {
    line("SCALARS " + name + " float 1");
    line("LOOKUP_TABLE default");
    for (float v : values) value(v);
    end_row();
  }

  std::string out;

 private:
  bool binary_;
};

}  // namespace

std::string safe_field_name(std::string name) {
  for (char& c : name)
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
  return name.empty() ? "field" : name;
}

std::string write_vtk(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields) {
  VtkOut vtk(options.binary);
  vtk.line("# vtk DataFile Version 3.0");
  std::string title = options.comment.empty() ? "dynpm mesh" : options.comment;
  std::replace(title.begin(), title.end(), '\n', ' ');
  vtk.line(title.substr(0, 255));
  vtk.line(options.binary ? "BINARY" : "ASCII");
  vtk.line("DATASET POLYDATA");
  vtk.line("POINTS " + std::to_string(topology.vertex_count) + " float");
  for (uint32_t v = 0; v < topology.vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) vtk.value(positions[size_t{v} * 3 + k]);
    vtk.end_row();
  }
  size_t corner_total = 0;
  for (const Face& f : topology.faces) corner_total += static_cast<size_t>(f.degree()) + 1;
  vtk.line("POLYGONS " + std::to_string(topology.faces.size()) + " " +
           std::to_string(corner_total));
  for (const Face& f : topology.faces) {
    const int degree = f.degree();
    vtk.value(static_cast<int32_t>(degree));
    for (int i = 0; i < degree; ++i) vtk.value(static_cast<int32_t>(f.v[i]));
    vtk.end_row();
  }
  vtk.line("CELL_DATA " + std::to_string(topology.faces.size()));
  vtk.line("SCALARS part_id int 1");
  vtk.line("LOOKUP_TABLE default");
  for (int32_t part : topology.part_ids) vtk.value(part);
  vtk.end_row();
  vtk.ids("element_id", topology.element_ids);
  for (const NamedValues& field : cell_fields)
    vtk.floats(safe_field_name(field.name), field.values);
  vtk.line("POINT_DATA " + std::to_string(topology.vertex_count));
  vtk.ids("node_id", topology.node_ids);
  for (const NamedValues& field : point_fields)
    vtk.floats(safe_field_name(field.name), field.values);
  if (vtk.out.back() != '\n') vtk.out += '\n';
  return std::move(vtk.out);
}

}  // namespace dynpm::io
