// Legacy VTK files (file versions 2.0 to 5.1), ascii or binary — binary data big-endian, as the
// format says. Datasets POLYDATA (POLYGONS, TRIANGLE_STRIPS; VERTICES and LINES skipped) and
// UNSTRUCTURED_GRID (CELLS + CELL_TYPES), with the cell lists of both generations: "n size" with
// a count before each cell's points (≤ 4.2), or OFFSETS + CONNECTIVITY arrays (5.x). Every
// attribute (SCALARS, VECTORS, FIELD arrays, …) is read; vtk_read.h says which ones are kept.
// Counts are checked against the bytes left before anything is allocated.
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "scalar_types.h"
#include "vtk_read.h"

namespace dynpm::io {
namespace {

// Legacy VTK writes its binary data big-endian.
constexpr bool kSwap = std::endian::native == std::endian::little;

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::optional<ScalarType> data_type(std::string_view name) {
  const std::string n = upper(name);
  if (n == "UNSIGNED_CHAR") return ScalarType::kUInt8;
  if (n == "CHAR" || n == "SIGNED_CHAR") return ScalarType::kInt8;
  if (n == "UNSIGNED_SHORT") return ScalarType::kUInt16;
  if (n == "SHORT") return ScalarType::kInt16;
  if (n == "UNSIGNED_INT") return ScalarType::kUInt32;
  if (n == "INT" || n == "VTKIDTYPE") return ScalarType::kInt32;  // VTK reads vtkIdType as int
  if (n == "UNSIGNED_LONG" || n == "VTKTYPEUINT64") return ScalarType::kUInt64;
  if (n == "LONG" || n == "VTKTYPEINT64") return ScalarType::kInt64;
  if (n == "FLOAT") return ScalarType::kFloat32;
  if (n == "DOUBLE") return ScalarType::kFloat64;
  return std::nullopt;
}

// VTK 5.1 writes blanks and other specials in names as %XX.
std::string unescape_name(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    int v = 0;
    if (s[i] == '%' && i + 2 < s.size() &&
        std::from_chars(s.data() + i + 1, s.data() + i + 3, v, 16).ptr == s.data() + i + 3) {
      out += static_cast<char>(v);
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

class Reader {
 public:
  Reader(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  void set_binary(bool binary) { binary_ = binary; }
  bool binary() const { return binary_; }
  size_t pos() const { return pos_; }
  uint32_t line() const { return line_; }
  // Where the reader is: a line in ascii files, a byte offset in binary ones.
  uint32_t place() const { return binary_ ? static_cast<uint32_t>(pos_) : line_; }
  std::string where() const {
    return binary_ ? path_ + ": byte " + std::to_string(pos_) : path_ + ":" + std::to_string(line_);
  }
  Status fail(const std::string& cause) const { return Status::error(where() + ": " + cause); }
  // A bad count names the line that announced it (ascii); binary files keep the byte offset.
  Status fail_at_keyword(const std::string& cause) const {
    if (binary_) return fail(cause);
    return Status::error(path_ + ":" + std::to_string(keyword_line_) + ": " + cause);
  }

  // The next line as it is (header lines), without its end; false at the end of the file.
  bool raw_line(std::string_view& out) {
    if (pos_ >= bytes_.size()) return false;
    size_t eol = bytes_.find('\n', pos_);
    if (eol == std::string_view::npos) eol = bytes_.size();
    out = bytes_.substr(pos_, eol - pos_);
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    pos_ = std::min(eol + 1, bytes_.size());
    ++line_;
    return true;
  }

  // The words of the next non-blank line, which is consumed with its end, so that binary data
  // start right after; empty at the end of the file.
  std::vector<std::string_view> words() {
    std::vector<std::string_view> out;
    skip_space();
    keyword_line_ = line_;
    while (pos_ < bytes_.size() && bytes_[pos_] != '\n') {
      // Any white space but the line end separates words (\v and \f too, or no loop advances).
      while (pos_ < bytes_.size() && bytes_[pos_] != '\n' &&
             std::isspace(static_cast<unsigned char>(bytes_[pos_])))
        ++pos_;
      const size_t start = pos_;
      while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_])))
        ++pos_;
      if (pos_ > start) out.push_back(bytes_.substr(start, pos_ - start));
    }
    if (pos_ < bytes_.size()) ++pos_, ++line_;
    return out;
  }
  uint32_t keyword_line() const { return keyword_line_; }

