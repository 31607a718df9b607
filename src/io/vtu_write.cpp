// VTK XML UnstructuredGrid (.vtu), written: points, triangles and quads as VTK_TRIANGLE (5) and
// VTK_QUAD (9), the part id and element id of every face and the node id of every vertex, and
// scalar fields per vertex (PointData) and per face (CellData). Binary files hold each array
// inline as base64 after a UInt64 byte count (ParaView, VisIt and meshio read it); --ascii
// writes numbers as text.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>

#include "dynpm/text.h"
#include "formats.h"
#include "scalar_types.h"

namespace dynpm::io {
namespace {

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void append_base64(std::string& out, std::string_view bytes) {
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t n = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 |
                       uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += kBase64[(n >> s) & 63];
  }
  if (const size_t rest = bytes.size() - i; rest > 0) {
    uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
    if (rest == 2) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += kBase64[(n >> 18) & 63];
    out += kBase64[(n >> 12) & 63];
    out += rest == 2 ? kBase64[(n >> 6) & 63] : '=';
    out += '=';
  }
}

// One DataArray: its values as little-endian bytes (binary) or text (ascii).
class ArrayOut {
 public:
  explicit ArrayOut(bool binary) : binary_(binary) {}

  template <class T>
  void value(T v) {
    binary_ ? append_binary(data_, v, std::endian::little) : append_text(data_, v);
  }

  // Appends the DataArray element to `out` and empties this one for the next array.
  void flush(std::string& out, const std::string& type, const std::string& name, int components) {
    out += "<DataArray type=\"" + type + "\" Name=\"" + name + "\"";
    if (components > 1) out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    out += binary_ ? " format=\"binary\">\n" : " format=\"ascii\">\n";
    if (binary_) {
      std::string bytes;
      append_binary(bytes, uint64_t{data_.size()}, std::endian::little);
      bytes += data_;
      append_base64(out, bytes);
    } else {
      out += data_;
    }
    out += "\n</DataArray>\n";
    data_.clear();
  }

 private:
  bool binary_;
  std::string data_;
};

}  // namespace

std::string write_vtu(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields) {
  std::string out = "<?xml version=\"1.0\"?>\n";
  if (!options.comment.empty()) {
    std::string comment = options.comment;
    std::replace(comment.begin(), comment.end(), '-', ' ');  // "--" may not appear in a comment
    out += "<!-- " + comment + " -->\n";
  }
  out +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"" +
      std::to_string(topology.vertex_count) + "\" NumberOfCells=\"" +
      std::to_string(topology.faces.size()) + "\">\n";
  ArrayOut a(options.binary);
  out += "<Points>\n";
  for (float c : positions.first(size_t{topology.vertex_count} * 3)) a.value(c);
  a.flush(out, "Float32", "Points", 3);
  out += "</Points>\n<Cells>\n";
  int64_t offset = 0;
  for (const Face& f : topology.faces)
    for (int i = 0; i < f.degree(); ++i) a.value(int64_t{f.v[i]});
  a.flush(out, "Int64", "connectivity", 1);
  for (const Face& f : topology.faces) a.value(offset += f.degree());
  a.flush(out, "Int64", "offsets", 1);
  for (const Face& f : topology.faces) a.value(uint8_t{f.is_triangle() ? uint8_t{5} : uint8_t{9}});
  a.flush(out, "UInt8", "types", 1);
  out += "</Cells>\n<CellData>\n";
  for (int32_t part : topology.part_ids) a.value(part);
  a.flush(out, "Int32", "part_id", 1);
  for (int64_t id : topology.element_ids) a.value(id);
  a.flush(out, "Int64", "element_id", 1);
  for (const NamedValues& field : cell_fields) {
    for (float v : field.values) a.value(v);
    a.flush(out, "Float32", xml_escaped(safe_field_name(field.name)), 1);
  }
  out += "</CellData>\n<PointData>\n";
  for (int64_t id : topology.node_ids) a.value(id);
  a.flush(out, "Int64", "node_id", 1);
  for (const NamedValues& field : point_fields) {
    for (float v : field.values) a.value(v);
    a.flush(out, "Float32", xml_escaped(safe_field_name(field.name)), 1);
  }
  out += "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace dynpm::io
