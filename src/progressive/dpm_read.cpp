// Reading the .dpm file: docs/FORMAT.md is the specification (the writer is dpm_write.cpp). The
// browser's decoder, viewer/src/dpm/file.js, makes the same checks at the same moment and rejects
// a file at the same byte (viewer/test/conformance.test.mjs).
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bytes.h"
#include "core/parallel.h"
#include "dpm_format.h"
#include "dpm_read_fields.h"
#include "dynpm/progressive.h"
#include "part_names_chunk.h"
#include "position_coding.h"
#include "split_records_coding.h"
#include "variants_chunk.h"
#include "zstd_frame.h"

namespace dynpm {
namespace {

using namespace progressive;

class Decoder {
 public:
  Decoder(std::string_view bytes, const std::string& name, const DpmReadLimits& limits)
      : bytes_(bytes), name_(name), limits_(limits) {}

  // A SPLT's positions are decoded beside the next one's records: a problem in them comes first.
  Result<ProgressiveMesh> run() {
    auto mesh = read();
    if (Status earlier = flush_positions(); !mesh.ok() && !earlier.ok()) return earlier;
    return mesh;
  }

 private:
  Result<ProgressiveMesh> read() {
    if (bytes_.size() < kMagic.size() + 4 || !looks_like_dpm(bytes_))
      return fail(0, "not a .dpm file (no DPM signature)");
    uint32_t version;
    std::memcpy(&version, bytes_.data() + kMagic.size(), 4);
    if (version >= 1 && version < kVersion)
      return fail(kMagic.size(), "written by an older dynpm (version " + std::to_string(version) +
                                     "): build it again");
    if (version != kVersion)
      return fail(kMagic.size(), "version " + std::to_string(version) +
                                     " is not supported (this dynpm reads version " +
                                     std::to_string(kVersion) + ")");
    pos_ = kMagic.size() + 4;

    std::string payload, tag;
    DYNPM_RETURN_IF_ERROR(expect_chunk("HEAD", payload, "the header"));
    DYNPM_RETURN_IF_ERROR(parse_head(payload));
    apply_limits_of_head();
    // Field definitions, part names, a family's variants (each if any), then the base mesh.
    auto got = next_chunk("BASE", tag, payload, "FDEF|PART|VARI");
    if (!got) return got.status();
    if (*got && tag == "FDEF") {
      if (auto e = parse_field_definitions(payload, mesh_)) return bad_at(*e);
      got = next_chunk("BASE", tag, payload, "PART|VARI");
      if (!got) return got.status();
    }
    if (*got && tag == "PART") {
      if (auto e = parse_part_names(payload, mesh_)) return bad_at(*e);
      got = next_chunk("BASE", tag, payload, "VARI");
      if (!got) return got.status();
    }
    if (*got && tag == "VARI") {
      if (auto e = parse_variants(payload, mesh_)) return bad_at(*e);
      DYNPM_RETURN_IF_ERROR(apply_variant_of_limits());
      got = next_chunk("BASE", tag, payload);
      if (!got) return got.status();
    }
    if (!*got) return fail(chunk_start_, "the file ends before the base mesh is complete");
    DYNPM_RETURN_IF_ERROR(parse_base(payload));
    const bool fields = !mesh_.fields.empty();
    decode_fields_ = fields && limits_.fields;
    if (decode_fields_) wanted_splits_ = UINT32_MAX, error_ = -1;  // their peaks need every split
    field_models_.emplace(mesh_.fields.size(), mesh_.step_count());
    if (error_ < 0) {  // the splits to read are known: the q-values' room taken at once
      // At most a split per bit of the file left for each step read (a real file spends a byte
      // or more on a split's step): a header's counts alone reserve no more than that.
      const uint64_t plausible = uint64_t{bytes_.size() - pos_} * 8 / std::max<uint64_t>(steps_, 1);
      const uint64_t splits =
          std::min<uint64_t>({mesh_.full_split_count, wanted_splits_, plausible});
      q_->reserve(steps_, static_cast<uint32_t>(mesh_.base_vertex_count + splits));
    }
    if (fields) {
      pending_faces_ = mesh_.base_face_count;  // the base FLDS: no split, the base faces
      DYNPM_RETURN_IF_ERROR(expect_chunk("FLDS", payload, "the FLDS of the base mesh"));
      if (decode_fields_) {
        if (auto e = parse_base_field_values(payload, mesh_)) return bad_at(*e);
      }
    }
    for (;;) {
      if (enough_splits()) break;
      got = next_chunk("SPLT", tag, payload);
      if (!got) return got.status();
      if (!*got) {  // a prefix: keep what has arrived
        mesh_.complete = false, mesh_.prefix = true;
        break;
      }
      if (tag == "END ") {
        if (mesh_.split_count() != mesh_.full_split_count)
          return fail(chunk_start_, "END after " + std::to_string(mesh_.split_count()) + " of " +
                                        std::to_string(mesh_.full_split_count) + " splits");
        if (pos_ != bytes_.size()) return fail(pos_, "bytes after the END chunk");
        break;
      }
      const uint32_t first = mesh_.split_count(), faces_before = records_->face_count();
      DYNPM_RETURN_IF_ERROR(parse_splits(std::move(payload)));
      if (!fields) continue;
      // A SPLT and its FLDS are one unit: a file that ends in the FLDS holds the levels before.
      pending_splits_ = mesh_.split_count() - first;
      pending_faces_ = records_->face_count() - faces_before;
      got = next_chunk("FLDS", tag, payload);
      if (!got) return got.status();
      if (!*got) {
        truncate(first, faces_before);
        mesh_.complete = false, mesh_.prefix = true;
        break;
      }
      if (!decode_fields_) continue;
      if (auto e = parse_split_field_values(
              payload, mesh_, {first, mesh_.split_count(), faces_before, records_->face_count()},
              deferred_->stencils, *field_models_, steps_))
        return bad_at(*e);
    }
    DYNPM_RETURN_IF_ERROR(flush_positions());
    for (size_t t = 0; t < steps_; ++t) q_->move_to_positions(mesh_, t, mesh_.base_vertex_count);
    drop_steps_not_asked();
    if (fields && !decode_fields_) {  // checked, not decoded: not in the result
      mesh_.fields.clear();
      mesh_.face_heir.clear();
    }
    return std::move(mesh_);
  }