  // A word of the current line, without consuming it (ascii only: looks past the line end).
  std::string_view peek_word() {
    const size_t pos = pos_;
    const uint32_t line = line_;
    skip_space();
    const size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    std::string_view w = bytes_.substr(start, pos_ - start);
    pos_ = pos, line_ = line;
    return w;
  }

  // count values of the given type, appended to out as doubles.
  Status values(ScalarType type, uint64_t count, std::vector<double>& out) {
    const size_t left = bytes_.size() - pos_;
    if (binary_) {
      const size_t size = size_of(type);
      if (count > left / size)
        return fail_at_keyword(std::to_string(count) + " values announced, but only " +
                               std::to_string(left) + " bytes left (truncated file?)");
      out.reserve(out.size() + count);
      for (uint64_t i = 0; i < count; ++i, pos_ += size)
        out.push_back(load_scalar(type, bytes_.data() + pos_, kSwap));
      return {};
    }
    if (count > left / 2 + 1)
      return fail_at_keyword(std::to_string(count) + " values announced, but only " +
                             std::to_string(left) + " bytes left (truncated file?)");
    out.reserve(out.size() + count);
    for (uint64_t i = 0; i < count; ++i) {
      skip_space();
      if (pos_ >= bytes_.size())
        return fail("the file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                    " values (truncated?)");
      size_t stop = pos_;
      while (stop < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[stop])))
        ++stop;
      const std::string_view token = bytes_.substr(pos_, stop - pos_);
      // The rule of every text reader (text.h): a whole number; an integer type takes whole
      // integers within its range, as its binary form could hold.
      double v = 0;
      const NumberError e = parse_scalar(token, type, v);
      if (e != NumberError::kNone)
        return fail("value " + std::to_string(i + 1) + " of " + std::to_string(count) + ", " +
                    quoted_bytes(token) + ", " +
                    (e == NumberError::kOutOfRange ? std::string("is out of the range of its type")
                                                   : std::string("is not ") + number_kind(type)));
      pos_ = stop;
      out.push_back(v);
    }
    return {};
  }

