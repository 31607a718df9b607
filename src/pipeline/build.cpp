// build(): simplify to the end while recording every collapse, then reverse the record into
// vertex splits in the progressive numbering, and read every step's positions once more, in that
// order: into memory (build_progressive_mesh) or straight into the file's coder (build_dpm).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <numeric>
#include <span>
#include <type_traits>

#include "build_fields.h"
#include "core/parallel.h"
#include "dynpm/pipeline.h"
#include "split_order.h"
#include "thumbnail_level.h"

namespace dynpm {
namespace {

// Everything a collapse did, in the input's numbering, kept until the simplifier is done: the
// new numbers of faces that vanish later are only known at the end. Wings and moved faces are
// pooled (about two of each per collapse): 24 B per collapse plus 12 B per wing and 4 B per
// moved face, where four wings kept inline took 80 B. Reserved for one collapse per vertex
// (at most that many happen): the untouched tail costs address space only, and the log never
// holds an old and a new copy at once while it grows.
class CollapseLog final : public CollapseListener {
 public:
  struct Entry {
    uint32_t v0, v1;
    uint32_t wings_begin, moved_begin;  // into wings and moved_faces; ends at the next entry's
    double error;                       // in bounding-box diagonals of the key steps
  };

  explicit CollapseLog(uint32_t vertex_count) {
    entries.reserve(vertex_count);
    wings_.reserve(size_t{vertex_count} * 2);
    moved_faces_.reserve(size_t{vertex_count} * 3);
  }

  void on_collapse(const CollapseRecord& record) override {
    entries.push_back({record.v0, record.v1, static_cast<uint32_t>(wings_.size()),
                       static_cast<uint32_t>(moved_faces_.size()), record.error});
    wings_.insert(wings_.end(), record.wings.begin(), record.wings.begin() + record.wing_count);
    moved_faces_.insert(moved_faces_.end(), record.moved_faces.begin(), record.moved_faces.end());
  }

  std::span<const SplitWing> wings(size_t i) const {
    const size_t end = i + 1 < entries.size() ? entries[i + 1].wings_begin : wings_.size();
    return {wings_.data() + entries[i].wings_begin, end - entries[i].wings_begin};
  }
  std::span<const uint32_t> moved_faces(size_t i) const {
    const size_t end = i + 1 < entries.size() ? entries[i + 1].moved_begin : moved_faces_.size();
    return {moved_faces_.data() + entries[i].moved_begin, end - entries[i].moved_begin};
  }

  size_t wing_total() const { return wings_.size(); }
  size_t moved_total() const { return moved_faces_.size(); }
  // Its memory back, once the splits are made from it.
  void release() {
    std::vector<Entry>().swap(entries);
    std::vector<SplitWing>().swap(wings_);
    std::vector<uint32_t>().swap(moved_faces_);
  }

  std::vector<Entry> entries;