  // Decodes the SPLT positions kept for later, if any; the first problem they had, kept.
  Status flush_positions() {
    const std::string problem = deferred_ ? deferred_->decode(mesh_, *models_, *q_) : "";
    if (!problem.empty()) positions_problem_ = fail(deferred_->payload_start, problem);
    deferred_.reset();
    return positions_problem_;
  }

  // What DpmReadLimits asks of this file, once HEAD has given its counts.
  void apply_limits_of_head() {
    const ProgressiveMesh& m = mesh_;
    if (limits_.vertices || limits_.ratio) wanted_splits_ = splits_for_limits(m, limits_);
    if (limits_.error) error_ = *limits_.error * (limits_.error_of_diagonal ? m.diagonal() : 1.0);
    steps_ = m.times.size();
    if (limits_.last_step) steps_ = std::min(steps_, *limits_.last_step + 1);
    mesh_.steps_read = steps_;
  }

  // The stored steps the variant asked for needs (DpmReadLimits::variant), once VARI is read:
  // those up to the last stored step of its steps up to last_step.
  Status apply_variant_of_limits() {
    if (!limits_.variant) return {};
    auto index = find_variant(mesh_, *limits_.variant);
    if (!index) return Status::error(name_ + ": " + index.message());
    const std::vector<uint32_t>& steps = mesh_.variants[*index].steps;
    const size_t count =
        limits_.last_step ? std::min(steps.size(), *limits_.last_step + 1) : steps.size();
    steps_ = size_t{*std::max_element(steps.begin(), steps.begin() + count)} + 1;
    mesh_.steps_read = steps_;
    return {};
  }

