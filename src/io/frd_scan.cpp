// CalculiX .frd results: the one scan of the file (frd_records.h, frd::scan()). It reads the
// node and element blocks, ASCII or binary, keeps the shells, and finds where each result block's
// data start without reading them.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <span>

#include "frd_records.h"

namespace dynpm::io::frd {
namespace {

// frd element types (cgx manual, "Element Types"): node count and what dynpm makes of it.
struct ElementType {
  int nodes = 0;
  int corners = 0;  // 3 or 4 for shells, 0 for solids and beams (skipped)
  bool quadratic = false;
};

std::optional<ElementType> element_type(int64_t type) {
  switch (type) {
    case 1: return ElementType{8, 0, false};   // he8  (C3D8)
    case 2: return ElementType{6, 0, false};   // pe6  (C3D6)
    case 3: return ElementType{4, 0, false};   // te4  (C3D4)
    case 4: return ElementType{20, 0, false};  // he20 (C3D20, and shells expanded by ccx)
    case 5: return ElementType{15, 0, false};  // pe15 (C3D15)
    case 6: return ElementType{10, 0, false};  // te10 (C3D10)
    case 7: return ElementType{3, 3, false};   // tr3  (S3)
    case 8: return ElementType{6, 3, true};    // tr6  (S6), corners first
    case 9: return ElementType{4, 4, false};   // qu4  (S4, S4R)
    case 10: return ElementType{8, 4, true};   // qu8  (S8, S8R), corners first
    case 11: return ElementType{2, 0, false};  // be2  (B31)
    case 12: return ElementType{3, 0, false};  // be3  (B32)
    default: return std::nullopt;
  }
}

// ---------------------------------------------------------------------------------------------
// The scan

// Fills the Layout it extends, block by block.
class FrdScanner : public Layout {
 public:
  explicit FrdScanner(const std::string& path) : path_(path) {}

  Status scan() {
    DYNPM_RETURN_IF_ERROR(reader_.open(path_));
    char magic[2] = {0, 0};
    if (reader_.size() >= 2 && reader_.read(magic, 2) && magic[0] == '\x1f' && magic[1] == '\x8b')
      return Status::error(path_ + ": is gzip-compressed; gunzip it first");
    reader_.seek(0, 1);

    std::string_view line;
    while (!ended && next(line)) {
      if (trim_blanks(line).empty()) continue;
      const auto key = to_int(columns(line, 0, 5));
      const char code = line.size() > 5 ? line[5] : ' ';
      if (!key) return fail("not a CalculiX .frd record (expected a block key such as '    2C')");
      if (*key == 9999) {
        ended = true;
      } else if (*key == 1) {
        continue;  // 1C model header, 1U user header, 1P parameter lines
      } else if (*key == 2 && code == 'C') {
        if (saw_nodes_) return fail("a second node block (2C); one mesh per file is supported");
        saw_nodes_ = true;
        DYNPM_RETURN_IF_ERROR(read_nodes(line));
      } else if (*key == 3 && code == 'C') {
        if (saw_elements_)
          return fail("a second element block (3C); one mesh per file is supported");
        saw_elements_ = true;
        DYNPM_RETURN_IF_ERROR(read_elements(line));
      } else if (*key == 100 && code == 'C') {
        if (!saw_nodes_) return fail("a result block (100C) before the node block (2C)");
        DYNPM_RETURN_IF_ERROR(scan_result(line));
      } else {
        return fail("unexpected record outside any block");
      }
    }
    if (!saw_nodes_)
      return Status::error(path_ + ": no node block (2C); is this a CalculiX .frd file?");
    if (!saw_elements_) return Status::error(path_ + ": no element block (3C)");
    return {};
  }

 private:
  bool next(std::string_view& line) {
    line_offset_ = reader_.offset();
    return reader_.next_line(line);
  }
  // "path:line" while the file is all text; "path: byte N" once binary records have appeared,
  // since line numbers mean nothing after them.
  std::string where() const {
    if (binary) return path_ + ": byte " + std::to_string(line_offset_);
    return path_ + ":" + std::to_string(reader_.line() - 1);
  }
  Status fail(const std::string& cause) const { return Status::error(where() + ": " + cause); }
  Status fail_at_byte(uint64_t offset, const std::string& cause) const {
    return Status::error(path_ + ": byte " + std::to_string(offset) + ": " + cause);
  }
  // Placed where the file ends: after its last line, or at its size once binary records have
  // appeared.
  Status truncated(const std::string& what) const {
    std::string end = binary ? ": byte " : ":";  // appended, not "literal" + string: gcc 12
    end += binary ? std::to_string(reader_.size()) : std::to_string(reader_.line() - 1);
    return Status::error(path_ + end + ": the file ends inside " + what + " (truncated?)");
  }

