// Stanford PLY (ascii, binary little- and big-endian). The vertex element's x, y, z (any numeric
// type) and optional node_id, the face element's vertex_indices/vertex_index list and optional
// part_id and element_id are read; every other element and property is skipped by its declared
// type. Counts in the header are checked against the bytes left before anything is allocated.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "formats.h"
#include "scalar_types.h"

namespace dynpm::io {
namespace {

enum class Encoding { kAscii, kBinaryLittle, kBinaryBig };

// A value read from the file as the file wrote it: "9", "2.5", "-1e+20", not "9.000000".
std::string number_text(double value) {
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(value);
}

std::optional<ScalarType> scalar_type(std::string_view name) {
  if (name == "char" || name == "int8") return ScalarType::kInt8;
  if (name == "uchar" || name == "uint8") return ScalarType::kUInt8;
  if (name == "short" || name == "int16") return ScalarType::kInt16;
  if (name == "ushort" || name == "uint16") return ScalarType::kUInt16;
  if (name == "int" || name == "int32") return ScalarType::kInt32;
  if (name == "uint" || name == "uint32") return ScalarType::kUInt32;
  if (name == "float" || name == "float32") return ScalarType::kFloat32;
  if (name == "double" || name == "float64") return ScalarType::kFloat64;
  return std::nullopt;
}

const char* type_name(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8: return "char";
    case ScalarType::kUInt8: return "uchar";
    case ScalarType::kInt16: return "short";
    case ScalarType::kUInt16: return "ushort";
    case ScalarType::kInt32: return "int";
    case ScalarType::kUInt32: return "uint";
    case ScalarType::kFloat32: return "float";
    case ScalarType::kFloat64: return "double";
    case ScalarType::kInt64:
    case ScalarType::kUInt64: break;  // no PLY types
  }
  return "?";
}

struct Property {
  std::string name;
  ScalarType type = ScalarType::kFloat32;
  bool is_list = false;
  ScalarType count_type = ScalarType::kUInt8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

// Reads one value at a time from the body, in the file's encoding.
class BodyReader {
 public:
  BodyReader(std::string_view body, size_t body_offset, Encoding encoding, const std::string& path)
      : body_(body), offset_(body_offset), encoding_(encoding), path_(path) {}

  bool read(ScalarType type, double& out) {
    if (encoding_ == Encoding::kAscii) return read_ascii(type, out);
    const size_t n = size_of(type);
    if (pos_ + n > body_.size()) return fail("the file ends inside the data (truncated)");
    // PLY's binary encodings name their byte order; swap when it is not the machine's.
    const bool swap =
        (encoding_ == Encoding::kBinaryBig) == (std::endian::native == std::endian::little);
    out = load_scalar(type, body_.data() + pos_, swap);
    pos_ += n;
    return true;
  }

  // Ascii PLY puts one record per line; a record must not run into the next line.
  bool end_record() {
    if (encoding_ != Encoding::kAscii) return true;
    while (pos_ < body_.size() &&
           (body_[pos_] == ' ' || body_[pos_] == '\t' || body_[pos_] == '\r'))
      ++pos_;
    if (pos_ < body_.size() && body_[pos_] != '\n')
      return fail("more values than the header declares");
    if (pos_ < body_.size()) ++pos_, ++line_;
    return true;
  }

  // Passes over one record without converting it: a later file's faces, which are only hashed
  // (FaceParsing::kHashOnly). Ascii: one line; binary: each property by its type.
  bool skip_record(const Element& element) {
    if (encoding_ == Encoding::kAscii) {
      if (pos_ >= body_.size()) return fail("the file ends inside the data (truncated)");
      const size_t eol = body_.find('\n', pos_);
      pos_ = eol == std::string_view::npos ? body_.size() : eol + 1;
      ++line_;
      return true;
    }
    for (const Property& property : element.properties) {
      double n = 1;
      if (property.is_list && !read(property.count_type, n)) return false;
      if (n < 0 || n > 1e6 || n != std::floor(n)) return fail("bad list length " + number_text(n));
      const size_t bytes = static_cast<size_t>(n) * size_of(property.type);
      if (bytes > body_.size() - pos_) return fail("the file ends inside the data (truncated)");
      pos_ += bytes;
    }
    return true;
  }

