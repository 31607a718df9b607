// VTK XML files: UnstructuredGrid (.vtu) and ParaView collections (.pvd).
//
// A .vtu's DataArrays may be ascii, inline base64 ("binary") or in the AppendedData section
// (raw or base64); binary data start with a UInt32 or UInt64 header (header_type) holding the
// byte count, or, with compressor="vtkZLibDataCompressor", the block table of zlib-compressed
// blocks. Byte order per byte_order. Only the first Piece is read (VTK writers use one).
// The XML is read by a small scanner that knows tags and attributes, nothing else.
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "scalar_types.h"
#include "vtk_read.h"
#include "xml_tags.h"

#if DYNPM_HAVE_ZLIB
#include <zlib.h>
#endif

namespace dynpm::io {
namespace {

// ---------------------------------------------------------------------------------------------
// DataArray payloads

std::optional<ScalarType> xml_type(std::string_view name) {
  if (name == "Int8" || name == "Char") return ScalarType::kInt8;
  if (name == "UInt8") return ScalarType::kUInt8;
  if (name == "Int16") return ScalarType::kInt16;
  if (name == "UInt16") return ScalarType::kUInt16;
  if (name == "Int32") return ScalarType::kInt32;
  if (name == "UInt32") return ScalarType::kUInt32;
  if (name == "Int64") return ScalarType::kInt64;
  if (name == "UInt64") return ScalarType::kUInt64;
  if (name == "Float32") return ScalarType::kFloat32;
  if (name == "Float64") return ScalarType::kFloat64;
  return std::nullopt;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Decodes base64 text, blanks ignored. VTK encodes a binary array's header and its data as two
// base64 runs, each with its own '=' padding, so decoding goes on after padding.
// Stops after `limit` output bytes. false on a character that is not base64.
bool decode_base64(std::string_view text, std::string& out, size_t limit = SIZE_MAX) {
  uint32_t bits = 0;
  int have = 0;
  for (char c : text) {
    if (out.size() >= limit) return true;
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c == '=') {
      bits = 0, have = 0;  // the end of one run
      continue;
    }
    const int v = base64_value(c);
    if (v < 0) return false;
    bits = (bits << 6) | uint32_t(v);
    have += 6;
    if (have >= 8) {
      have -= 8;
      out += static_cast<char>((bits >> have) & 0xff);
    }
  }
  return true;
}

// Characters of base64 text that encode n bytes (with padding).
size_t base64_length(uint64_t n) { return size_t((n + 2) / 3 * 4); }

struct FileInfo {
  std::string path;
  bool swap = false;          // byte_order differs from this machine's
  size_t header_size = 4;     // UInt32 or UInt64
  bool compressed = false;    // vtkZLibDataCompressor
  std::string_view appended;  // the bytes after AppendedData's '_'
  bool appended_base64 = false;
  size_t appended_at = 0;  // file offset of appended[0]
};

struct ArrayRef {
  std::string name;
  ScalarType type = ScalarType::kFloat32;
  size_t components = 1;
  std::string format;        // ascii, binary, appended
  uint64_t offset = 0;       // appended
  std::string_view content;  // between the tags (ascii, binary)
  size_t content_at = 0;     // file offset of the content
};

class Decoder {
 public:
  explicit Decoder(const FileInfo& file) : f_(file) {}