  // Format flag and record count of a 2C / 3C header: (1X,'   2','C',18X,I12,37X,I1).
  Status block_header(std::string_view line, const char* what, int max_format, int& format,
                      uint64_t& count) {
    const auto n = to_int(columns(line, 24, 36));
    const auto f = to_int(columns(line, 36, line.size()));
    if (!n && !trim_blanks(columns(line, 24, 36)).empty())
      return fail(std::string("the record count of the ") + what + " header, " +
                  quoted_bytes(trim_blanks(columns(line, 24, 36))) + ", is not a whole number");
    if (n && *n < 0) return fail(std::string("negative record count in the ") + what + " header");
    count = n ? static_cast<uint64_t>(*n) : 0;
    if (!f && line.size() > 36)
      return fail(std::string("cannot read the format flag of the ") + what + " header");
    if (f && (*f < 0 || *f > max_format))
      return fail("unknown format flag " + std::to_string(*f) + " in the " + what + " header");
    format = f ? static_cast<int>(*f) : 0;
    return {};
  }

  // A count from a header must fit in the bytes left, each record taking at least min_bytes.
  Status check_count(uint64_t count, uint64_t min_bytes, const char* what) const {
    if (count > reader_.left() / min_bytes)
      return fail("the header announces " + std::to_string(count) + " " + what + ", more than " +
                  std::to_string(reader_.left()) + " bytes left in the file can hold");
    return {};
  }

  Status read_nodes(std::string_view header) {
    int format = 0;
    uint64_t count = 0;
    DYNPM_RETURN_IF_ERROR(block_header(header, "node block (2C)", 3, format, count));
    if (format >= 2) {
      binary = true;
      const size_t real = format == 2 ? 4 : 8;
      const size_t record = 4 + 3 * real;
      DYNPM_RETURN_IF_ERROR(check_count(count, record, "nodes"));
      nodes.resize(count);
      char b[28];
      for (NodeRecord& node : nodes) {
        if (!reader_.read(b, record)) return truncated("the node block");
        node.id = from_native<int32_t>(b);
        for (int k = 0; k < 3; ++k)
          node.xyz[k] =
              real == 4 ? from_native<float>(b + 4 + 4 * k) : from_native<double>(b + 4 + 8 * k);
      }
      return {};
    }
    const size_t width = format == 1 ? 10 : 5;
    DYNPM_RETURN_IF_ERROR(check_count(count, 3 + width + 36, "nodes"));
    nodes.reserve(count);
    std::string_view line;
    while (true) {
      if (!next(line)) return truncated("the node block (no ' -3' line)");
      const int key = record_key(line);
      if (key == 3) break;
      if (key != 1) return fail("expected a ' -1' node record or the ' -3' end of the node block");
      NodeRecord node;
      const auto id = to_int(columns(line, 3, 3 + width));
      if (!id) return fail("cannot read the node number");
      node.id = *id;
      for (int k = 0; k < 3; ++k) {
        const size_t a = 3 + width + 12 * size_t(k);
        const auto v = to_real(columns(line, a, a + 12));
        if (!v)
          return fail("cannot read coordinate " + std::to_string(k + 1) + " of node " +
                      std::to_string(node.id));
        node.xyz[k] = *v;
      }
      nodes.push_back(node);
    }
    return {};
  }

  // Adds an element of the given type if it is a shell; counts the others.
  Status add_element(int64_t id, int64_t type, int64_t group, int64_t material,
                     std::span<const int64_t> node_ids, uint64_t place) {
    const auto t = element_type(type);
    assert(t);
    if (t->corners == 0) {
      ++skipped_elements;
      return {};
    }
    if (t->quadratic) ++quadratic_elements;
    ElementRecord e;
    e.id = id;
    // ccx writes group 0 and the material number (1, 2, … in the order of the 1UMAT lines);
    // other writers may fill the group: it is the part when it is set.
    const int64_t part = group != 0 ? group : material;
    if (part < INT32_MIN || part > INT32_MAX)
      return fail("element " + std::to_string(id) + ": group/material number out of range");
    e.part = static_cast<int32_t>(part);
    e.corners = static_cast<uint8_t>(t->corners);
    std::copy_n(node_ids.begin(), t->corners, e.nodes);
    e.place = place;
    elements.push_back(e);
    return {};
  }