  size_t position() const { return pos_; }
  std::string_view bytes_from(size_t begin) const { return body_.substr(begin, pos_ - begin); }
  size_t remaining() const { return body_.size() - pos_; }
  // Where the reader is: a line for ascii, a byte offset for binary.
  uint32_t place() const {
    return encoding_ == Encoding::kAscii ? line_ : static_cast<uint32_t>(offset_ + pos_);
  }
  std::string where() const {
    return encoding_ == Encoding::kAscii ? path_ + ":" + std::to_string(line_)
                                         : path_ + ": byte " + std::to_string(offset_ + pos_);
  }
  void set_first_line(uint32_t line) { line_ = line; }
  const std::string& error() const { return error_; }

 private:
  // One token, by the rule of every text reader (text.h): a whole number; an integer property
  // takes a whole integer within its type, as its binary form could hold.
  bool read_ascii(ScalarType type, double& out) {
    while (pos_ < body_.size() &&
           (body_[pos_] == ' ' || body_[pos_] == '\t' || body_[pos_] == '\r'))
      ++pos_;
    if (pos_ >= body_.size()) return fail("the file ends inside the data (truncated)");
    if (body_[pos_] == '\n') return fail("fewer values on this line than the header declares");
    size_t stop = pos_;
    while (stop < body_.size() && body_[stop] != ' ' && body_[stop] != '\t' &&
           body_[stop] != '\r' && body_[stop] != '\n')
      ++stop;
    const std::string_view token = body_.substr(pos_, stop - pos_);
    const NumberError e = parse_scalar(token, type, out);
    if (e == NumberError::kNotANumber)
      return fail(quoted_bytes(token) + " is not " + number_kind(type));
    if (e == NumberError::kOutOfRange)
      return fail(quoted_bytes(token) + " is out of the range of its type " + type_name(type));
    pos_ = stop;
    return true;
  }
  bool fail(const std::string& cause) {
    error_ = where() + ": " + cause;
    return false;
  }

  std::string_view body_;
  size_t offset_;
  size_t pos_ = 0;
  uint32_t line_ = 1;
  Encoding encoding_;
  const std::string& path_;
  std::string error_;
};

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  size_t body_offset = 0;
  uint32_t body_line = 1;
  std::optional<double> time;
};

Result<Header> parse_header(std::string_view bytes, const std::string& path) {
  Header header;
  size_t pos = 0;
  uint32_t line = 0;
  bool saw_format = false;
  while (true) {
    const size_t eol = bytes.find('\n', pos);
    ++line;
    if (eol == std::string_view::npos)
      return Status::error(path + ":" + std::to_string(line) +
                           ": the header never ends (no end_header line)");
    std::string_view text = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    const std::string where = path + ":" + std::to_string(line);

    std::vector<std::string_view> words;
    for (size_t i = 0; i < text.size();) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      const size_t start = i;
      while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
      if (i > start) words.push_back(text.substr(start, i - start));
    }
    if (line == 1) {
      if (words.size() != 1 || words[0] != "ply")
        return Status::error(where + ": not a PLY file (it must start with 'ply')");
      continue;
    }
    if (words.empty()) continue;
    if (words[0] == "comment" || words[0] == "obj_info") {
      if (!header.time) {
        auto time = time_from_comment(text);
        if (!time) return Status::error(where + ": " + time.message());
        header.time = *time;
      }
    } else if (words[0] == "format") {
      if (words.size() < 2) return Status::error(where + ": 'format' without an encoding");
      if (words[1] == "ascii")
        header.encoding = Encoding::kAscii;
      else if (words[1] == "binary_little_endian")
        header.encoding = Encoding::kBinaryLittle;
      else if (words[1] == "binary_big_endian")
        header.encoding = Encoding::kBinaryBig;
      else
        return Status::error(where + ": unknown PLY format " + quoted_bytes(words[1]));
      saw_format = true;
    } else if (words[0] == "element") {
      uint64_t count = 0;
      if (words.size() != 3) return Status::error(where + ": expected 'element <name> <count>'");
      const NumberError e = parse_count(words[2], count);
      if (e != NumberError::kNone)
        return Status::error(
            where + ": the count of element " + quoted_bytes(words[1]) + ", " +
            quoted_bytes(words[2]) +
            (e == NumberError::kOutOfRange ? ", is out of range" : ", is not a whole number"));
      header.elements.push_back({std::string(words[1]), count, {}});
    } else if (words[0] == "property") {
      if (header.elements.empty())
        return Status::error(where + ": 'property' before any 'element'");
      Property property;
      if (words.size() == 5 && words[1] == "list") {
        auto count_type = scalar_type(words[2]);
        auto item_type = scalar_type(words[3]);
        if (!count_type || !item_type)
          return Status::error(where + ": unknown property type in a list");
        property = {std::string(words[4]), *item_type, true, *count_type};
      } else if (words.size() == 3) {
        auto type = scalar_type(words[1]);
        if (!type)
          return Status::error(where + ": unknown property type " + quoted_bytes(words[1]));
        property = {std::string(words[2]), *type, false, ScalarType::kUInt8};
      } else {
        return Status::error(where +
                             ": expected 'property <type> <name>' or "
                             "'property list <count type> <item type> <name>'");
      }
      header.elements.back().properties.push_back(property);
    } else if (words[0] == "end_header") {
      break;
    } else {
      return Status::error(where + ": unknown header line " + quoted_bytes(text));
    }
  }
  if (!saw_format) return Status::error(path + ": the header has no 'format' line");
  header.body_offset = pos;
  header.body_line = line + 1;
  return header;
}