  // The array's values, exactly `count` of them (tuples × components), as doubles.
  Result<std::vector<double>> values(const ArrayRef& a, uint64_t count) {
    const std::string where =
        f_.path + ": byte " + std::to_string(a.content_at) + ": DataArray " + quoted_bytes(a.name);
    std::vector<double> out;
    if (a.format == "ascii") {
      if (count > a.content.size() / 2 + 1)
        return Status::error(where + ": " + std::to_string(count) +
                             " values expected, more than the text can hold");
      out.reserve(count);
      const char* p = a.content.data();
      const char* end = p + a.content.size();
      while (true) {
        while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
        if (p == end) break;
        const char* stop = p;
        while (stop < end && !std::isspace(static_cast<unsigned char>(*stop))) ++stop;
        const std::string_view token(p, static_cast<size_t>(stop - p));
        // The rule of every text reader (text.h): a whole number; an integer type takes whole
        // integers within its range, as its binary form could hold.
        double v = 0;
        const NumberError e = parse_scalar(token, a.type, v);
        if (e != NumberError::kNone)
          return Status::error(where + ": value " + std::to_string(out.size() + 1) + ", " +
                               quoted_bytes(token) + ", " +
                               (e == NumberError::kOutOfRange
                                    ? std::string("is out of the range of its type")
                                    : std::string("is not ") + number_kind(a.type)));
        if (out.size() == count)
          return Status::error(where + ": more than the " + std::to_string(count) +
                               " values expected");
        out.push_back(v);
        p = stop;
      }
      if (out.size() != count)
        return Status::error(where + ": " + std::to_string(out.size()) + " values, expected " +
                             std::to_string(count));
      return out;
    }
    const size_t size = size_of(a.type);
    if (count > (uint64_t(1) << 40) / size) return Status::error(where + ": too many values");
    const uint64_t expected = count * size;
    std::string bytes;
    if (a.format == "binary") {
      std::string decoded;
      decoded.reserve(a.content.size() / 4 * 3 + 3);
      if (!decode_base64(a.content, decoded)) return Status::error(where + ": not base64 text");
      auto payload = unpack(decoded, expected, where);
      if (!payload) return payload.status();
      bytes = std::move(payload).value();
    } else if (a.format == "appended") {
      auto payload = appended(a.offset, expected, where);
      if (!payload) return payload.status();
      bytes = std::move(payload).value();
    } else {
      return Status::error(where + ": unknown format " + quoted_bytes(a.format));
    }
    out.resize(count);
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    for (uint64_t i = 0; i < count; ++i) out[i] = load_scalar(a.type, p + i * size, f_.swap);
    return out;
  }

 private:
  uint64_t header_word(const std::string& b, size_t i) const {
    const auto* p = reinterpret_cast<const unsigned char*>(b.data()) + i * f_.header_size;
    return f_.header_size == 8 ? uint64_t(load_scalar<uint64_t>(p, f_.swap))
                               : uint64_t(load_scalar<uint32_t>(p, f_.swap));
  }

  // Header + data (decoded) → the expected bytes of data, decompressed if need be.
  Result<std::string> unpack(const std::string& b, uint64_t expected, const std::string& where) {
    const size_t hs = f_.header_size;
    if (!f_.compressed) {
      if (b.size() < hs) return Status::error(where + ": no size header");
      const uint64_t n = header_word(b, 0);
      if (n != expected)
        return Status::error(where + ": holds " + std::to_string(n) + " bytes, expected " +
                             std::to_string(expected));
      if (b.size() - hs < n) return Status::error(where + ": the data are cut short");
      return b.substr(hs, n);
    }
    if (b.size() < 3 * hs) return Status::error(where + ": no compression header");
    const uint64_t blocks = header_word(b, 0), block_size = header_word(b, 1),
                   last = header_word(b, 2);
    if (blocks > (b.size() - 3 * hs) / hs)
      return Status::error(where + ": the compression header announces " + std::to_string(blocks) +
                           " blocks, more than the data can hold");
    const uint64_t total =
        blocks == 0 ? 0 : (blocks - 1) * block_size + (last == 0 ? block_size : last);
    if (total != expected)
      return Status::error(where + ": holds " + std::to_string(total) + " bytes, expected " +
                           std::to_string(expected));
    // zlib cannot expand by more than about 1032:1: a larger claim is a broken header, and
    // must not become an allocation.
    if (total / 1100 > b.size())
      return Status::error(where + ": claims " + std::to_string(total) +
                           " bytes, more than its compressed data can hold");
#if DYNPM_HAVE_ZLIB
    std::string out(expected, '\0');
    size_t in_at = size_t(3 + blocks) * hs, out_at = 0;
    for (uint64_t k = 0; k < blocks; ++k) {
      const uint64_t compressed = header_word(b, size_t(3 + k));
      const uint64_t raw = k + 1 == blocks && last != 0 ? last : block_size;
      if (compressed > b.size() - in_at || raw > out.size() - out_at)
        return Status::error(where + ": compressed block " + std::to_string(k) + " is cut short");
      uLongf out_len = static_cast<uLongf>(raw);
      const int rc = ::uncompress(reinterpret_cast<Bytef*>(out.data() + out_at), &out_len,
                                  reinterpret_cast<const Bytef*>(b.data() + in_at),
                                  static_cast<uLong>(compressed));
      if (rc != Z_OK || out_len != raw)
        return Status::error(where + ": zlib cannot decompress block " + std::to_string(k));
      in_at += compressed, out_at += raw;
    }
    return out;
#else
    return Status::error(where +
                         ": zlib-compressed, and this dynpm was built without zlib "
                         "(install zlib1g-dev and rebuild)");
#endif
  }

