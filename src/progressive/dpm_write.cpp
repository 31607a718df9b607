// Writing the .dpm file: docs/FORMAT.md is the specification; this file follows it section by
// section (the reader is dpm_read.cpp).
#include <zstd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bytes.h"
#include "core/parallel.h"
#include "dpm_format.h"
#include "dynpm/progressive.h"
#include "field_coding.h"
#include "part_names_chunk.h"
#include "position_coding.h"
#include "split_records_coding.h"
#include "variants_chunk.h"

namespace dynpm {

namespace progressive {

constexpr int kZstdLevel = 12;

void put_chunk(std::string& out, std::string_view tag, std::string_view raw, bool compress) {
  if (compress) {
    std::string stored(ZSTD_compressBound(raw.size()), '\0');
    const size_t n =
        ZSTD_compress(stored.data(), stored.size(), raw.data(), raw.size(), kZstdLevel);
    if (!ZSTD_isError(n)) {
      stored.resize(n);
      const size_t header = out.size();
      out.append(kChunkHeaderSize, '\0');
      write_chunk_header(out.data() + header, tag, true, n, raw.size(), crc32(stored));
      out += stored;
      return;
    }
  }
  put_chunk_in_place(out, tag, [&](std::string& payload) { payload += raw; });
}

}  // namespace progressive

namespace {

using namespace progressive;

constexpr uint32_t kFirstChunkSplits = 256;
constexpr uint32_t kMaxChunkSplits = 16384;

// A stored q-value (GridValues' convention: 32 bits, signed unless lossless) as an integer.
int64_t q_value(uint32_t stored, bool lossless) {
  return lossless ? int64_t{stored} : int64_t{static_cast<int32_t>(stored)};
}

// The base vertices' positions (svarints, as in version 1) from their q-values, step by step.
void write_base_positions(ByteWriter& w, const Grid& g,
                          const std::vector<std::vector<uint32_t>>& base_q, uint32_t b) {
  for (size_t t = 0; t < base_q.size(); ++t)
    for (uint32_t v = 0; v < b; ++v)
      for (int c = 0; c < 3; ++c) {
        const auto q = [&](uint32_t u, size_t s) {
          return q_value(base_q[s][size_t{u} * 3 + c], g.lossless);
        };
        w.svarint(g.residual(q(v, t), predict_base(v, t, q)));
      }
}

void write_vertex_attributes(ByteWriter& w, const ProgressiveMesh& mesh, uint32_t v, Deltas& d) {
  w.svarint(int64_t{mesh.vertex_original_index[v]} - d.vertex_index);
  w.svarint(mesh.node_ids[v] - d.node_id);
  d.vertex_index = mesh.vertex_original_index[v];
  d.node_id = mesh.node_ids[v];
}

void write_face_attributes(ByteWriter& w, const ProgressiveMesh& mesh, uint32_t f, Deltas& d) {
  w.svarint(mesh.part_ids[f]);
  w.svarint(mesh.element_ids[f] - d.element_id);
  w.svarint(int64_t{mesh.face_original_index[f]} - d.face_index);
  d.element_id = mesh.element_ids[f];
  d.face_index = mesh.face_original_index[f];
}

std::string field_definitions(const ProgressiveMesh& mesh) {
  ByteWriter w;
  w.put<uint32_t>(static_cast<uint32_t>(mesh.fields.size()));
  for (const ProgressiveField& f : mesh.fields) {
    w.text(f.info.name);
    w.text(f.info.unit);
    w.put<uint8_t>(static_cast<uint8_t>(f.info.location));
    w.put<uint8_t>(f.lossless ? 1u : 0u);
    w.put<uint16_t>(0);
    w.put<double>(f.min);
    w.put<double>(f.max);
    w.put<double>(f.quant_step);
    w.put<double>(f.max_error);
    w.put<float>(f.base_error);
  }
  return std::move(w.bytes);
}

// The FLDS after BASE: the base vertices' (faces') values as svarints (FORMAT.md).
std::string base_field_values(const ProgressiveMesh& mesh) {
  ByteWriter w;
  w.put<uint32_t>(0);
  w.put<uint32_t>(0);
  for (const ProgressiveField& f : mesh.fields) {
    const uint32_t end =
        f.info.location == FieldLocation::kElement ? mesh.base_face_count : mesh.base_vertex_count;
    const FieldGrid g(f);
    const auto q = [&](uint32_t u, size_t s) { return g.q(f.values[s][u]); };
    for (size_t t = 0; t < mesh.step_count(); ++t)
      for (uint32_t item = 0; item < end; ++item)
        w.svarint(g.residual(q(item, t), predict_base(item, t, q)));
  }
  return std::move(w.bytes);
}

// The FLDS after the SPLT of chunk c (the k-th): the heirs of the faces its splits create, then
// per field the errors after each split and the range-coded sections of every step.
std::string split_field_values(const ProgressiveMesh& mesh, const FieldChunk& c, size_t k,
                               const std::vector<std::vector<std::vector<FieldSection>>>& coded) {
  ByteWriter w;
  w.put<uint32_t>(c.first);
  w.put<uint32_t>(c.last - c.first);
  if (has_element_field(mesh)) {
    uint32_t g = c.face_begin;
    for (uint32_t i = c.first; i < c.last; ++i) {
      const uint32_t before = g;  // F: the faces before split i
      for (uint32_t j = mesh.wing_start[i]; j < mesh.wing_start[i + 1]; ++j)
        if (mesh.wings[j].was_triangle()) w.varint(before - 1 - mesh.face_heir[g++]);
    }
  }
  for (size_t f = 0; f < mesh.fields.size(); ++f) {
    for (uint32_t i = c.first; i < c.last; ++i) w.put<float>(mesh.fields[f].error[i]);
    for (const std::vector<FieldSection>& step : coded[f]) {
      w.put<uint8_t>(static_cast<uint8_t>(step[k].predictor));
      w.put<uint32_t>(static_cast<uint32_t>(step[k].bytes.size()));
      w.bytes += step[k].bytes;
    }
  }
  return std::move(w.bytes);
}

std::string head_payload(const ProgressiveMesh& mesh) {
  ByteWriter w;
  w.put<uint32_t>(mesh.full_vertex_count);
  w.put<uint32_t>(mesh.full_face_count);
  w.put<uint32_t>(mesh.base_vertex_count);
  w.put<uint32_t>(mesh.base_face_count);
  w.put<uint32_t>(mesh.full_split_count);
  w.put<uint32_t>(static_cast<uint32_t>(mesh.step_count()));
  w.put<uint32_t>(0);  // field_count: the fields have chunks of their own (FDEF, FLDS)
  w.put<uint32_t>(mesh.lossless ? 1u : 0u);
  for (double x : mesh.bbox_min) w.put<double>(x);
  for (double x : mesh.bbox_max) w.put<double>(x);
  w.put<double>(mesh.quant_step);
  w.put<double>(mesh.max_error);
  w.put<double>(mesh.base_error);
  for (double t : mesh.times) w.put<double>(t);
  w.put<uint32_t>(static_cast<uint32_t>(mesh.key_steps.size()));
  for (size_t k : mesh.key_steps) w.put<uint32_t>(static_cast<uint32_t>(k));
  w.text(mesh.note);
  return std::move(w.bytes);
}

}  // namespace

// The records, chunk by chunk (each coded against the mesh the splits before it left, which the
// records' models keep as the decoder has it, and which gives each split's stencil), made
// before the first step; the positions as the steps come; the rest of the file at the end.
struct DpmStepEncoder::State {
  struct SplitChunk {
    uint32_t first, last, first_face, end_face;
    std::string records, attributes;
  };
  explicit State(const ProgressiveMesh& m) : mesh(m) {}
  const ProgressiveMesh& mesh;
  unsigned threads = 1;
  std::vector<SplitChunk> chunks;
  std::vector<std::pair<uint32_t, uint32_t>> ranges;  // the chunks' splits
  ChunkStencils stencils;                             // every split's, in split order
  std::optional<StepPositionEncoder> positions;
  std::vector<std::vector<uint32_t>> base_q;  // per step, the base vertices' q-values
  size_t steps_given = 0;