  // Whether the splits read so far reach the level asked for; if they do, the splits beyond it
  // are dropped and reading stops (the file after them is never touched).
  bool enough_splits() {
    const ProgressiveMesh& m = mesh_;
    uint32_t k = m.split_count();
    if (k == m.full_split_count) return false;  // the whole stream: read on to END
    if (error_ >= 0) {
      if (m.level_error(k) > error_) return false;
      while (k > 0 && m.level_error(k - 1) <= error_) --k;  // the coarsest such level
    } else if (k < wanted_splits_) {
      return false;
    } else {
      k = wanted_splits_;
    }
    if (k < m.split_count()) truncate(k, m.face_count_after(k));
    mesh_.complete = false;
    mesh_.limited = true;
    return true;
  }

  // Positions of the steps not asked for were never decoded; their field values go too.
  void drop_steps_not_asked() {
    if (steps_ == mesh_.times.size()) return;
    for (size_t t = steps_; t < mesh_.times.size(); ++t) {
      std::vector<float>().swap(mesh_.positions[t]);  // freed: `= {}` keeps the capacity
      for (ProgressiveField& f : mesh_.fields) std::vector<float>().swap(f.values[t]);
    }
    mesh_.complete = false;
    mesh_.limited = true;
  }

  Status fail(size_t at, const std::string& what) const {
    return Status::error(name_ + ": byte " + std::to_string(at) + ": " + what);
  }

  // A problem inside a payload, found by dpm_read_fields.cpp.
  Status bad_at(const PayloadError& e) const {
    return fail(payload_start_,
                e.what + " (at byte " + std::to_string(e.offset) + " of the chunk's data)");
  }

  // What a chunk's 24 header bytes say, checked before its payload is looked at (the browser's
  // decoder checks them as they arrive, in this order). `expected`: HEAD, BASE, FLDS, or SPLT
  // (which END may end); `optional`: chunks that may come instead, as "FDEF|PART" (before BASE). An
  // unknown chunk after HEAD is checked as an optional one, to be skipped.
  Status check_chunk_header(std::string_view expected, std::string_view optional,
                            const std::string& tag, uint32_t flags, uint32_t stored, uint32_t raw,
                            uint32_t reserved) const {
    const size_t at = pos_;
    const bool unknown = !is_known_tag(tag);
    if (unknown && !is_optional_tag(tag))
      return fail(at,
                  "unknown chunk tag (not HEAD, FDEF, BASE, FLDS, SPLT, END or four of A-Z, "
                  "0-9 and space)");
    if (unknown && expected == "HEAD")
      return fail(at, "expected the HEAD chunk, found '" + tag + "'");
    if (!unknown && expected != "SPLT" && tag != expected &&
        (optional.empty() || optional.find(tag) == std::string_view::npos))
      return fail(at, "expected the " + std::string(expected) + " chunk, found '" + tag + "'");
    if (!unknown && expected == "SPLT" && tag != "SPLT" && tag != "END ")
      return fail(at, "unexpected chunk '" + tag + "'");
    if (flags > 1) return fail(at + 4, "unknown chunk flags " + std::to_string(flags));
    if (reserved != 0) return fail(at + 20, "the chunk's reserved field is not 0");
    if (stored > kMaxRawChunk)
      return fail(at + 8, "the chunk's stored size " + std::to_string(stored) + " is above 2^31");
    if (flags == 0 && raw != stored) return fail(at + 12, "an uncompressed chunk's sizes differ");
    if (flags == 1 && (tag == "HEAD" || tag == "END "))
      return fail(at + 4, "a compressed " + tag + " chunk (only BASE, SPLT, FDEF and FLDS may be)");
    if (tag == "END " && raw != 0) return fail(at + 12, "the END chunk is not empty");
    if (tag == "HEAD" || tag == "END ") return {};
    // Before any allocation: what the chunk says it holds against what it can hold.
    const double limit = std::min(payload_limit(tag), double(kMaxRawChunk));
    if (raw > limit)
      return fail(at + 12, "the " + tag + " chunk claims " + std::to_string(raw) +
                               " bytes; the header's counts allow at most " +
                               std::to_string(uint64_t(limit)));
    if (flags == 1 && raw > uint64_t{stored} * kMaxZstdRatio)
      return fail(at + 12, "the " + tag + " chunk claims " + std::to_string(raw) +
                               " bytes, more than " + std::to_string(stored) +
                               " compressed bytes can hold");
    return {};
  }