int find_property(const Element& e, std::string_view name) {
  for (size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == name) return static_cast<int>(i);
  return -1;
}

// ---------------------------------------------------------------------------------------------
// parse_ply()'s phases

// Every record takes at least one byte per property (two in ascii: value and separator), so a
// count the remaining bytes cannot hold is refused before anything is allocated.
Status check_count(const Element& e, Encoding encoding, const BodyReader& reader,
                   const std::string& path) {
  size_t min_record = 0;
  for (const Property& p : e.properties)
    min_record += encoding == Encoding::kAscii ? 2 : size_of(p.is_list ? p.count_type : p.type);
  if (min_record > 0 && e.count > reader.remaining() / min_record)
    return Status::error(path + ": element " + quoted_bytes(e.name) + " claims " +
                         std::to_string(e.count) + " records, more than the " +
                         std::to_string(reader.remaining()) + " bytes left can hold");
  return {};
}

// The properties of an element that dynpm reads (-1 where absent): x, y, z and node_id of the
// vertex element; the corner list, part_id and element_id of the face element.
struct Roles {
  bool is_vertex = false, is_face = false;
  int x = -1, y = -1, z = -1, node = -1, list = -1, part = -1, elem = -1;
};

// The element's roles, its count checked, and the mesh made ready for its records.
Result<Roles> prepare_element(const Element& element, Encoding encoding, const BodyReader& reader,
                              const std::string& path, bool& have_vertices, bool& have_faces,
                              ParsedMesh& mesh) {
  Roles r;
  r.is_vertex = element.name == "vertex";
  r.is_face = element.name == "face";
  if (r.is_vertex) {
    if (have_vertices) return Status::error(path + ": two 'vertex' elements");
    r.x = find_property(element, "x"), r.y = find_property(element, "y"),
    r.z = find_property(element, "z");
    r.node = find_property(element, "node_id");
    if (r.x < 0 || r.y < 0 || r.z < 0)
      return Status::error(path + ": the vertex element lacks x, y or z");
    DYNPM_RETURN_IF_ERROR(check_count(element, encoding, reader, path));
    if (element.count >= kNoVertex)
      return Status::error(path + ": too many vertices (" + std::to_string(element.count) + ")");
    mesh.positions.resize(element.count * 3);
    mesh.topology = Topology::with_vertices(static_cast<uint32_t>(element.count));
    have_vertices = true;
  } else if (r.is_face) {
    if (have_faces) return Status::error(path + ": two 'face' elements");
    r.list = find_property(element, "vertex_indices");
    if (r.list < 0) r.list = find_property(element, "vertex_index");
    if (r.list < 0 || !element.properties[r.list].is_list)
      return Status::error(path + ": the face element lacks a vertex_indices list");
    DYNPM_RETURN_IF_ERROR(check_count(element, encoding, reader, path));
    r.part = find_property(element, "part_id");
    r.elem = find_property(element, "element_id");
    have_faces = true;
  } else {
    DYNPM_RETURN_IF_ERROR(check_count(element, encoding, reader, path));
  }
  return r;
}