  Result<std::string> appended(uint64_t offset, uint64_t expected, const std::string& where) {
    const std::string_view data = f_.appended;
    if (offset > data.size()) return Status::error(where + ": offset past the appended data");
    const size_t hs = f_.header_size;
    if (!f_.appended_base64) {
      // Raw: the header words, then (compressed) blocks; unpack() takes them as one string
      // once their extent is known.
      const std::string_view rest = data.substr(size_t(offset));
      if (rest.size() < (f_.compressed ? 3 * hs : hs))
        return Status::error(where + ": the appended data end inside its header");
      std::string head(rest.substr(0, f_.compressed ? 3 * hs : hs));
      uint64_t length = 0;
      if (!f_.compressed) {
        length = hs + header_word(head, 0);
      } else {
        const uint64_t blocks = header_word(head, 0);
        if (blocks > (rest.size() - 3 * hs) / hs)
          return Status::error(where + ": the compression header announces more blocks than fit");
        const std::string table(rest.substr(0, size_t(3 + blocks) * hs));
        length = table.size();
        for (uint64_t k = 0; k < blocks; ++k) length += header_word(table, size_t(3 + k));
      }
      if (length > rest.size()) return Status::error(where + ": the appended data are cut short");
      return unpack(std::string(rest.substr(0, size_t(length))), expected, where);
    }
    // base64: the header and the data are separate runs.
    const std::string_view rest = data.substr(size_t(offset));
    std::string head;
    const size_t first = f_.compressed ? 3 * hs : hs;
    if (!decode_base64(rest.substr(0, std::min(rest.size(), base64_length(first))), head) ||
        head.size() < first)
      return Status::error(where + ": cannot decode the appended header");
    size_t header_bytes = first;
    uint64_t body = 0;
    if (!f_.compressed) {
      // Uncompressed, VTK encodes the size and the data as one run; a '=' ending the size's
      // characters says another writer encoded them as two.
      body = header_word(head, 0);
      const size_t one_run = base64_length(hs + body);
      const bool two_runs = rest.size() >= base64_length(hs) && rest[base64_length(hs) - 1] == '=';
      const size_t chars = two_runs ? base64_length(hs) + base64_length(body) : one_run;
      if (body > rest.size() || chars > rest.size())
        return Status::error(where + ": the appended data are cut short");
      std::string all;
      if (!decode_base64(rest.substr(0, chars), all))
        return Status::error(where + ": cannot decode the appended data");
      return unpack(all, expected, where);
    } else {
      const uint64_t blocks = header_word(head, 0);
      if (blocks > rest.size()) return Status::error(where + ": bad compression header");
      header_bytes = size_t(3 + blocks) * hs;
      head.clear();
      if (!decode_base64(rest.substr(0, std::min(rest.size(), base64_length(header_bytes))),
                         head) ||
          head.size() < header_bytes)
        return Status::error(where + ": cannot decode the appended header");
      for (uint64_t k = 0; k < blocks; ++k) body += header_word(head, size_t(3 + k));
    }
    if (body > rest.size()) return Status::error(where + ": the appended data are cut short");
    head.resize(header_bytes);
    const size_t chars = base64_length(header_bytes);
    if (chars > rest.size()) return Status::error(where + ": the appended data are cut short");
    if (!decode_base64(rest.substr(chars, std::min(rest.size() - chars, base64_length(body))),
                       head))
      return Status::error(where + ": cannot decode the appended data");
    return unpack(head, expected, where);
  }