  // The next chunk that is not an unknown optional one (those are checked and skipped). false:
  // the file ends inside a chunk (a prefix).
  Result<bool> next_chunk(std::string_view expected, std::string& tag, std::string& payload,
                          std::string_view optional = {}) {
    for (;;) {
      auto got = one_chunk(expected, optional, tag, payload);
      if (!got || !*got || is_known_tag(tag)) return got;
    }
  }

  Result<bool> one_chunk(std::string_view expected, std::string_view optional, std::string& tag,
                         std::string& payload) {
    chunk_start_ = pos_;
    if (bytes_.size() - pos_ < kChunkHeaderSize) return false;
    ByteReader h(bytes_.substr(pos_, kChunkHeaderSize));
    tag.assign(bytes_.substr(pos_, 4));
    h.get<uint32_t>();
    const uint32_t flags = h.get<uint32_t>();
    const uint32_t stored = h.get<uint32_t>();
    const uint32_t raw = h.get<uint32_t>();
    const uint32_t crc = h.get<uint32_t>();
    const uint32_t reserved = h.get<uint32_t>();
    DYNPM_RETURN_IF_ERROR(
        check_chunk_header(expected, optional, tag, flags, stored, raw, reserved));
    if (bytes_.size() - pos_ - kChunkHeaderSize < stored) return false;
    const std::string_view body = bytes_.substr(pos_ + kChunkHeaderSize, stored);
    if (crc32(body) != crc)
      return fail(pos_, tag + " chunk checksum mismatch (the file is damaged)");
    if (!is_known_tag(tag)) {  // an optional chunk this reader does not know: skipped
      pos_ += kChunkHeaderSize + stored;
      return true;
    }
    if (flags == 0) {
      payload.assign(body);
    } else {
      const unsigned long long content = ZSTD_getFrameContentSize(body.data(), body.size());
      if (content != raw)
        return fail(pos_ + kChunkHeaderSize, "compressed chunk size does not match its header");
      if (std::string why = inflate(body, raw, payload); !why.empty())
        return fail(pos_ + kChunkHeaderSize, "cannot decompress the " + tag + " chunk: " + why);
    }
    payload_start_ = pos_ + kChunkHeaderSize;
    pos_ += kChunkHeaderSize + stored;
    return true;
  }