 private:
  void skip_space() {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) {
      if (bytes_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string_view bytes_;
  const std::string& path_;
  size_t pos_ = 0;
  uint32_t line_ = 1;
  uint32_t keyword_line_ = 1;
  bool binary_ = false;
};

Result<uint64_t> count_word(Reader& r, const std::vector<std::string_view>& w, size_t i,
                            const char* what) {
  if (i >= w.size())
    return r.fail_at_keyword(std::string("expected ") + what + " after " + quoted_bytes(w[0]));
  uint64_t n = 0;
  const NumberError e = parse_count(w[i], n);
  if (e == NumberError::kOutOfRange)
    return r.fail_at_keyword(std::string(what) + " " + quoted_bytes(w[i]) + " after " +
                             quoted_bytes(w[0]) + " is out of range");
  if (e != NumberError::kNone)
    return r.fail_at_keyword(std::string("expected ") + what + " after " + quoted_bytes(w[0]) +
                             ", found " + quoted_bytes(w[i]));
  return n;
}

Result<ScalarType> type_word(Reader& r, const std::vector<std::string_view>& w, size_t i) {
  if (i >= w.size()) return r.fail_at_keyword("expected a data type after " + quoted_bytes(w[0]));
  auto t = data_type(w[i]);
  if (!t)
    return r.fail_at_keyword("unsupported data type " + quoted_bytes(w[i]) + " in " +
                             quoted_bytes(w[0]));
  return *t;
}

// A cell list: offsets (cells + 1) into the point indices.
struct CellList {
  std::vector<double> offsets{0.0};
  std::vector<double> points;
  uint32_t place = 0;
  uint64_t count() const { return offsets.size() - 1; }
};

// "NAME n size" followed by either n groups "k i1 … ik" (size numbers in all) or, in 5.x files,
// "OFFSETS type" (n values, n = cells + 1) and "CONNECTIVITY type" (size values).
Status read_cell_list(Reader& r, const std::vector<std::string_view>& w, CellList& cells) {
  auto n = count_word(r, w, 1, "a cell count");
  if (!n) return n.status();
  auto size = count_word(r, w, 2, "a size");
  if (!size) return size.status();
  cells.place = r.binary() ? static_cast<uint32_t>(r.pos()) : r.keyword_line();
  // 5.x lists start with an OFFSETS line, older ones with the first cell's count (in binary
  // files four bytes that never spell a word).
  const bool new_style = upper(r.peek_word()) == "OFFSETS";
  if (new_style) {
    auto ow = r.words();
    auto ot = type_word(r, ow, 1);
    if (!ot) return ot.status();
    cells.offsets.clear();
    DYNPM_RETURN_IF_ERROR(r.values(*ot, *n, cells.offsets));
    auto cw = r.words();
    if (cw.empty() || upper(cw[0]) != "CONNECTIVITY")
      return r.fail("expected CONNECTIVITY after the OFFSETS of " + quoted_bytes(w[0]));
    auto ct = type_word(r, cw, 1);
    if (!ct) return ct.status();
    DYNPM_RETURN_IF_ERROR(r.values(*ct, *size, cells.points));
    if (cells.offsets.empty()) cells.offsets.push_back(0);
    if (cells.offsets.front() != 0 || cells.offsets.back() != double(cells.points.size()))
      return r.fail(std::string(w[0]) + ": OFFSETS must run from 0 to the CONNECTIVITY size");
    for (size_t i = 1; i < cells.offsets.size(); ++i)
      if (!(cells.offsets[i] >= cells.offsets[i - 1]))
        return r.fail(std::string(w[0]) + ": OFFSETS decrease at cell " + std::to_string(i - 1));
    return {};
  }
  std::vector<double> flat;
  DYNPM_RETURN_IF_ERROR(r.values(ScalarType::kInt32, *size, flat));
  // Each cell takes at least its point count from the list: a larger n fails below, unreserved.
  cells.offsets.reserve(std::min<uint64_t>(*n, flat.size()) + 1);
  cells.points.reserve(flat.size());
  size_t at = 0;
  for (uint64_t c = 0; c < *n; ++c) {
    if (at >= flat.size())
      return r.fail(std::string(w[0]) + ": the list ends after " + std::to_string(c) + " of " +
                    std::to_string(*n) + " cells (size " + std::to_string(*size) + ")");
    const double k = flat[at++];
    if (!(k >= 0) || k > double(flat.size() - at))
      return r.fail(std::string(w[0]) + ": cell " + std::to_string(c) + " announces " +
                    vtk::number_text(k) + " points, more than the list holds");
    cells.points.insert(cells.points.end(), flat.begin() + at, flat.begin() + at + size_t(k));
    at += size_t(k);
    cells.offsets.push_back(double(cells.points.size()));
  }
  if (at != flat.size())
    return r.fail(std::string(w[0]) + ": the list size " + std::to_string(*size) +
                  " does not match its " + std::to_string(*n) + " cells");
  return {};
}

// ---------------------------------------------------------------------------------------------
// parse_vtk()'s phases

// The first lines: the version line, the title (which may hold a "time" note), ASCII or BINARY,
// and the DATASET line.
struct Header {
  bool binary = false;
  std::optional<double> time;
  std::string dataset;  // POLYDATA or UNSTRUCTURED_GRID
};

Result<Header> read_header(Reader& r, const std::string& path) {
  std::string_view line;
  if (!r.raw_line(line) || !line.starts_with("# vtk DataFile"))
    return Status::error(path + ":1: not a legacy VTK file (no '# vtk DataFile' line)");
  std::string_view title;
  if (!r.raw_line(title)) return r.fail("the file ends after the first line");
  if (!r.raw_line(line)) return r.fail("the file ends in the header");
  const std::string encoding = upper(std::string(line.substr(0, line.find_last_not_of(" \t") + 1)));
  if (encoding != "ASCII" && encoding != "BINARY")
    return Status::error(path + ":3: expected ASCII or BINARY, found " + quoted_bytes(line));
  Header header;
  header.binary = encoding == "BINARY";
  auto title_time = time_from_comment(title);
  if (!title_time) return Status::error(path + ":2: " + title_time.message());
  header.time = *title_time;
  const auto w = r.words();
  if (w.size() < 2 || upper(w[0]) != "DATASET")
    return r.fail("expected 'DATASET POLYDATA' or 'DATASET UNSTRUCTURED_GRID'");
  header.dataset = upper(w[1]);
  if (header.dataset != "POLYDATA" && header.dataset != "UNSTRUCTURED_GRID")
    return r.fail_at_keyword("DATASET " + quoted_bytes(w[1]) +
                             " is not a surface mesh; dynpm reads POLYDATA and UNSTRUCTURED_GRID");
  r.set_binary(header.binary);
  return header;
}

// What the sections after the header hold, as read.
struct Sections {
  std::vector<double> points;
  bool have_points = false;
  // POLYDATA numbers its cells vertices, lines, polygons, strips, whatever the file order.
  CellList poly[4];  // VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS
  CellList cells;    // UNSTRUCTURED_GRID
  std::vector<double> cell_types;
  std::vector<vtk::Array> point_arrays, cell_arrays, dataset_arrays;
  uint64_t point_data = 0, cell_data = 0;  // the counts of POINT_DATA and CELL_DATA
};

// The sections, keyword by keyword up to the end of the file: points, cells, attribute data.
Status read_sections(Reader& r, const std::string& dataset, size_t file_size, Sections& s) {
  std::vector<vtk::Array>* target = &s.dataset_arrays;
  uint64_t target_count = 0;
  std::vector<std::string_view> w;

  // An attribute array of `components` values per tuple.
  auto attribute = [&](std::string_view name, ScalarType type, uint64_t components) -> Status {
    if (target == &s.dataset_arrays) return r.fail("attribute data before POINT_DATA or CELL_DATA");
    if (components == 0 || components > 1000) return r.fail("bad component count");
    vtk::Array a;
    a.name = unescape_name(name);
    a.components = components;
    DYNPM_RETURN_IF_ERROR(r.values(type, target_count * components, a.values));
    target->push_back(std::move(a));
    return {};
  };

  while (true) {
    w = r.words();
    if (w.empty()) break;
    const std::string key = upper(w[0]);
    if (key == "METADATA") {
      // Information keys (5.x): skipped up to the blank line that ends them.
      std::string_view skip;
      while (r.raw_line(skip) && skip.find_first_not_of(" \t\r") != std::string_view::npos) {
      }
    } else if (key == "POINTS") {
      auto n = count_word(r, w, 1, "a point count");
      if (!n) return n.status();
      auto t = type_word(r, w, 2);
      if (!t) return t.status();
      if (*n > kNoVertex - 1) return r.fail("too many points");
      s.points.clear();
      DYNPM_RETURN_IF_ERROR(r.values(*t, *n * 3, s.points));
      s.have_points = true;
    } else if (dataset == "POLYDATA" && (key == "VERTICES" || key == "LINES" || key == "POLYGONS" ||
                                         key == "TRIANGLE_STRIPS")) {
      const int k = key == "VERTICES" ? 0 : key == "LINES" ? 1 : key == "POLYGONS" ? 2 : 3;
      DYNPM_RETURN_IF_ERROR(read_cell_list(r, w, s.poly[k]));
    } else if (dataset == "UNSTRUCTURED_GRID" && key == "CELLS") {
      DYNPM_RETURN_IF_ERROR(read_cell_list(r, w, s.cells));
    } else if (dataset == "UNSTRUCTURED_GRID" && key == "CELL_TYPES") {
      auto n = count_word(r, w, 1, "a cell count");
      if (!n) return n.status();
      s.cell_types.clear();
      DYNPM_RETURN_IF_ERROR(r.values(ScalarType::kInt32, *n, s.cell_types));
    } else if (key == "POINT_DATA" || key == "CELL_DATA") {
      auto n = count_word(r, w, 1, "a count");
      if (!n) return n.status();
      if (*n > file_size)
        return r.fail(key + " " + std::to_string(*n) + ": more than the file can hold");
      const bool is_point = key == "POINT_DATA";
      (is_point ? s.point_data : s.cell_data) = *n;
      target = is_point ? &s.point_arrays : &s.cell_arrays;
      target_count = *n;
    } else if (key == "SCALARS") {
      if (w.size() < 3) return r.fail("SCALARS needs a name and a data type");
      auto t = type_word(r, w, 2);
      if (!t) return t.status();
      uint64_t components = 1;
      if (w.size() > 3) {
        auto c = count_word(r, w, 3, "a component count");
        if (!c) return c.status();
        components = *c;
      }
      // LOOKUP_TABLE is required; ascii files written by hand sometimes leave it out.
      if (r.binary() || upper(r.peek_word()) == "LOOKUP_TABLE") {
        auto lw = r.words();
        if (lw.empty() || upper(lw[0]) != "LOOKUP_TABLE")
          return r.fail("expected LOOKUP_TABLE after SCALARS " + quoted_bytes(w[1]));
      }
      DYNPM_RETURN_IF_ERROR(attribute(w[1], *t, components));
    } else if (key == "VECTORS" || key == "NORMALS" || key == "TENSORS" || key == "TENSORS6" ||
               key == "GLOBAL_IDS" || key == "PEDIGREE_IDS") {
      if (w.size() < 3) return r.fail(key + " needs a name and a data type");
      auto t = type_word(r, w, 2);
      if (!t) return t.status();
      const uint64_t components = key == "TENSORS"        ? 9
                                  : key == "TENSORS6"     ? 6
                                  : key.ends_with("_IDS") ? 1
                                                          : 3;
      DYNPM_RETURN_IF_ERROR(attribute(w[1], *t, components));
    } else if (key == "TEXTURE_COORDINATES") {
      if (w.size() < 4) return r.fail("TEXTURE_COORDINATES needs a name, a dimension and a type");
      auto d = count_word(r, w, 2, "a dimension");
      if (!d) return d.status();
      auto t = type_word(r, w, 3);
      if (!t) return t.status();
      DYNPM_RETURN_IF_ERROR(attribute(w[1], *t, *d));
    } else if (key == "COLOR_SCALARS") {
      auto c = count_word(r, w, 2, "a component count");
      if (!c) return c.status();
      DYNPM_RETURN_IF_ERROR(
          attribute(w[1], r.binary() ? ScalarType::kUInt8 : ScalarType::kFloat32, *c));
    } else if (key == "LOOKUP_TABLE") {
      auto n = count_word(r, w, 2, "a table size");
      if (!n) return n.status();
      if (*n > file_size) return r.fail("a LOOKUP_TABLE larger than the file");
      std::vector<double> table;
      DYNPM_RETURN_IF_ERROR(
          r.values(r.binary() ? ScalarType::kUInt8 : ScalarType::kFloat32, *n * 4, table));
    } else if (key == "FIELD") {
      auto n = count_word(r, w, 2, "an array count");
      if (!n) return n.status();
      for (uint64_t i = 0; i < *n; ++i) {
        auto aw = r.words();
        if (!aw.empty() && upper(aw[0]) == "METADATA") {
          std::string_view skip;
          while (r.raw_line(skip) && skip.find_first_not_of(" \t\r") != std::string_view::npos) {
          }
          aw = r.words();
        }
        if (aw.size() == 1 && aw[0] == "NULL_ARRAY") continue;
        if (aw.size() < 4) return r.fail("expected 'name components tuples type' in FIELD");
        auto c = count_word(r, aw, 1, "a component count");
        if (!c) return c.status();
        auto tuples = count_word(r, aw, 2, "a tuple count");
        if (!tuples) return tuples.status();
        auto t = type_word(r, aw, 3);
        if (!t) return t.status();
        if (*c == 0 || *c > 1000) return r.fail("bad component count in FIELD array");
        if (*tuples > file_size) return r.fail("more tuples than the file can hold");
        vtk::Array a;
        a.name = unescape_name(aw[0]);
        a.components = *c;
        DYNPM_RETURN_IF_ERROR(r.values(*t, *c * *tuples, a.values));
        target->push_back(std::move(a));
      }
    } else {
      return r.fail_at_keyword("unexpected keyword " + quoted_bytes(w[0]));
    }
  }
  return {};
}

// The cells of either dataset into the sink, numbered as CELL_DATA counts them; their count.
Result<uint64_t> add_cells(const Sections& s, const std::string& dataset, const std::string& path,
                           vtk::CellSink& sink) {
  auto cell_points = [](const CellList& list, uint64_t c) {
    const size_t a = size_t(list.offsets[c]), b = size_t(list.offsets[c + 1]);
    return std::span<const double>(list.points.data() + a, b - a);
  };
  uint64_t cell_count = 0;
  if (dataset == "UNSTRUCTURED_GRID") {
    if (s.cell_types.size() != s.cells.count())
      return Status::error(path + ": CELL_TYPES lists " + std::to_string(s.cell_types.size()) +
                           " cells, CELLS " + std::to_string(s.cells.count()));
    for (uint64_t c = 0; c < s.cells.count(); ++c)
      DYNPM_RETURN_IF_ERROR(sink.add(s.cell_types[c], cell_points(s.cells, c), c, s.cells.place));
    return s.cells.count();
  }
  const int types[4] = {1, 4, 7, 6};  // vertex, polyline, polygon, triangle strip
  for (int k = 0; k < 4; ++k) {
    for (uint64_t c = 0; c < s.poly[k].count(); ++c)
      DYNPM_RETURN_IF_ERROR(
          sink.add(types[k], cell_points(s.poly[k], c), cell_count + c, s.poly[k].place));
    cell_count += s.poly[k].count();
  }
  return cell_count;
}

}  // namespace

Result<ParsedMesh> parse_vtk(std::string_view bytes, const std::string& path,
                             const ReadOptions& options) {
  Reader r(bytes, path);
  // 1. The header: version, title, encoding, dataset.
  auto header = read_header(r, path);
  if (!header) return header.status();
  ParsedMesh mesh;
  mesh.places_are_lines = !header->binary;
  mesh.time = header->time;
  // 2. The sections: points, cells, attribute data.
  Sections s;
  DYNPM_RETURN_IF_ERROR(read_sections(r, header->dataset, bytes.size(), s));
  if (!s.have_points) return Status::error(path + ": no POINTS");
  // 3. The points as positions, and the time a FIELD array may hold.
  const uint64_t n_points = s.points.size() / 3;
  mesh.topology = Topology::with_vertices(static_cast<uint32_t>(n_points));
  mesh.positions.resize(s.points.size());
  std::transform(s.points.begin(), s.points.end(), mesh.positions.begin(),
                 [](double c) { return static_cast<float>(c); });
  std::vector<double>().swap(s.points);
  for (const vtk::Array& a : s.dataset_arrays)
    if ((a.name == "TIME" || a.name == "TimeValue") && a.values.size() == 1) {
      if (!std::isfinite(a.values[0]))
        return Status::error(path + ": the FIELD array " + a.name + " holds the time " +
                             vtk::number_text(a.values[0]) + ", not a finite number");
      mesh.time = a.values[0];
    }
  // 4. The cells, as faces.
  vtk::CellSink sink(mesh, n_points, path, options);
  auto cell_count = add_cells(s, header->dataset, path, sink);
  if (!cell_count) return cell_count.status();
  sink.finish();
  // 5. Cell data (parts, element numbers) and point data (node numbers, fields).
  if (s.point_data && s.point_data != n_points)
    return Status::error(path + ": POINT_DATA " + std::to_string(s.point_data) + " but " +
                         std::to_string(n_points) + " points");
  if (s.cell_data && s.cell_data != *cell_count)
    return Status::error(path + ": CELL_DATA " + std::to_string(s.cell_data) + " but " +
                         std::to_string(*cell_count) + " cells");
  vtk::apply_point_data(s.point_arrays, path, options, mesh);
  vtk::apply_cell_data(s.cell_arrays, *cell_count, sink.cell_of_face, path, options, mesh);
  return mesh;
}

}  // namespace dynpm::io