  const FileInfo& f_;
};

// ---------------------------------------------------------------------------------------------
// parse_vtu()'s phases

// What the tags of a .vtu say: the file's encoding, the piece's counts, and where each
// DataArray lies.
struct VtuLayout {
  FileInfo file;
  std::optional<ArrayRef> points, connectivity, offsets, types;
  std::vector<ArrayRef> point_arrays, cell_arrays, field_arrays;
  uint64_t n_points = 0, n_cells = 0;
};

Result<VtuLayout> scan_tags(std::string_view bytes, const std::string& path) {
  VtuLayout layout;
  FileInfo& file = layout.file;
  file.path = path;
  XmlScanner xml(bytes);
  Tag tag;
  std::vector<std::string_view> stack;
  int pieces = 0;
  bool saw_file = false;
  auto fail_at = [&](size_t at, const std::string& cause) {
    return Status::error(path + ": byte " + std::to_string(at) + ": " + cause);
  };
  auto count_attribute = [&](const Tag& t, std::string_view key) -> Result<uint64_t> {
    auto v = attribute(t, key);
    if (!v) return fail_at(t.begin, std::string(t.name) + " needs a number in " + std::string(key));
    uint64_t n = 0;
    const NumberError e = parse_count(*v, n);
    if (e != NumberError::kNone)
      return fail_at(
          t.begin,
          std::string(t.name) + " " + std::string(key) + "=" + quoted_bytes(*v) +
              (e == NumberError::kOutOfRange ? " is out of range" : " is not a whole number"));
    return n;
  };

  while (xml.next(tag)) {
    if (tag.closing) {
      if (stack.empty() || stack.back() != tag.name)
        return fail_at(tag.begin, "</" + printable(tag.name) + "> does not close <" +
                                      (stack.empty() ? "" : printable(stack.back())) + ">");
      stack.pop_back();
      continue;
    }
    const std::string_view parent = stack.empty() ? std::string_view() : stack.back();
    if (tag.name == "VTKFile") {
      saw_file = true;
      const auto type = attribute(tag, "type");
      if (type != "UnstructuredGrid")
        return fail_at(tag.begin, "a VTK XML file of type " + quoted_bytes(type.value_or("")) +
                                      "; dynpm reads UnstructuredGrid (.vtu)");
      const std::string order = attribute(tag, "byte_order").value_or("LittleEndian");
      file.swap = (order == "BigEndian") != (std::endian::native == std::endian::big);
      const std::string header = attribute(tag, "header_type").value_or("UInt32");
      if (header != "UInt32" && header != "UInt64")
        return fail_at(tag.begin, "unsupported header_type " + quoted_bytes(header));
      file.header_size = header == "UInt64" ? 8 : 4;
      if (auto c = attribute(tag, "compressor")) {
        if (*c != "vtkZLibDataCompressor")
          return fail_at(tag.begin, "compressor " + quoted_bytes(*c) +
                                        " is not supported (dynpm reads zlib-compressed and "
                                        "uncompressed VTU files)");
        file.compressed = true;
      }
    } else if (tag.name == "Piece") {
      if (++pieces > 1)
        return fail_at(tag.begin, "a second Piece; dynpm reads single-piece .vtu files");
      auto np = count_attribute(tag, "NumberOfPoints");
      if (!np) return np.status();
      auto nc = count_attribute(tag, "NumberOfCells");
      if (!nc) return nc.status();
      layout.n_points = *np, layout.n_cells = *nc;
      if (layout.n_cells > (uint64_t(1) << 40)) return fail_at(tag.begin, "too many cells");
      if (layout.n_points > kNoVertex - 1) return fail_at(tag.begin, "too many points");
    } else if (tag.name == "DataArray") {
      ArrayRef a;
      a.name = attribute(tag, "Name").value_or("");
      const std::string type = attribute(tag, "type").value_or("");
      const auto t = xml_type(type);
      if (!t)
        return fail_at(tag.begin, "DataArray " + quoted_bytes(a.name) + " has unsupported type " +
                                      quoted_bytes(type));
      a.type = *t;
      if (auto c = attribute(tag, "NumberOfComponents")) {
        auto n = count_attribute(tag, "NumberOfComponents");
        if (!n) return n.status();
        if (*n == 0 || *n > 1000) return fail_at(tag.begin, "bad NumberOfComponents");
        a.components = *n;
      }
      a.format = attribute(tag, "format").value_or("ascii");
      if (a.format == "appended") {
        auto o = count_attribute(tag, "offset");
        if (!o) return o.status();
        a.offset = *o;
      }
      a.content_at = tag.end;
      if (!tag.empty) {
        // The data run up to the first child (VTK adds <InformationKey> elements after them)
        // or the end tag.
        const size_t child = bytes.find('<', tag.end);
        const size_t close = bytes.find("</DataArray", tag.end);
        if (close == std::string_view::npos) return fail_at(tag.begin, "<DataArray> never ends");
        a.content = bytes.substr(tag.end, child - tag.end);
        xml.seek(close);
      }
      if (parent == "Points" && a.name.empty()) a.name = "Points";
      if (parent == "Points" && !layout.points) {
        layout.points = a;
      } else if (parent == "Cells") {
        if (a.name == "connectivity") layout.connectivity = a;
        if (a.name == "offsets") layout.offsets = a;
        if (a.name == "types") layout.types = a;
      } else if (parent == "PointData") {
        layout.point_arrays.push_back(a);
      } else if (parent == "CellData") {
        layout.cell_arrays.push_back(a);
      } else if (parent == "FieldData") {
        layout.field_arrays.push_back(a);
      }
    } else if (tag.name == "AppendedData") {
      const std::string encoding = attribute(tag, "encoding").value_or("raw");
      if (encoding != "raw" && encoding != "base64")
        return fail_at(tag.begin,
                       "AppendedData encoding " + quoted_bytes(encoding) + " is not supported");
      file.appended_base64 = encoding == "base64";
      const size_t mark = bytes.find('_', tag.end);
      if (mark == std::string_view::npos) return fail_at(tag.begin, "AppendedData without '_'");
      file.appended = bytes.substr(mark + 1);
      file.appended_at = mark + 1;
      break;  // raw data follow: no more tags to look for
    }
    if (!tag.empty) stack.push_back(tag.name);
  }
  if (!xml.error().empty()) return fail_at(xml.error_at(), xml.error());
  if (!saw_file) return Status::error(path + ": not a VTK XML file (no <VTKFile>)");
  if (pieces == 0) return Status::error(path + ": no <Piece>");
  if (!layout.points) return Status::error(path + ": no <Points> DataArray");
  if (layout.n_cells > 0 && (!layout.connectivity || !layout.offsets || !layout.types))
    return Status::error(path + ": <Cells> needs the DataArrays connectivity, offsets and types");

  return layout;
}

// The points as positions, and the time a FieldData array (TimeValue, TIME) may hold.
Status read_points(const VtuLayout& layout, Decoder& decode, const std::string& path,
                   ParsedMesh& mesh) {
  const ArrayRef& points = *layout.points;
  if (points.components != 3)
    return Status::error(path + ": Points have " + std::to_string(points.components) +
                         " components, expected 3");
  auto xyz = decode.values(points, layout.n_points * 3);
  if (!xyz) return xyz.status();
  mesh.topology = Topology::with_vertices(static_cast<uint32_t>(layout.n_points));
  mesh.positions.resize(xyz->size());
  std::transform(xyz->begin(), xyz->end(), mesh.positions.begin(),
                 [](double c) { return static_cast<float>(c); });
  for (const ArrayRef& a : layout.field_arrays)
    if (a.name == "TimeValue" || a.name == "TIME") {
      auto t = decode.values(a, 1);
      if (!t) return t.status();
      if (!std::isfinite((*t)[0]))
        return Status::error(path + ": byte " + std::to_string(a.content_at) + ": FieldData " +
                             a.name + " holds the time " + vtk::number_text((*t)[0]) +
                             ", not a finite number");
      mesh.time = (*t)[0];
    }
  return {};
}

// The cells (offsets, types, connectivity) into the sink, which makes them faces.
Status read_cells(const VtuLayout& layout, Decoder& decode, const std::string& path,
                  vtk::CellSink& sink) {
  const uint64_t n_cells = layout.n_cells;
  if (n_cells == 0) return {};
  auto off = decode.values(*layout.offsets, n_cells);
  if (!off) return off.status();
  auto ty = decode.values(*layout.types, n_cells);
  if (!ty) return ty.status();
  const double conn_size = off->back();
  if (!(conn_size >= 0) || conn_size > 9.007199254740992e15)
    return Status::error(path + ": the last cell offset (" + std::to_string(conn_size) +
                         ") is not a possible connectivity size");
  auto conn = decode.values(*layout.connectivity, uint64_t(conn_size));
  if (!conn) return conn.status();
  double start = 0;
  const uint32_t place = static_cast<uint32_t>(layout.connectivity->content_at);
  for (uint64_t c = 0; c < n_cells; ++c) {
    const double stop = (*off)[c];
    if (!(stop >= start) || stop > conn_size)
      return Status::error(path + ": cell offsets decrease or overrun at cell " +
                           std::to_string(c));
    DYNPM_RETURN_IF_ERROR(sink.add(
        (*ty)[c], std::span<const double>(conn->data() + size_t(start), size_t(stop - start)), c,
        place));
    start = stop;
  }
  return {};
}

// The DataArrays of CellData or PointData, `tuples` tuples each.
Result<std::vector<vtk::Array>> read_arrays(Decoder& decode, const std::vector<ArrayRef>& refs,
                                            uint64_t tuples) {
  std::vector<vtk::Array> arrays;
  for (const ArrayRef& r : refs) {
    auto v = decode.values(r, tuples * r.components);
    if (!v) return v.status();
    arrays.push_back(vtk::Array{r.name, r.components, std::move(v).value()});
  }
  return arrays;
}

}  // namespace

Result<ParsedMesh> parse_vtu(std::string_view bytes, const std::string& path,
                             const ReadOptions& options) {
  // 1. The tags: the file's encoding, the piece's counts, where each DataArray lies.
  auto layout = scan_tags(bytes, path);
  if (!layout) return layout.status();
  Decoder decode(layout->file);
  ParsedMesh mesh;
  mesh.places_are_lines = false;
  // 2. The points, and the step's time.
  DYNPM_RETURN_IF_ERROR(read_points(*layout, decode, path, mesh));
  // 3. The cells, as faces.
  vtk::CellSink sink(mesh, layout->n_points, path, options);
  DYNPM_RETURN_IF_ERROR(read_cells(*layout, decode, path, sink));
  sink.finish();
  // 4. Point data (node numbers, node fields), then cell data (parts, element numbers,
  //    element fields).
  auto point_data = read_arrays(decode, layout->point_arrays, layout->n_points);
  if (!point_data) return point_data.status();
  vtk::apply_point_data(*point_data, path, options, mesh);
  auto cell_data = read_arrays(decode, layout->cell_arrays, layout->n_cells);
  if (!cell_data) return cell_data.status();
  vtk::apply_cell_data(*cell_data, layout->n_cells, sink.cell_of_face, path, options, mesh);
  return mesh;
}

Result<std::vector<PvdStep>> parse_pvd(std::string_view bytes, const std::string& path) {
  XmlScanner xml(bytes);
  Tag tag;
  std::vector<PvdStep> steps;
  std::vector<std::string> parts;
  bool saw_collection = false;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  while (xml.next(tag)) {
    if (tag.closing) continue;
    if (tag.name == "VTKFile") {
      if (attribute(tag, "type") != "Collection")
        return Status::error(path + ": byte " + std::to_string(tag.begin) +
                             ": a VTKFile that is not a Collection");
      saw_collection = true;
    } else if (tag.name == "DataSet") {
      const auto file = attribute(tag, "file");
      if (!file || file->empty())
        return Status::error(path + ": byte " + std::to_string(tag.begin) +
                             ": a DataSet without a file attribute");
      // The name goes into messages as it is: no control characters (escape sequences).
      if (std::any_of(file->begin(), file->end(),
                      [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
        return Status::error(path + ": byte " + std::to_string(tag.begin) + ": DataSet file " +
                             quoted_bytes(*file) + " holds control characters");
      PvdStep step;
      std::filesystem::path p(*file);
      step.path = (p.is_absolute() || folder.empty() ? p : folder / p).string();
      const std::string t = attribute(tag, "timestep").value_or(std::to_string(steps.size()));
      if (parse_real(t, step.time) != NumberError::kNone)
        return Status::error(path + ": byte " + std::to_string(tag.begin) + ": timestep " +
                             quoted_bytes(t) + " is not a number");
      if (!std::isfinite(step.time))
        return Status::error(path + ": byte " + std::to_string(tag.begin) + ": timestep " +
                             quoted_bytes(t) + " is not a finite number");
      const std::string part = attribute(tag, "part").value_or("0");
      if (std::find(parts.begin(), parts.end(), part) == parts.end()) parts.push_back(part);
      steps.push_back(std::move(step));
    }
  }
  if (!xml.error().empty())
    return Status::error(path + ": byte " + std::to_string(xml.error_at()) + ": " + xml.error());
  if (!saw_collection) return Status::error(path + ": not a ParaView collection (.pvd)");
  if (steps.empty()) return Status::error(path + ": the collection lists no DataSet");
  if (parts.size() > 1)
    return Status::error(path + ": the collection has " + std::to_string(parts.size()) +
                         " parts per time step; dynpm reads one data set per step");
  std::stable_sort(steps.begin(), steps.end(),
                   [](const PvdStep& a, const PvdStep& b) { return a.time < b.time; });
  return steps;
}

}  // namespace dynpm::io