// The element's records in file order: vertices' positions and node numbers, faces with their
// parts and element numbers; every other property read by its type and dropped.
Status read_records(const Element& element, const Roles& roles, bool have_vertices,
                    const std::string& path, const ReadOptions& options, BodyReader& reader,
                    ParsedMesh& mesh, size_t& split_count) {
  std::vector<uint32_t> corners;
  for (uint64_t r = 0; r < element.count; ++r) {
    const uint32_t place = reader.place();
    int32_t part_id = 0;
    int64_t element_id = 0;
    corners.clear();
    for (int pi = 0; pi < static_cast<int>(element.properties.size()); ++pi) {
      const Property& property = element.properties[pi];
      double value = 0;
      if (property.is_list) {
        double n = 0;
        if (!reader.read(property.count_type, n)) return Status::error(reader.error());
        if (n < 0 || n > 1e6 || n != std::floor(n))
          return Status::error(reader.where() + ": bad list length " + number_text(n));
        for (int k = 0; k < static_cast<int>(n); ++k) {
          if (!reader.read(property.type, value)) return Status::error(reader.error());
          if (pi == roles.list) {
            if (value < 0 || value != std::floor(value) || value >= mesh.topology.vertex_count)
              return Status::error(reader.where() + ": face index " + number_text(value) +
                                   " is not a vertex (there are " +
                                   std::to_string(mesh.topology.vertex_count) + ")");
            corners.push_back(static_cast<uint32_t>(value));
          }
        }
        continue;
      }
      if (!reader.read(property.type, value)) return Status::error(reader.error());
      // Ids are integers: an ascii value out of their range would not convert.
      const bool is_id = (roles.is_vertex && pi == roles.node) ||
                         (roles.is_face && (pi == roles.part || pi == roles.elem));
      if (is_id && !(value >= -9.2e18 && value <= 9.2e18 &&
                     (pi != roles.part || (value >= INT32_MIN && value <= INT32_MAX))))
        return Status::error(reader.where() + ": " + (roles.is_vertex ? "vertex " : "face ") +
                             std::to_string(r) + ": id " + number_text(value) + " is out of range");
      if (roles.is_vertex) {
        if (pi == roles.x) mesh.positions[r * 3 + 0] = static_cast<float>(value);
        if (pi == roles.y) mesh.positions[r * 3 + 1] = static_cast<float>(value);
        if (pi == roles.z) mesh.positions[r * 3 + 2] = static_cast<float>(value);
        if (pi == roles.node) mesh.topology.node_ids[r] = static_cast<int64_t>(value);
      } else if (roles.is_face) {
        if (pi == roles.part) part_id = static_cast<int32_t>(value);
        if (pi == roles.elem) element_id = static_cast<int64_t>(value);
      }
    }
    if (roles.is_face) {
      if (!have_vertices) return Status::error(path + ": faces come before the vertex element");
      DYNPM_RETURN_IF_ERROR(add_polygon(corners, part_id, element_id, place, reader.where(),
                                        options, mesh, split_count));
    }
    if (!reader.end_record()) return Status::error(reader.error());
  }
  return {};
}

}  // namespace

Result<ParsedMesh> parse_ply(std::string_view bytes, const std::string& path,
                             const ReadOptions& options, FaceParsing faces) {
  // 1. The header: the encoding, the elements with their properties, a time note.
  auto header = parse_header(bytes, path);
  if (!header) return header.status();
  BodyReader reader(bytes.substr(header->body_offset), header->body_offset, header->encoding, path);
  reader.set_first_line(header->body_line);
  ParsedMesh mesh;
  mesh.places_are_lines = header->encoding == Encoding::kAscii;
  mesh.time = header->time;
  // 2. The elements in file order: the vertex element, the face element (its records' bytes
  //    hashed, and parsed unless only hashed), any other one skipped.
  const bool parse_faces = faces == FaceParsing::kParse;
  bool have_vertices = false, have_faces = false;
  size_t split_count = 0;
  for (const Element& element : header->elements) {
    auto roles =
        prepare_element(element, header->encoding, reader, path, have_vertices, have_faces, mesh);
    if (!roles) return roles.status();
    const size_t begin = reader.position();
    if (roles->is_face && !parse_faces) {
      for (uint64_t r = 0; r < element.count; ++r)
        if (!reader.skip_record(element)) return Status::error(reader.error());
    } else {
      if (roles->is_face) mesh.topology.reserve_faces(element.count);
      DYNPM_RETURN_IF_ERROR(
          read_records(element, *roles, have_vertices, path, options, reader, mesh, split_count));
    }
    if (roles->is_face) {
      ByteHash hash;
      hash.add(reader.bytes_from(begin));
      mesh.faces_hash = hash.value();
    }
  }
  // 3. A mesh needs both.
  if (!have_vertices || mesh.topology.vertex_count == 0)
    return Status::error(path + ": no vertices");
  if (!have_faces || (parse_faces && mesh.topology.faces.empty()))
    return Status::error(path + ": no faces");
  if (split_count && options.warn)
    options.warn(path + ": " + std::to_string(split_count) +
                 " faces with more than 4 corners split into triangle fans");
  return mesh;
}