  // The next step's q-values, every vertex in the progressive numbering.
  void add_step(std::vector<uint32_t> q) {
    base_q.emplace_back(q.begin(), q.begin() + size_t{mesh.base_vertex_count} * 3);
    positions->add_step(std::move(q));
    ++steps_given;
  }
};

DpmStepEncoder::DpmStepEncoder(std::unique_ptr<State> state) : state_(std::move(state)) {}
DpmStepEncoder::DpmStepEncoder(DpmStepEncoder&&) noexcept = default;
DpmStepEncoder& DpmStepEncoder::operator=(DpmStepEncoder&&) noexcept = default;
DpmStepEncoder::~DpmStepEncoder() = default;

Result<DpmStepEncoder> DpmStepEncoder::start(const ProgressiveMesh& mesh, unsigned threads,
                                             const std::function<void(uint32_t)>& coded_splits) {
  // Ids a reader would refuse (dpm_format.h kIdLimit) are refused here, before any is coded.
  for (const auto* ids : {&mesh.node_ids, &mesh.element_ids})
    for (size_t k = 0; k < ids->size(); ++k)
      if (!id_fits((*ids)[k]))
        return Status::error(std::string(ids == &mesh.node_ids ? "node" : "element") + " id " +
                             std::to_string((*ids)[k]) + " is not within ±2^51, as a .dpm needs");
  auto state = std::make_unique<State>(mesh);
  state->threads = thread_count(threads);
  uint32_t chunk = kFirstChunkSplits;
  for (uint32_t first = 0; first < mesh.split_count();
       first += chunk, chunk = std::min(chunk * 2, kMaxChunkSplits)) {
    const uint32_t last = std::min(mesh.split_count(), first + chunk);
    state->ranges.emplace_back(first, last);
    state->chunks.push_back({first, last, 0, 0, {}, {}});
  }
  // Reserved (a ring has about 7 vertices): grown by doubling, each copy was fresh memory.
  state->stencils.splits.reserve(mesh.split_count());
  state->stencils.ring.reserve(size_t{mesh.split_count()} * 8);
  // The records, and the attributes with the stencils (read from the faces the splits leave):
  // two walks of about equal work, on two threads when there are, each writing only its own
  // fields of the chunks.
  std::array<Status, 2> walked;
  // Each walk's splits so far; the walk on the caller's thread tells their mean.
  std::array<std::atomic<uint32_t>, 2> walked_to{};
  const std::thread::id caller = std::this_thread::get_id();
  parallel_for(2, 2, state->threads, [&](size_t begin, size_t end, size_t) {
    for (size_t walk = begin; walk < end; ++walk) {
      const bool records = walk == 0;
      RecordModels models(mesh, RecordModels::Room::kFull);
      for (State::SplitChunk& c : state->chunks) {
        const uint32_t first_face = models.face_count();
        auto coded =
            records
                ? encode_split_records(mesh, c.first, c.last, models, {}, SplitSections::kRecords)
                : encode_split_records(
                      mesh, c.first, c.last, models,
                      [&](uint32_t i) { state->stencils.add(mesh, i, models.faces()); },
                      SplitSections::kAttributes);
        if (!coded.ok()) {
          walked[walk] = coded.status();
          break;
        }
        if (records) {
          c.first_face = first_face, c.end_face = models.face_count();
          c.records = std::move(coded->first);
        } else {
          c.attributes = std::move(coded->second);
        }
        walked_to[walk] = c.last;
        if (coded_splits && std::this_thread::get_id() == caller)
          coded_splits(static_cast<uint32_t>((uint64_t{walked_to[0]} + walked_to[1]) / 2));
      }
    }
  });
  for (const Status& status : walked) DYNPM_RETURN_IF_ERROR(status);
  if (coded_splits) coded_splits(mesh.split_count());  // both walks are done
  state->positions.emplace(mesh, state->stencils, state->ranges, state->threads);
  return DpmStepEncoder(std::move(state));
}

void DpmStepEncoder::add_step(std::span<const float> xyz) {
  State& s = *state_;
  assert(s.steps_given < s.mesh.step_count() && xyz.size() == size_t{s.mesh.vertex_count()} * 3);
  const Grid g = grid_of(s.mesh);
  std::vector<uint32_t> q = s.positions->spare_step();
  const size_t vertices = xyz.size() / 3;
  parallel_for(vertices, std::max<size_t>(1, vertices / 65536), s.threads,
               [&](size_t begin, size_t end, size_t) {
                 for (size_t k = begin * 3; k < end * 3; ++k)
                   q[k] = static_cast<uint32_t>(g.q(xyz[k], static_cast<int>(k % 3)));
               });
  s.add_step(std::move(q));
}

Status DpmStepEncoder::add_input_step(std::span<const float> xyz,
                                      std::span<const uint32_t> progressive_of) {
  State& s = *state_;
  assert(s.steps_given < s.mesh.step_count() && xyz.size() == progressive_of.size() * 3 &&
         progressive_of.size() == s.mesh.vertex_count());
  const Grid g = grid_of(s.mesh);
  std::vector<uint32_t> q = s.positions->spare_step();
  const size_t vertices = progressive_of.size();
  std::atomic<bool> finite{true};
  parallel_for(vertices, std::max<size_t>(1, vertices / 65536), s.threads,
               [&](size_t begin, size_t end, size_t) {
                 bool all_finite = true;
                 for (size_t v = begin; v < end; ++v) {
                   const float* p = &xyz[v * 3];
                   uint32_t* out = &q[size_t{progressive_of[v]} * 3];
                   for (int c = 0; c < 3; ++c) {
                     const bool ok = std::isfinite(p[c]);  // a step with a bad one is refused
                     all_finite &= ok;
                     out[c] = g.lossless ? std::bit_cast<uint32_t>(p[c])
                                         : static_cast<uint32_t>(ok ? g.nearest(p[c], c) : 0);
                   }
                 }
                 if (!all_finite) finite = false;
               });
  if (!finite)
    return Status::error("time step " + std::to_string(s.steps_given) +
                         " has a non-finite coordinate");
  s.add_step(std::move(q));
  return {};
}

Result<std::string> DpmStepEncoder::finish(std::string_view thumbnail_png) {
  State& s = *state_;
  const ProgressiveMesh& mesh = s.mesh;
  assert(s.steps_given == mesh.step_count());
  const std::vector<std::vector<std::string>> positions = s.positions->finish();
  // The file's size but for HEAD, BASE and the small chunks, reserved: grown by doubling, a file
  // of tens of MB was copied five times and each copy faulted in afresh.
  size_t splits_bytes = 0;
  for (const auto& c : s.chunks) splits_bytes += c.records.size() + c.attributes.size() + 64;
  for (const auto& step : positions)
    for (const std::string& section : step) splits_bytes += section.size() + 4;
  std::string out;
  out.reserve(splits_bytes + thumbnail_png.size() + (size_t{1} << 20));
  out += kMagic;
  ByteWriter version;
  version.put<uint32_t>(kVersion);
  out += version.bytes;
  put_chunk(out, "HEAD", head_payload(mesh), false);
  const bool fields = !mesh.fields.empty();
  if (fields) put_chunk(out, "FDEF", field_definitions(mesh), false);
  if (const std::string parts = part_names_payload(mesh); !parts.empty())
    put_chunk(out, "PART", parts, false);
  if (const std::string variants = variants_payload(mesh); !variants.empty())
    put_chunk(out, "VARI", variants, false);

  Deltas d;
  {
    ByteWriter w;
    for (uint32_t v = 0; v < mesh.base_vertex_count; ++v) write_vertex_attributes(w, mesh, v, d);
    for (const Face& face : mesh.base_faces) {
      w.put<uint8_t>(static_cast<uint8_t>(face.degree()));
      for (int c = 0; c < face.degree(); ++c) w.varint(face.v[c]);
    }
    for (uint32_t f = 0; f < mesh.base_face_count; ++f) write_face_attributes(w, mesh, f, d);
    write_base_positions(w, grid_of(mesh), s.base_q, mesh.base_vertex_count);
    put_chunk(out, "BASE", w.bytes, true);
  }
  if (fields) put_chunk(out, "FLDS", base_field_values(mesh), true);

  // The fields of each chunk: coded a field and step a task, then compressed on every thread.
  const auto& chunks = s.chunks;
  std::vector<FieldChunk> field_ranges;
  for (const auto& c : chunks) field_ranges.push_back({c.first, c.last, c.first_face, c.end_face});
  const auto coded_fields = fields ? encode_split_fields(mesh, s.stencils, field_ranges, s.threads)
                                   : std::vector<std::vector<std::vector<FieldSection>>>{};
  std::vector<std::string> field_chunks(fields ? chunks.size() : 0);
  parallel_for(field_chunks.size(), field_chunks.size(), s.threads,
               [&](size_t begin, size_t end, size_t) {
                 for (size_t k = begin; k < end; ++k)
                   put_chunk(field_chunks[k], "FLDS",
                             split_field_values(mesh, field_ranges[k], k, coded_fields), true);
               });

  for (size_t k = 0; k < chunks.size(); ++k) {
    std::vector<std::string_view> sections{chunks[k].records, chunks[k].attributes};
    for (size_t t = 0; t < positions.size(); ++t) sections.push_back(positions[t][k]);
    ByteWriter w;
    w.put<uint32_t>(chunks[k].first);
    w.put<uint32_t>(chunks[k].last - chunks[k].first);
    w.put<uint32_t>(static_cast<uint32_t>(sections.size()));
    for (std::string_view section : sections)
      w.put<uint32_t>(static_cast<uint32_t>(section.size()));
    put_chunk_in_place(out, "SPLT", [&](std::string& payload) {  // range-coded: no zstd
      payload += w.bytes;
      for (std::string_view section : sections) payload += section;
    });
    if (fields) out += field_chunks[k];
  }
  // PNG data is compressed already; as with_thumbnail() would add it.
  if (!thumbnail_png.empty()) put_chunk(out, kThumbnailTag, thumbnail_png, false);
  put_chunk(out, "END ", {}, false);
  return out;
}

Result<std::string> encode_dpm(const ProgressiveMesh& mesh, unsigned threads) {
  auto encoder = DpmStepEncoder::start(mesh, threads);
  if (!encoder) return encoder.status();
  for (size_t t = 0; t < mesh.step_count(); ++t) encoder->add_step(mesh.positions[t]);
  return encoder->finish();
}

Status write_dpm(const std::string& path, const ProgressiveMesh& mesh) {
  if (!mesh.complete) return Status::error(path + ": cannot write a partial progressive mesh");
  auto bytes = encode_dpm(mesh);
  if (!bytes.ok()) return bytes.status();
  return write_file_atomically(path, *bytes);
}

}  // namespace dynpm
