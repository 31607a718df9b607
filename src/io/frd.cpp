// CalculiX .frd results ("Result Format" in the cgx manual): a node block (2C), an element block
// (3C) and nodal result blocks (100C), each either ASCII fixed-column records or, when the
// block header's format flag says so, raw native-endian binary records without the closing
// " -3" line (what ccx writes for *NODE OUTPUT / *ELEMENT OUTPUT).
//
// open_frd() reads the mesh and scans the rest of the file once, keeping only where each DISP
// block (and each result-field block) starts; read_step(t) / read_field() seek there and parse
// that one block, so a result much larger than memory can be streamed.
//
//   step 0        the undeformed node coordinates, time 0 (as our OBJ sequences' frame_000)
//   step k ≥ 1    coordinates + the k-th DISP block, time = the block's 100C value
//   fields        STRESS → "S_MISES" (von Mises), PE → "PEEQ", any other one-component block
//                 by its name; zeros at step 0 and where a step has no such block
//
// Here: open_frd()'s phases and the step reader. The scan is frd_scan.cpp; what both share (the
// chunked file, the fixed-column fields, the layout the scan finds) is frd_records.h.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <span>

#include "frd_records.h"

namespace dynpm::io {
namespace {

using namespace frd;

struct Step {
  double time = 0;
  ResultBlock disp;
  std::vector<int64_t> field_block;  // per field, index into FrdLayout::blocks or -1
};

// Node number → position in an ascending list of node numbers: a table when the numbers are
// dense enough (ccx numbers from 1), else a binary search.
class NodeLookup {
 public:
  explicit NodeLookup(std::span<const int64_t> ids) : ids_(ids) {
    if (!ids.empty() && ids.back() - ids.front() < int64_t(ids.size()) * 8 + 1024) {
      first_ = ids.front();
      table_.assign(size_t(ids.back() - first_ + 1), kNoIndex);
      for (size_t k = 0; k < ids.size(); ++k) table_[size_t(ids[k] - first_)] = uint32_t(k);
    }
  }

  // kNoIndex for a number not in the list.
  uint32_t find(int64_t id) const {
    if (!table_.empty()) {
      if (id < first_ || id - first_ >= int64_t(table_.size())) return kNoIndex;
      return table_[size_t(id - first_)];
    }
    auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
    return it != ids_.end() && *it == id ? uint32_t(it - ids_.begin()) : kNoIndex;
  }

 private:
  std::span<const int64_t> ids_;
  std::vector<uint32_t> table_;
  int64_t first_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The FrameSource: the mesh in memory, the steps on disk

class FrdSource final : public FrameSource {
 public:
  FrdSource(std::string path, std::vector<int64_t> node_ids, std::vector<double> base,
            std::vector<Step> steps, std::vector<ResultBlock> field_blocks,
            std::vector<std::string> field_names)
      : path_(std::move(path)),
        node_ids_(std::move(node_ids)),
        base_(std::move(base)),
        steps_(std::move(steps)),
        field_blocks_(std::move(field_blocks)),
        field_names_(std::move(field_names)),
        vertex_of_(node_ids_) {}