  // The most bytes a BASE or SPLT payload can take for the counts in HEAD, each value at the
  // longest encoding the reader accepts (docs/FORMAT.md), its section headers included. A split's
  // moved faces are bounded only by the face count, which makes the SPLT bound loose but still a
  // bound. An FLDS: its BASE's or SPLT's counts; FDEF and optional chunks: 2^31.
  double payload_limit(std::string_view tag) const {
    const ProgressiveMesh& m = mesh_;
    if (tag == "FLDS")
      return field_values_limit(m, pending_splits_, records_->face_count() - pending_faces_,
                                records_->face_count());
    const double steps = double(m.times.size());
    const double per_vertex = 2 * kMaxVarint + steps * 3 * kMaxVarint;
    const double per_face_attributes = 3 * kMaxVarint;
    if (tag == "BASE")
      return m.base_vertex_count * per_vertex +
             m.base_face_count * (1 + 4 * kMaxVarint + per_face_attributes);
    if (tag != "SPLT") return double(kMaxRawChunk);
    const double splits = double(m.full_split_count) - double(m.split_count());
    const double per_record =
        kMaxVarint + 4 + 1 + 4 * (1 + 2 * kMaxVarint) + kMaxVarint + kMaxVarint * m.full_face_count;
    const double per_attributes = 2 * kMaxVarint + 4 * per_face_attributes;
    // A range-coded integer takes at most kMaxCodedInteger bytes; a section adds its 5 flushed.
    const double per_positions = steps * 3 * kMaxCodedInteger;
    return 12 + 4 * (2 + steps) + 5 * (2 + steps) +
           splits * (per_record + per_attributes + per_positions);
  }

  Status expect_chunk(const char* tag, std::string& payload, const char* what) {
    std::string got;
    auto ok = next_chunk(tag, got, payload);
    if (!ok) return ok.status();
    if (!*ok)
      return fail(chunk_start_, std::string("the file ends before ") + what + " is complete");
    return {};
  }

  Status bad(const ByteReader& r, const std::string& what) const {
    return fail(payload_start_,
                what + " (at byte " + std::to_string(r.offset()) + " of the chunk's data)");
  }

  Status parse_head(std::string_view payload) {
    ByteReader r(payload);
    ProgressiveMesh& m = mesh_;
    m.full_vertex_count = r.get<uint32_t>();
    m.full_face_count = r.get<uint32_t>();
    m.base_vertex_count = r.get<uint32_t>();
    m.base_face_count = r.get<uint32_t>();
    m.full_split_count = r.get<uint32_t>();
    const uint32_t steps = r.get<uint32_t>();
    const uint32_t fields = r.get<uint32_t>();
    const uint32_t flags = r.get<uint32_t>();
    for (double& x : m.bbox_min) x = r.get<double>();
    for (double& x : m.bbox_max) x = r.get<double>();
    m.quant_step = r.get<double>();
    m.max_error = r.get<double>();
    m.base_error = r.get<double>();
    if (!r.ok()) return bad(r, "the header is too short");
    // Each split brings back at most 4 faces (its triangle wings).
    if (m.base_vertex_count > m.full_vertex_count || m.base_face_count > m.full_face_count ||
        m.full_split_count != m.full_vertex_count - m.base_vertex_count ||
        m.full_face_count - m.base_face_count > uint64_t{4} * m.full_split_count)
      return bad(r, "the header's counts do not add up");
    if (steps == 0 || !r.can_hold(steps, 8)) return bad(r, "the header's step count is not valid");
    if (flags > 1) return bad(r, "unknown header flags");
    m.lossless = flags == 1;
    for (double x : m.bbox_min)
      if (!std::isfinite(x)) return bad(r, "the bounding box is not finite");
    for (double x : m.bbox_max)
      if (!std::isfinite(x)) return bad(r, "the bounding box is not finite");
    if (!m.lossless && !(m.quant_step > 0 && std::isfinite(m.quant_step)))
      return bad(r, "the quantization step is not valid");
    // The writer keeps the grid at least 4 float32 ulps at the box's largest coordinate
    // (FORMAT.md "Positions"), so that positions survive float32 and the predictions made from
    // them are the grid's integers; a finer grid is refused, as the browser's decoder does.
    double largest = 0;
    for (int k = 0; k < 3; ++k)
      largest = std::max({largest, std::abs(m.bbox_min[k]), std::abs(m.bbox_max[k])});
    if (!m.lossless && m.quant_step < 4 * largest * std::ldexp(1.0, -23))
      return bad(r, "the quantization step is finer than float32 holds in the bounding box");
    if (!(std::isfinite(m.max_error) && m.max_error >= 0 && m.base_error >= 0 &&
          m.base_error <= kMaxBaseError))
      return bad(r, "the header's error bounds are not finite numbers ≥ 0 (base error ≤ 2^1000)");
    m.times.resize(steps);
    for (double& t : m.times) t = r.get<double>();
    for (double t : m.times)
      if (!std::isfinite(t)) return bad(r, "a step's time is not finite");
    const uint32_t keys = r.get<uint32_t>();
    if (!r.can_hold(keys, 4)) return bad(r, "the key-step count is not valid");
    for (uint32_t k = 0; k < keys; ++k) m.key_steps.push_back(r.get<uint32_t>());
    if (fields != 0)
      return bad(r, "the header lists fields (written by an older dynpm: build it again)");
    m.note = r.text();
    if (!r.ok()) return bad(r, "the header is too short");
    if (r.remaining() != 0) return bad(r, "unexpected bytes after the header");
    m.positions.resize(steps);
    models_.emplace(steps);
    q_.emplace(grid_of(m), steps);
    return {};
  }