namespace {

template <class T>
void append_little(std::string& out, T value) {
  append_binary(out, value, std::endian::little);
}

bool fits_int32(std::span<const int64_t> ids) {
  return std::all_of(ids.begin(), ids.end(),
                     [](int64_t v) { return v >= INT32_MIN && v <= INT32_MAX; });
}

}  // namespace

std::string write_ply(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options, std::span<const NamedValues> point_fields,
                      std::span<const NamedValues> cell_fields) {
  const bool node_int = fits_int32(topology.node_ids);
  const bool element_int = fits_int32(topology.element_ids);
  std::string out = "ply\nformat ";
  out += options.binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  if (!options.comment.empty()) out += "comment " + options.comment + "\n";
  out += "element vertex " + std::to_string(topology.vertex_count) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  out += node_int ? "property int node_id\n" : "property double node_id\n";
  for (const NamedValues& field : point_fields)
    out += "property float " + safe_field_name(field.name) + "\n";
  out += "element face " + std::to_string(topology.faces.size()) + "\n";
  out += "property list uchar int vertex_indices\nproperty int part_id\n";
  out += element_int ? "property int element_id\n" : "property double element_id\n";
  for (const NamedValues& field : cell_fields)
    out += "property float " + safe_field_name(field.name) + "\n";
  out += "end_header\n";

  char buffer[32];
  auto text = [&](auto value, char after) {
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, end);
    out += after;
  };
  for (uint32_t v = 0; v < topology.vertex_count; ++v) {
    const float* p = &positions[size_t{v} * 3];
    const int64_t id = topology.node_ids[v];
    if (options.binary) {
      for (int k = 0; k < 3; ++k) append_little(out, p[k]);
      node_int ? append_little(out, static_cast<int32_t>(id))
               : append_little(out, static_cast<double>(id));
      for (const NamedValues& field : point_fields) append_little(out, field.values[v]);
    } else {
      for (int k = 0; k < 3; ++k) text(p[k], ' ');
      text(id, point_fields.empty() ? '\n' : ' ');
      for (size_t i = 0; i < point_fields.size(); ++i)
        text(point_fields[i].values[v], i + 1 == point_fields.size() ? '\n' : ' ');
    }
  }
  for (size_t fi = 0; fi < topology.faces.size(); ++fi) {
    const Face& f = topology.faces[fi];
    const int degree = f.degree();
    const int64_t id = topology.element_ids[fi];
    if (options.binary) {
      append_little(out, static_cast<uint8_t>(degree));
      for (int i = 0; i < degree; ++i) append_little(out, static_cast<int32_t>(f.v[i]));
      append_little(out, topology.part_ids[fi]);
      element_int ? append_little(out, static_cast<int32_t>(id))
                  : append_little(out, static_cast<double>(id));
      for (const NamedValues& field : cell_fields) append_little(out, field.values[fi]);
    } else {
      text(degree, ' ');
      for (int i = 0; i < degree; ++i) text(f.v[i], ' ');
      text(topology.part_ids[fi], ' ');
      text(id, cell_fields.empty() ? '\n' : ' ');
      for (size_t i = 0; i < cell_fields.size(); ++i)
        text(cell_fields[i].values[fi], i + 1 == cell_fields.size() ? '\n' : ' ');
    }
  }
  return out;
}

}  // namespace dynpm::io