  uint32_t vertex_count() const override { return uint32_t(node_ids_.size()); }
  size_t step_count() const override { return steps_.size() + 1; }
  double step_time(size_t t) const override { return t == 0 ? 0.0 : steps_[t - 1].time; }
  bool parallel_reads() const override { return true; }  // each read opens the file anew
  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> infos;
    for (const std::string& name : field_names_) infos.push_back({name, FieldLocation::kNode, {}});
    return infos;
  }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < step_count() && out.size() == base_.size());
    if (t == 0) {
      std::transform(base_.begin(), base_.end(), out.begin(),
                     [](double c) { return static_cast<float>(c); });
      return {};
    }
    // Nodes a DISP block leaves out keep their coordinates.
    std::vector<double> xyz = base_;
    DYNPM_RETURN_IF_ERROR(read_block(steps_[t - 1].disp, [&](uint32_t v, const double* d) {
      for (int k = 0; k < 3; ++k) xyz[size_t(v) * 3 + k] += d[k];
    }));
    std::transform(xyz.begin(), xyz.end(), out.begin(),
                   [](double c) { return static_cast<float>(c); });
    return {};
  }

  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < field_names_.size() && t < step_count() && out.size() == vertex_count());
    std::fill(out.begin(), out.end(), 0.0f);
    if (t == 0 || steps_[t - 1].field_block[field] < 0) return {};
    const ResultBlock& block = field_blocks_[size_t(steps_[t - 1].field_block[field])];
    if (block.kind == BlockKind::kStress)
      return read_block(block, [&](uint32_t v, const double* s) {
        // von Mises from SXX SYY SZZ SXY SYZ SZX
        const double d1 = s[0] - s[1], d2 = s[1] - s[2], d3 = s[2] - s[0];
        out[v] = static_cast<float>(std::sqrt(0.5 * (d1 * d1 + d2 * d2 + d3 * d3) +
                                              3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
      });
    return read_block(block, [&](uint32_t v, const double* s) { out[v] = float(s[0]); });
  }

 private:
  // Calls visit(vertex, values) for every record of the block whose node is a vertex (nodes of
  // skipped solids are not).
  template <class Visit>
  Status read_block(const ResultBlock& block, Visit&& visit) const {
    ChunkReader reader;
    DYNPM_RETURN_IF_ERROR(reader.open(path_));
    reader.seek(block.data_offset, block.data_line);
    std::vector<double> values(block.values);
    if (block.format >= 2) {
      const size_t real = block.format == 2 ? 4 : 8;
      const size_t record = 4 + block.values * real;
      std::vector<char> b(record);
      for (uint64_t i = 0; i < block.node_count; ++i) {
        const uint64_t place = reader.offset();
        if (!reader.read(b.data(), record))
          return Status::error(path_ + ": byte " + std::to_string(place) +
                               ": the file ends inside a result block (changed since opened?)");
        const uint32_t v = vertex_of_.find(from_native<int32_t>(b.data()));
        if (v == kNoIndex) continue;
        for (size_t k = 0; k < block.values; ++k)
          values[k] = real == 4 ? from_native<float>(b.data() + 4 + 4 * k)
                                : from_native<double>(b.data() + 4 + 8 * k);
        visit(v, values.data());
      }
      return {};
    }
    const size_t width = block.format == 1 ? 10 : 5;
    const size_t first = 3 + width;
    std::string_view line;
    auto fail = [&](const std::string& cause) {
      return Status::error(path_ + ":" + std::to_string(reader.line() - 1) + ": " + cause);
    };
    while (true) {
      if (!reader.next_line(line))
        return Status::error(path_ +
                             ": the file ends inside a result block (changed since "
                             "opened?)");
      const int key = record_key(line);
      if (key == 3) return {};
      if (key != 1) return fail("expected a ' -1' data record or the ' -3' end of the block");
      const auto node = to_int(columns(line, 3, first));
      if (!node) return fail("cannot read the node number");
      size_t have = 0;
      while (true) {
        for (size_t on_line = 0; on_line < 6 && have < block.values; ++on_line) {
          const size_t a = first + 12 * on_line;
          const auto v = to_real(columns(line, a, a + 12));
          if (!v)
            return fail("cannot read value " + std::to_string(have + 1) + " of node " +
                        std::to_string(*node));
          values[have++] = *v;
        }
        if (have == block.values) break;
        if (!reader.next_line(line) || record_key(line) != 2)
          return fail("expected a ' -2' continuation line for node " + std::to_string(*node));
      }
      const uint32_t v = vertex_of_.find(*node);
      if (v != kNoIndex) visit(v, values.data());
    }
  }

  std::string path_;
  std::vector<int64_t> node_ids_;  // ascending: the vertices
  std::vector<double> base_;       // 3 · #V undeformed coordinates
  std::vector<Step> steps_;        // steps 1 …
  std::vector<ResultBlock> field_blocks_;
  std::vector<std::string> field_names_;
  NodeLookup vertex_of_;  // over node_ids_
};

// ---------------------------------------------------------------------------------------------
// open_frd()'s phases

using Note = std::function<void(const std::string&)>;

// The vertices: the nodes the shells use, in ascending node number (as our OBJ sequences).
struct ShellVertices {
  std::vector<int64_t> node_ids;
  std::vector<double> base;  // 3 · #V undeformed coordinates
};

Result<ShellVertices> shell_vertices(const std::string& path, Layout& layout) {
  std::vector<NodeRecord>& nodes = layout.nodes;
  auto by_id = [](const auto& a, const auto& b) { return a.id < b.id; };
  if (!std::is_sorted(nodes.begin(), nodes.end(), by_id))
    std::sort(nodes.begin(), nodes.end(), by_id);
  for (size_t i = 1; i < nodes.size(); ++i)
    if (nodes[i].id == nodes[i - 1].id)
      return Status::error(path + ": node " + std::to_string(nodes[i].id) +
                           " is defined twice in the node block");
  if (nodes.size() > kNoVertex - 1)
    return Status::error(path + ": more nodes than dynpm can index");
  std::vector<int64_t> ids(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) ids[i] = nodes[i].id;
  const NodeLookup node_of(ids);
  const std::string place_prefix = layout.binary ? ": byte " : ":";
  std::vector<bool> used(nodes.size(), false);
  for (const ElementRecord& e : layout.elements)
    for (int k = 0; k < e.corners; ++k) {
      const uint32_t i = node_of.find(e.nodes[k]);
      if (i == kNoIndex)
        return Status::error(path + place_prefix + std::to_string(e.place) + ": element " +
                             std::to_string(e.id) + " uses node " + std::to_string(e.nodes[k]) +
                             ", which the node block does not define");
      used[i] = true;
    }
  if (layout.elements.empty())
    return Status::error(path + ": no shell elements (S3, S4, S6, S8); " +
                         std::to_string(layout.skipped_elements) +
                         " solid or beam elements were skipped. ccx writes shells as 20-node "
                         "bricks unless the deck asks for *NODE FILE, OUTPUT=2D");
  ShellVertices vertices;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!used[i]) continue;
    vertices.node_ids.push_back(nodes[i].id);
    vertices.base.insert(vertices.base.end(), nodes[i].xyz, nodes[i].xyz + 3);
  }
  std::vector<NodeRecord>().swap(nodes);
  return vertices;
}