  Status read_vertex_attributes(ByteReader& r, uint32_t count) {
    for (uint32_t k = 0; k < count; ++k) {
      const bool index = add_base_delta(d_.vertex_index, r.svarint(), 0, mesh_.full_vertex_count);
      if (!add_base_delta(d_.node_id, r.svarint()) || !index)
        return bad(r, index ? kIdOutOfRange : "a vertex's original index is out of range");
      mesh_.vertex_original_index.push_back(static_cast<uint32_t>(d_.vertex_index));
      mesh_.node_ids.push_back(d_.node_id);
    }
    return r.ok() ? Status{} : bad(r, "vertex attributes are cut short");
  }

  Status read_face_attributes(ByteReader& r, uint32_t count) {
    for (uint32_t k = 0; k < count; ++k) {
      const int64_t part = r.svarint();
      const bool id = add_base_delta(d_.element_id, r.svarint());
      const bool index = add_base_delta(d_.face_index, r.svarint(), 0, mesh_.full_face_count);
      if (part < INT32_MIN || part > INT32_MAX) return bad(r, "a part id is out of range");
      if (!index) return bad(r, "a face's original index is out of range");
      if (!id) return bad(r, kIdOutOfRange);
      mesh_.part_ids.push_back(static_cast<int32_t>(part));
      mesh_.element_ids.push_back(d_.element_id);
      mesh_.face_original_index.push_back(static_cast<uint32_t>(d_.face_index));
    }
    return r.ok() ? Status{} : bad(r, "face attributes are cut short");
  }

  // The base vertices' positions [begin, end) of the steps asked for (svarints, as version 1).
  Status read_positions(ByteReader& r, uint32_t begin, uint32_t end) {
    const size_t steps = steps_;
    if (!r.can_hold(uint64_t{end - begin} * steps * 3, 1)) return bad(r, "positions are cut short");
    const Grid g = grid_of(mesh_);
    // A quantized position lies in the bounding box, give or take two grid steps.
    std::array<double, 3> top{};
    for (int c = 0; c < 3; ++c) top[c] = (mesh_.bbox_max[c] - mesh_.bbox_min[c]) / g.step + 2;
    for (size_t t = 0; t < steps; ++t) mesh_.positions[t].resize(size_t{end} * 3);
    for (size_t t = 0; t < steps; ++t)
      for (uint32_t v = begin; v < end; ++v)
        for (int c = 0; c < 3; ++c) {
          const auto known = [&](uint32_t u, size_t s) {
            return g.q(mesh_.positions[s][size_t{u} * 3 + c], c);
          };
          const int64_t residual = r.svarint(), q = g.add(predict_base(v, t, known), residual);
          if (g.lossless ? !residual_fits(residual, true) : q < -2 || double(q) > top[c])
            return bad(
                r, g.lossless ? kLosslessResidual : "a position is far outside the bounding box");
          mesh_.positions[t][size_t{v} * 3 + c] = g.p(q, c);
        }
    return r.ok() ? Status{} : bad(r, "positions are cut short");
  }