  Status read_elements(std::string_view header) {
    int format = 0;
    uint64_t count = 0;
    DYNPM_RETURN_IF_ERROR(block_header(header, "element block (3C)", 2, format, count));
    int64_t node_ids[20];
    if (format == 2) {
      binary = true;
      DYNPM_RETURN_IF_ERROR(check_count(count, 4 * 6, "elements"));
      elements.reserve(count);
      char b[4 * 24];
      for (uint64_t i = 0; i < count; ++i) {
        const uint64_t place = reader_.offset();
        if (!reader_.read(b, 16)) return truncated("the element block");
        const int32_t id = from_native<int32_t>(b);
        const int32_t type = from_native<int32_t>(b + 4);
        const auto t = element_type(type);
        if (!t)
          return fail_at_byte(place, "element " + std::to_string(id) +
                                         " has the unknown frd type " + std::to_string(type));
        if (!reader_.read(b + 16, 4 * size_t(t->nodes))) return truncated("the element block");
        for (int k = 0; k < t->nodes; ++k) node_ids[k] = from_native<int32_t>(b + 16 + 4 * k);
        DYNPM_RETURN_IF_ERROR(add_element(id, type, from_native<int32_t>(b + 8),
                                          from_native<int32_t>(b + 12),
                                          std::span(node_ids, size_t(t->nodes)), place));
      }
      return {};
    }
    const size_t width = format == 1 ? 10 : 5;
    const size_t per_line = format == 1 ? 10 : 15;
    // The smallest element record is a triangle: its " -1" line and one " -2" line of 3 nodes.
    DYNPM_RETURN_IF_ERROR(
        check_count(count, (3 + width + 15 + 1) + (3 + 3 * width + 1), "elements"));
    elements.reserve(count);
    std::string_view line;
    while (true) {
      if (!next(line)) return truncated("the element block (no ' -3' line)");
      const int key = record_key(line);
      if (key == 3) break;
      if (key != 1)
        return fail("expected a ' -1' element record or the ' -3' end of the element block");
      const uint64_t place = reader_.line() - 1;
      const auto id = to_int(columns(line, 3, 3 + width));
      const auto type = to_int(columns(line, 3 + width, 8 + width));
      const auto group = to_int(columns(line, 8 + width, 13 + width));
      const auto material = to_int(columns(line, 13 + width, 18 + width));
      if (!id || !type) return fail("cannot read the element number and type");
      const auto t = element_type(*type);
      if (!t)
        return fail("element " + std::to_string(*id) + " has the unknown frd type " +
                    std::to_string(*type));
      int have = 0;
      while (have < t->nodes) {
        if (!next(line)) return truncated("the node list of element " + std::to_string(*id));
        if (record_key(line) != 2)
          return fail("expected the ' -2' node list of element " + std::to_string(*id) + " (" +
                      std::to_string(t->nodes) + " nodes)");
        size_t on_line = 0;
        for (size_t a = 3; a < line.size() && on_line < per_line && have < t->nodes;
             a += width, ++on_line) {
          const auto n = to_int(columns(line, a, a + width));
          if (!n) return fail("cannot read a node number of element " + std::to_string(*id));
          node_ids[have++] = *n;
        }
        if (on_line == 0) return fail("an empty ' -2' node list line");
      }
      DYNPM_RETURN_IF_ERROR(add_element(*id, *type, group.value_or(0), material.value_or(0),
                                        std::span(node_ids, size_t(t->nodes)), place));
    }
    return {};
  }

  size_t field_index(const std::string& name) {
    auto it = std::find(field_names.begin(), field_names.end(), name);
    if (it != field_names.end()) return static_cast<size_t>(it - field_names.begin());
    field_names.push_back(name);
    return field_names.size() - 1;
  }