// The faces, in ascending element number (as our OBJ sequences), with their parts and numbers.
Topology shell_faces(Layout& layout, const std::vector<int64_t>& node_ids) {
  std::vector<ElementRecord>& elements = layout.elements;
  auto by_id = [](const ElementRecord& a, const ElementRecord& b) { return a.id < b.id; };
  if (!std::is_sorted(elements.begin(), elements.end(), by_id))
    std::stable_sort(elements.begin(), elements.end(), by_id);
  const NodeLookup vertex_of(node_ids);
  Topology topology;
  topology.vertex_count = uint32_t(node_ids.size());
  topology.reserve_faces(elements.size());
  for (const ElementRecord& e : elements) {
    Face f;
    for (int k = 0; k < e.corners; ++k) f.v[k] = vertex_of.find(e.nodes[k]);
    topology.faces.push_back(f);
    topology.part_ids.push_back(e.part);
    topology.element_ids.push_back(e.id);
  }
  topology.node_ids = node_ids;
  return topology;
}

// What the scan left out: quadratic shells' mid-side nodes, solids and beams, result blocks.
void note_left_out(const std::string& path, const Layout& layout, const Note& note) {
  if (layout.quadratic_elements)
    note(path + ": " + std::to_string(layout.quadratic_elements) +
         " quadratic shells (S6, S8) reduced to their corner nodes");
  if (layout.skipped_elements)
    note(path + ": skipped " + std::to_string(layout.skipped_elements) +
         " solid and beam elements (dynpm reads the shells S3, S4, S6, S8)");
  if (!layout.ignored_blocks.empty()) {
    std::string names;
    for (const std::string& n : layout.ignored_blocks) names += (names.empty() ? "" : ", ") + n;
    note(path +
         ": result blocks not read (only DISP, STRESS, PE and one-component blocks): " + names);
  }
}

// The step index: one step per DISP block; other blocks join the step whose DISP block has the
// same step number and time in its 100C line (ccx writes DISP, STRESS, PE … of one increment
// together).
struct StepIndex {
  std::vector<Step> steps;
  std::vector<ResultBlock> field_blocks;  // what Step::field_block points into
};

StepIndex step_index(const std::string& path, const Layout& layout, const Note& note) {
  StepIndex index;
  std::vector<Step>& steps = index.steps;
  std::map<std::pair<int64_t, std::string>, size_t> step_of_key;
  for (const ResultBlock& b : layout.blocks)
    if (b.kind == BlockKind::kDisp) {
      step_of_key[{b.step_number, b.value_text}] = steps.size();
      Step s;
      s.time = b.time;
      s.disp = b;
      s.field_block.assign(layout.field_names.size(), -1);
      steps.push_back(std::move(s));
    }
  size_t unmatched = 0;
  for (const ResultBlock& b : layout.blocks) {
    if (b.kind == BlockKind::kDisp) continue;
    auto it = step_of_key.find({b.step_number, b.value_text});
    if (it == step_of_key.end()) {
      ++unmatched;
      continue;
    }
    int64_t& slot = steps[it->second].field_block[b.field];
    if (slot >= 0) continue;  // the first block of a name in a step counts
    slot = int64_t(index.field_blocks.size());
    index.field_blocks.push_back(b);
  }
  if (unmatched)
    note(path + ": " + std::to_string(unmatched) +
         " result blocks without a DISP block of the same step and time were not read");
  if (steps.empty()) note(path + ": no DISP block: only the undeformed mesh (one step)");
  return index;
}

}  // namespace

Result<AnimationStream> open_frd(const std::string& path, const ReadOptions& options) {
  const Note note = [&](const std::string& text) {
    if (options.warn) options.warn(text);
  };
  // 1. One pass over the file: the header, node and element blocks read, the result blocks
  //    indexed by where their data start.
  auto layout = frd::scan(path);
  if (!layout) return layout.status();
  // A result still being written, or a file cut at a line boundary after a complete block.
  if (!layout->ended)
    note(path + ": no ' 9999' end record: the file may be cut short or still being written; " +
         "reading the steps it holds");
  // 2. The vertices: the nodes the shells use.
  auto vertices = shell_vertices(path, *layout);
  if (!vertices) return vertices.status();
  // 3. The faces, over those vertices.
  AnimationStream stream;
  stream.topology = shell_faces(*layout, vertices->node_ids);
  note_left_out(path, *layout, note);
  // 4. The step index: each DISP block a step, the field blocks of its increment beside it.
  StepIndex index = step_index(path, *layout, note);
  // 5. The steps stay on disk, read block by block.
  stream.frames = std::make_unique<FrdSource>(
      path, std::move(vertices->node_ids), std::move(vertices->base), std::move(index.steps),
      std::move(index.field_blocks), std::move(layout->field_names));
  return stream;
}

}  // namespace dynpm::io