  Status parse_base(std::string_view payload) {
    ByteReader r(payload);
    ProgressiveMesh& m = mesh_;
    if (!r.can_hold(m.base_vertex_count, 2) || !r.can_hold(m.base_face_count, 4))
      return bad(r, "the base mesh is shorter than its counts");
    DYNPM_RETURN_IF_ERROR(read_vertex_attributes(r, m.base_vertex_count));
    m.base_faces.resize(m.base_face_count);
    for (Face& face : m.base_faces) {
      const uint8_t degree = r.get<uint8_t>();
      if (degree != 3 && degree != 4)
        return bad(r, "a base face has " + std::to_string(degree) + " corners");
      for (int c = 0; c < degree; ++c) {
        const uint64_t v = r.varint();
        if (v >= m.base_vertex_count) return bad(r, "a base face's corner is out of range");
        face.v[c] = static_cast<uint32_t>(v);
      }
      for (int a = 0; a < degree; ++a)
        for (int b = a + 1; b < degree; ++b)
          if (face.v[a] == face.v[b]) return bad(r, "a base face repeats a corner");
    }
    DYNPM_RETURN_IF_ERROR(read_face_attributes(r, m.base_face_count));
    DYNPM_RETURN_IF_ERROR(read_positions(r, 0, m.base_vertex_count));
    q_->take(m, steps_, 0, m.base_vertex_count);
    if (r.remaining() != 0 && steps_ == mesh_.times.size())
      return bad(r, "unexpected bytes after the base mesh");
    records_.emplace(m);
    return {};
  }

  Status parse_splits(std::string payload_bytes) {
    const std::string_view payload = payload_bytes;
    ByteReader r(payload);
    ProgressiveMesh& m = mesh_;
    const uint32_t first = r.get<uint32_t>();
    const uint32_t n = r.get<uint32_t>();
    if (!r.ok() || first != m.split_count())
      return bad(r, "splits out of order (expected split " + std::to_string(m.split_count()) + ")");
    if (n == 0 || n > m.full_split_count - first) return bad(r, "the split count is not valid");
    // The sections: records, attributes, then the positions of each step (FORMAT.md).
    const uint32_t sections = r.get<uint32_t>();
    if (!r.ok() || sections != 2 + m.step_count())
      return bad(r, "the SPLT does not have 2 + " + std::to_string(m.step_count()) + " sections");
    std::vector<uint64_t> sizes(sections);
    uint64_t total = 0;
    for (uint64_t& size : sizes) total += size = r.get<uint32_t>();
    if (!r.ok() || total != r.remaining())
      return bad(r, "the SPLT's section sizes do not add up to its payload");
    DeferredPositions next;  // of the steps asked for; the later steps' are not decoded
    next.first = first, next.payload_start = payload_start_;
    for (size_t k = 0, at = r.offset(); k < sections; at += sizes[k++])
      if (k < 2 + steps_) next.sections.emplace_back(at, sizes[k]);
    // The records, checked and applied as decoded; the faces after each split give its stencil.
    // Beside them the last SPLT's positions (they write only q_, read only m's header values).
    std::optional<PayloadError> e;
    const auto records = next.sections[0], attributes = next.sections[1];  // clang: no bindings
    parallel_for(2, 2, thread_count(0), [&](size_t part, size_t, size_t) {
      if (part == 1) return void(flush_positions());
      e = decode_split_records(payload.substr(records.first, records.second),
                               payload.substr(attributes.first, attributes.second), first, n, m,
                               *records_,
                               [&](uint32_t i) { next.stencils.add(m, i, records_->faces()); });
    });
    DYNPM_RETURN_IF_ERROR(positions_problem_);
    if (e) return bad_at({e->what, records.first + e->offset});
    q_->resize(steps_, m.base_vertex_count + first + n);  // positions: at the end (run())
    next.sections.erase(next.sections.begin(), next.sections.begin() + 2);
    next.payload = std::move(payload_bytes);
    deferred_ = std::move(next);
    return {};
  }