 private:
  std::vector<SplitWing> wings_;
  std::vector<uint32_t> moved_faces_;
};

// The simplifier's record in the progressive numbering: the mesh without its positions.
struct Recorded {
  ProgressiveMesh pm;
  std::vector<uint32_t> new_vertex, new_face;  // input → progressive numbering
};

// The box of every step: the caller's, else the simplifier's when every step was a key step,
// else a pass of its own over the steps.
Result<BoundingBox> all_steps_box(const FrameSource& frames, const BuildOptions& options,
                                  const SimplifyResult& simplified) {
  if (options.all_steps_box) return *options.all_steps_box;
  if (simplified.key_steps.size() == frames.step_count()) return simplified.key_step_box;
  std::vector<size_t> every(frames.step_count());
  std::iota(every.begin(), every.end(), size_t{0});
  BoundingBox box;
  DYNPM_RETURN_IF_ERROR(for_each_step(frames, every, options.simplify.threads,
                                      [&](size_t, std::span<const float> step) {
                                        box.extend(step);
                                        return Status{};
                                      }));
  return box;
}

Result<Recorded> record(const Topology& topology, const FrameSource& frames,
                        const BuildOptions& options) {
  if (options.simplify.placement != Placement::kHalfEdge)
    return Status::error(
        "a progressive mesh is built with half-edge collapses (positions stay original); "
        "optimal placement is only available in 'dynpm simplify'");
  if (frames.step_count() == 0) return Status::error("the input has no time step");
  if (!(options.max_position_error > 0) && !options.lossless)
    return Status::error("the position error bound must be positive (or use lossless)");

  SimplifyOptions simplify_options = options.simplify;
  simplify_options.target_vertices.reset();
  simplify_options.target_faces.reset();
  simplify_options.target_ratio.reset();
  simplify_options.max_error.reset();
  simplify_options.progress = options.progress;
  CollapseLog log(topology.vertex_count);
  auto simplified = simplify(topology, frames, simplify_options, &log);
  if (!simplified) return simplified.status();

  const uint32_t n = topology.vertex_count;
  const uint32_t splits = static_cast<uint32_t>(log.entries.size());
  // In splits, by the share of the phase's time each part took at 1 M vertices (BENCHMARKS.md
  // "The table, redone"): the records a fifth, the split order seven tenths, then the rest.
  const auto recording = [&](double share) {
    if (options.progress)
      options.progress("recording the splits", static_cast<size_t>(share * splits),
                       std::max(1u, splits));
  };
  recording(0);
  Recorded recorded;
  ProgressiveMesh& pm = recorded.pm;
  std::vector<uint32_t>& new_vertex = recorded.new_vertex;
  std::vector<uint32_t>& new_face = recorded.new_face;

  // Vertices: never removed → base, in input order; the v0 of the last collapse → b, …
  new_vertex.assign(n, kNoVertex);
  std::vector<char> removed(n, 0);
  for (const auto& e : log.entries) removed[e.v0] = 1;
  uint32_t next = 0;
  for (uint32_t v = 0; v < n; ++v)
    if (!removed[v]) new_vertex[v] = next++;
  pm.base_vertex_count = next;
  for (uint32_t i = 0; i < splits; ++i) new_vertex[log.entries[splits - 1 - i].v0] = next++;

  // Faces: alive at the end → base, in input order; then each split's re-created triangles.
  const uint32_t face_total = static_cast<uint32_t>(topology.faces.size());
  new_face.assign(face_total, kNoIndex);
  std::vector<char> vanished(face_total, 0);
  for (size_t j = 0; j < splits; ++j)
    for (const SplitWing& w : log.wings(j))
      if (w.was_triangle()) vanished[w.face] = 1;
  uint32_t next_face = 0;
  for (uint32_t f = 0; f < face_total; ++f)
    if (!vanished[f]) new_face[f] = next_face++;
  pm.base_face_count = next_face;
  for (uint32_t i = 0; i < splits; ++i)
    for (const SplitWing& w : log.wings(splits - 1 - i))
      if (w.was_triangle()) new_face[w.face] = next_face++;
  if (next_face != face_total) return Status::error("internal: a face was lost in the record");

  // The base mesh: the simplifier's live faces, in input order.
  const Topology& base = simplified->topology;
  if (base.faces.size() != pm.base_face_count)
    return Status::error("internal: the simplified mesh does not match the record");
  pm.base_faces.reserve(base.faces.size());
  for (Face face : base.faces) {
    for (uint32_t& c : face.v)
      if (c != kNoVertex) c = new_vertex[simplified->original_vertex[c]];
    pm.base_faces.push_back(face);
  }

  // Splits, in reverse collapse order; errors become "the error of the level after the split"
  // (the largest error of the collapses still in effect), which never increases.
  std::vector<double> prefix_max(splits + 1, 0.0);
  for (uint32_t j = 0; j < splits; ++j)
    prefix_max[j + 1] = std::max(prefix_max[j], log.entries[j].error);

  pm.parent.reserve(splits);
  pm.error.reserve(splits);
  pm.wings.reserve(log.wing_total());
  pm.wing_start.reserve(size_t{splits} + 1);
  pm.moved_faces.reserve(log.moved_total());
  pm.moved_start.reserve(size_t{splits} + 1);
  for (uint32_t i = 0; i < splits; ++i) {
    const size_t j = splits - 1 - i;
    pm.parent.push_back(new_vertex[log.entries[j].v1]);
    pm.error.push_back(0);                   // below, once the scale is known
    for (const SplitWing& w : log.wings(j))  // renumbered, its flags as they are
      pm.wings.push_back({new_face[w.face], new_vertex[w.vertex], w.flags});
    pm.wing_start.push_back(static_cast<uint32_t>(pm.wings.size()));
    for (uint32_t f : log.moved_faces(j)) pm.moved_faces.push_back(new_face[f]);
    pm.moved_start.push_back(static_cast<uint32_t>(pm.moved_faces.size()));
  }
  log.release();  // before the attributes, the box and the reordering take their memory
  recording(0.2);

  // Attributes in the progressive numbering.
  pm.full_vertex_count = n;
  pm.full_face_count = face_total;
  pm.full_split_count = splits;
  pm.vertex_original_index.resize(n);
  pm.node_ids.resize(n);
  for (uint32_t v = 0; v < n; ++v) {
    pm.vertex_original_index[new_vertex[v]] = v;
    pm.node_ids[new_vertex[v]] = topology.node_ids[v];
  }
  pm.face_original_index.resize(face_total);
  pm.part_ids.resize(face_total);
  pm.part_names = topology.part_names;
  pm.element_ids.resize(face_total);
  for (uint32_t f = 0; f < face_total; ++f) {
    pm.face_original_index[new_face[f]] = f;
    pm.part_ids[new_face[f]] = topology.part_ids[f];
    pm.element_ids[new_face[f]] = topology.element_ids[f];
  }

  // The grid: the box of every step (known before the positions are read, which are then
  // quantized as they come).
  auto box = all_steps_box(frames, options, *simplified);
  if (!box) return box.status();
  for (int k = 0; k < 3; ++k) {
    pm.bbox_min[k] = box->empty ? 0.0 : box->min[k];
    pm.bbox_max[k] = box->empty ? 0.0 : box->max[k];
  }
  pm.times.resize(frames.step_count());
  for (size_t t = 0; t < pm.times.size(); ++t) pm.times[t] = frames.step_time(t);

  // Errors in absolute units: the simplifier measured them in key-step diagonals. Each level's
  // error is rounded to float32 once, the base's too (the file keeps a split's error as f32):
  // rounding the base's differently could put it a float ulp below the first split's, and level
  // errors must never increase along the stream (docs/FORMAT.md).
  const double diagonal = simplified->key_step_box.diagonal();
  const double scale = diagonal > 0 ? diagonal : 1.0;
  auto absolute = [scale](double e) { return static_cast<float>(e * scale); };
  pm.base_error = absolute(prefix_max[splits]);
  for (uint32_t i = 0; i < splits; ++i) pm.error[i] = absolute(prefix_max[splits - 1 - i]);
  std::vector<double>().swap(prefix_max);
  pm.key_steps = simplified->key_steps;
  pm.lossless = options.lossless;
  pm.max_error = options.lossless ? 0.0 : options.max_position_error * pm.diagonal();
  pm.note = options.note;
  pm.variants = options.variants;
  set_position_grid(pm);
  order_splits_by_parent(
      pm, new_vertex, new_face,  // parents ascending within error bands
      [&](double share) { recording(0.2 + 0.7 * share); }, options.simplify.threads);
  prepare_split_records(pm);  // errors on the file's grid, moved faces ascending (as read back)
  // Result fields, per vertex or per face, permuted like the positions (build_fields.cpp).
  DYNPM_RETURN_IF_ERROR(
      build_fields(frames, new_vertex, new_face, options.field_bound, options.lossless, pm));
  if (splits > 0) recording(1);  // (none: 0 of 1, ended by the next phase)
  return recorded;
}

// Every step's positions, read once each (several at once where the source allows), permuted
// into the progressive numbering and put on the grid, to use(t, xyz) in step order. Reports
// `phase` (steps). (build_dpm()'s last pass is encode_steps().)
Status for_each_progressive_step(const FrameSource& frames, const Recorded& r,
                                 const BuildOptions& options, const char* phase,
                                 const std::function<void(size_t, std::span<const float>)>& use) {
  const size_t steps = frames.step_count();
  std::vector<size_t> every(steps);
  std::iota(every.begin(), every.end(), size_t{0});
  const uint32_t n = static_cast<uint32_t>(r.new_vertex.size());
  std::vector<float> out(size_t{n} * 3);
  const unsigned threads = thread_count(options.simplify.threads);
  const size_t parts = std::max<size_t>(1, n / 65536);
  if (options.progress) options.progress(phase, 0, steps);
  return for_each_step(
      frames, every, options.simplify.threads, [&](size_t t, std::span<const float> step) {
        // Checked, renumbered and put on the grid on every thread (each vertex's own slots).
        std::atomic<bool> finite{true};
        parallel_for(n, parts, threads, [&](size_t begin, size_t end, size_t) {
          for (size_t v = begin; v < end; ++v) {
            const float* xyz = &step[v * 3];
            if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
              finite = false;
            std::copy_n(xyz, 3, &out[r.new_vertex[v] * size_t{3}]);
          }
        });
        if (!finite)
          return Status::error("time step " + std::to_string(t) + " has a non-finite coordinate");
        parallel_for(n, parts, threads, [&](size_t begin, size_t end, size_t) {
          quantize_step(r.pm, std::span(out).subspan(begin * 3, (end - begin) * 3));
        });
        use(t, out);
        if (options.progress) options.progress(phase, t + 1, steps);
        return Status{};
      });
}

// After DpmStepEncoder::start() has coded the records: what finish() will not read again
// (it reads the header's values, the base's attributes and faces, and, for the fields' chunks,
// the records and every attribute), so that the steps have its room (76 B per split). Without
// fields: the split records and the attributes of the split vertices and of the faces the
// splits make; `parent` stays (the split count). BuiltFile::mesh is the report's.
void release_coded_records(ProgressiveMesh& mesh) {
  if (!mesh.fields.empty()) return;
  const auto keep = [](auto& values, size_t count) {
    count = std::min(count, values.size());
    std::remove_reference_t<decltype(values)>(values.begin(), values.begin() + count).swap(values);
  };
  keep(mesh.wings, 0), keep(mesh.moved_faces, 0);
  keep(mesh.wing_start, 1), keep(mesh.moved_start, 1);
  keep(mesh.vertex_original_index, mesh.base_vertex_count);
  keep(mesh.node_ids, mesh.base_vertex_count);
  keep(mesh.face_original_index, mesh.base_face_count);
  keep(mesh.part_ids, mesh.base_face_count);
  keep(mesh.element_ids, mesh.base_face_count);
}

// The build's last pass: every step read once and given to the encoder as read (renumbered and
// put on the grid there, in one pass over the step); the thumbnail's level keeps the first and
// the last step, quantized as the file has them.
Status encode_steps(const FrameSource& frames, const Recorded& r, const BuildOptions& options,
                    DpmStepEncoder& encoder, ProgressiveMesh* thumbnail) {
  const size_t steps = frames.step_count();
  std::vector<uint32_t> input_of(thumbnail ? thumbnail->vertex_count() : 0);  // level → input
  for (uint32_t v = 0; v < r.new_vertex.size(); ++v)
    if (r.new_vertex[v] < input_of.size()) input_of[r.new_vertex[v]] = v;
  std::vector<size_t> every(steps);
  std::iota(every.begin(), every.end(), size_t{0});
  const char* phase = "encoding positions";
  if (options.progress) options.progress(phase, 0, steps);
  return for_each_step(frames, every, options.simplify.threads,
                       [&](size_t t, std::span<const float> step) {
                         DYNPM_RETURN_IF_ERROR(encoder.add_input_step(step, r.new_vertex));
                         if (thumbnail && thumbnail_keeps_step(t, steps)) {
                           std::vector<float> xyz(input_of.size() * 3);
                           for (size_t u = 0; u < input_of.size(); ++u)
                             std::copy_n(&step[size_t{input_of[u]} * 3], 3, &xyz[u * 3]);
                           quantize_step(r.pm, xyz);
                           keep_thumbnail_step(*thumbnail, t, steps, xyz);
                         }
                         if (options.progress) options.progress(phase, t + 1, steps);
                         return Status{};
                       });
}

}  // namespace

Result<ProgressiveMesh> build_progressive_mesh(const Topology& topology, const FrameSource& frames,
                                               const BuildOptions& options) {
  auto recorded = record(topology, frames, options);
  if (!recorded) return recorded.status();
  ProgressiveMesh& pm = recorded->pm;
  pm.positions.resize(frames.step_count());
  DYNPM_RETURN_IF_ERROR(for_each_progressive_step(frames, *recorded, options, "gathering positions",
                                                  [&](size_t t, std::span<const float> xyz) {
                                                    pm.positions[t].assign(xyz.begin(), xyz.end());
                                                  }));
  return std::move(pm);
}

namespace {

// build_dpm(), with `release` (the same topology, or null) freed of what the coding does not
// read once the splits are recorded.
Result<BuiltFile> record_and_code(const Topology& topology, Topology* release,
                                  const FrameSource& frames, const BuildOptions& options) {
  auto recorded = record(topology, frames, options);
  if (!recorded) return recorded.status();
  std::vector<uint32_t>().swap(recorded->new_face);  // the steps need only new_vertex
  if (release) release->release_faces();
  const uint32_t splits = std::max(1u, recorded->pm.split_count());  // 0 of 1 while coding none
  const auto coded = [&](uint32_t done) { options.progress("coding the splits", done, splits); };
  if (options.progress) coded(0);
  auto encoder = DpmStepEncoder::start(recorded->pm, options.simplify.threads,
                                       options.progress ? coded : std::function<void(uint32_t)>{});
  if (!encoder) return encoder.status();
  std::optional<ProgressiveMesh> thumbnail;  // its level, before the records go
  if (options.thumbnail) thumbnail = thumbnail_level(recorded->pm, *options.thumbnail);
  release_coded_records(recorded->pm);  // the records are coded: room for the steps
  DYNPM_RETURN_IF_ERROR(
      encode_steps(frames, *recorded, options, *encoder, thumbnail ? &*thumbnail : nullptr));
  // The picture first: the file is then written once, with it in place before END.
  std::string picture;
  if (thumbnail) {
    if (options.progress) options.progress("thumbnail", 0, 1);
    picture = render_thumbnail(*thumbnail, *options.thumbnail);
    thumbnail.reset();
    if (options.progress) options.progress("thumbnail", 1, 1);
  }
  if (options.progress) options.progress("encoding", 0, 1);
  auto bytes = encoder->finish(picture);
  if (!bytes) return bytes.status();
  if (options.progress) options.progress("encoding", 1, 1);
  return BuiltFile{std::move(recorded->pm), std::move(bytes).value()};
}

}  // namespace

Result<BuiltFile> build_dpm(const Topology& topology, const FrameSource& frames,
                            const BuildOptions& options) {
  return record_and_code(topology, nullptr, frames, options);
}

Result<BuiltFile> build_dpm(Topology&& topology, const FrameSource& frames,
                            const BuildOptions& options) {
  return record_and_code(topology, &topology, frames, options);
}

}  // namespace dynpm