  // A 100C block: (1X,' 100','C',6A1,E12.5,I12,20A1,I2,I5,10A1,I2), then " -4" (name, number
  // of components), one " -5" line per component, the data records. Only where the data start
  // is kept; ASCII data are skipped line by line, binary data by their size.
  Status scan_result(std::string_view header) {
    ResultBlock block;
    block.value_text = std::string(trim_blanks(columns(header, 12, 24)));
    const auto time = to_real(block.value_text);
    if (!time)
      return fail("cannot read the step time " + quoted_bytes(block.value_text) +
                  " (columns 13-24 of the 100C line)");
    if (!std::isfinite(*time))
      return fail("the step time " + quoted_bytes(block.value_text) +
                  " (columns 13-24 of the 100C line) is not a finite number");
    block.time = *time;
    // Integer fields: blank means not given; anything else must be a whole number.
    auto field = [&](size_t a, size_t b, const char* what) -> Result<int64_t> {
      const std::string_view text = trim_blanks(columns(header, a, b));
      if (text.empty()) return int64_t{0};
      const auto v = to_int(text);
      if (!v)
        return fail(std::string("the ") + what + " of the 100C line, " + quoted_bytes(text) +
                    ", is not a whole number");
      return *v;
    };
    const auto n = field(24, 36, "node count");
    if (!n) return n.status();
    if (*n < 0) return fail("negative node count in the 100C line");
    block.node_count = static_cast<uint64_t>(*n);
    const auto step_number = field(58, 63, "step number");
    if (!step_number) return step_number.status();
    block.step_number = *step_number;
    const auto format = field(73, header.size(), "format flag");
    if (!format) return format.status();
    if (*format < 0 || *format > 3)
      return fail("unknown format flag " + std::to_string(*format) + " in the 100C line");
    block.format = static_cast<int>(*format);
    if (block.format >= 2 && header.size() < 74)
      return fail("a binary block without a format flag");
    if (block.format >= 2) binary = true;

    std::string_view line;
    // " -4" record: (1X,I2,2X,8A1,2I5)
    do {
      if (!next(line)) return truncated("a result block header");
    } while (record_key(line) == 0 && trim_blanks(line).empty());
    if (record_key(line) != 4) return fail("expected the ' -4' record after a 100C line");
    // Shown in messages and used as a field name: only printable characters.
    const std::string name = printable(trim_blanks(columns(line, 5, 13)));
    const auto components = to_int(columns(line, 13, 18));
    if (!components || *components < 1 || *components > 1000)
      return fail("cannot read the component count of result block " + name);
    // " -5" records, one per component: (1X,I2,2X,8A1,5I5,8A1); IEXIST = 1 marks a component
    // the reader computes (DISP's "ALL"), which has no value in the data records.
    uint32_t stored = 0;
    for (int64_t c = 0; c < *components;) {
      if (!next(line)) return truncated("the components of result block " + name);
      const int key = record_key(line);
      if (key == 6 && block.format < 2) continue;  // " -6": predefined calculations (unused)
      if (key != 5)
        return fail("expected " + std::to_string(*components) + " ' -5' component records in " +
                    "result block " + name);
      if (to_int(columns(line, 33, 38)).value_or(0) != 1) ++stored;
      ++c;
    }
    if (stored == 0) return fail("result block " + name + " has no stored component");
    block.values = stored;
    block.data_offset = reader_.offset();
    block.data_line = reader_.line();

    if (name == "DISP") {
      if (stored < 3) return fail("result block DISP has fewer than 3 components");
      block.kind = BlockKind::kDisp;
    } else if (name == "STRESS" && stored >= 6) {
      block.kind = BlockKind::kStress;
      block.field = field_index("S_MISES");
    } else if (stored == 1) {
      block.kind = BlockKind::kScalar;
      block.field = field_index(name == "PE" ? "PEEQ" : name);
    } else {
      ignored_blocks.insert(name);
    }
    const bool keep = block.kind == BlockKind::kDisp || !ignored_blocks.count(name);

    if (block.format >= 2) {
      const uint64_t record = 4 + uint64_t{stored} * (block.format == 2 ? 4 : 8);
      if (block.node_count > reader_.left() / record)
        return fail("result block " + name + " announces " + std::to_string(block.node_count) +
                    " nodes, more than the " + std::to_string(reader_.left()) +
                    " bytes left in the file can hold");
      reader_.skip(block.node_count * record);
    } else {
      while (true) {
        if (!next(line)) return truncated("result block " + name + " (no ' -3' line)");
        if (record_key(line) == 3) break;
      }
    }
    if (keep) blocks.push_back(std::move(block));
    return {};
  }

  const std::string& path_;
  ChunkReader reader_;
  uint64_t line_offset_ = 0;
  bool saw_nodes_ = false, saw_elements_ = false;
};

}  // namespace

Result<Layout> scan(const std::string& path) {
  FrdScanner scanner(path);
  DYNPM_RETURN_IF_ERROR(scanner.scan());
  return Layout(std::move(scanner));
}

}  // namespace dynpm::io::frd