  // Back to the levels before split `splits`, which had `faces` faces (a prefix, or a limit).
  void truncate(uint32_t splits, uint32_t faces) {
    flush_positions();  // a problem in them is kept, and returned before the mesh
    ProgressiveMesh& m = mesh_;
    const uint32_t vertices = m.base_vertex_count + splits;
    m.parent.resize(splits);
    m.error.resize(splits);
    m.wings.resize(m.wing_start[splits]);
    m.wing_start.resize(splits + 1);
    m.moved_faces.resize(m.moved_start[splits]);
    m.moved_start.resize(splits + 1);
    m.vertex_original_index.resize(vertices);
    m.node_ids.resize(vertices);
    m.face_original_index.resize(faces);
    m.part_ids.resize(faces);
    m.element_ids.resize(faces);
    q_->resize(steps_, vertices);
    if (!m.face_heir.empty()) m.face_heir.resize(faces);
    for (ProgressiveField& f : m.fields) {
      if (f.error.size() > splits) f.error.resize(splits);
      const size_t items = f.info.location == FieldLocation::kElement ? faces : vertices;
      for (auto& values : f.values)
        if (values.size() > items) values.resize(items);
    }
  }

  std::string_view bytes_;
  std::string name_;
  DpmReadLimits limits_;
  uint32_t wanted_splits_ = UINT32_MAX;  // the level asked for as a split count
  double error_ = -1;                    // the level asked for as an absolute error (≥ 0)
  bool decode_fields_ = false;
  size_t steps_ = 0;  // the steps whose positions are decoded: 0 … steps_ − 1
  size_t pos_ = 0, chunk_start_ = 0, payload_start_ = 0;
  ProgressiveMesh mesh_;
  Deltas d_;
  std::optional<SplitPositionModels> models_;     // sized by HEAD's step count
  std::optional<GridValues> q_;                   // the decoded positions' q-values
  std::optional<RecordModels> records_;           // the records' models and the decode-time replay
  std::optional<DeferredPositions> deferred_;     // the last SPLT's positions, not yet decoded
  std::optional<SplitFieldModels> field_models_;  // the fields' models, SPLT to SPLT
  Status positions_problem_;                      // the first problem in them
  // The last SPLT's split and face counts, for the size of the FLDS that follows it.
  uint32_t pending_splits_ = 0, pending_faces_ = 0;
};

}  // namespace

bool looks_like_dpm(std::string_view head) { return head.substr(0, kMagic.size()) == kMagic; }

uint32_t splits_for_limits(const ProgressiveMesh& mesh, const DpmReadLimits& limits) {
  double vertices = mesh.full_vertex_count;
  if (limits.vertices)
    vertices = *limits.vertices;
  else if (limits.ratio)
    vertices = std::round(*limits.ratio * mesh.full_vertex_count);
  vertices = std::clamp(vertices, double(mesh.base_vertex_count), double(mesh.full_vertex_count));
  return static_cast<uint32_t>(vertices) - mesh.base_vertex_count;
}

Result<ProgressiveMesh> decode_dpm(std::string_view bytes, const std::string& name,
                                   const DpmReadLimits& limits) {
  return Decoder(bytes, name, limits).run();
}

Result<ProgressiveMesh> read_dpm(const std::string& path, const DpmReadLimits& limits) {
  auto file = MappedFile::open(path);  // pages after the last chunk needed are never read
  if (!file) return file.status();
  return decode_dpm(file->bytes(), path, limits);
}

}  // namespace dynpm
