// The .dpm file: docs/FORMAT.md is the specification; this file follows it section by section.
#include <zstd.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

#include "bytes.h"
#include "dynpm/progressive.h"

namespace dynpm {
namespace {

using progressive::ByteReader;
using progressive::ByteWriter;

constexpr std::string_view kMagic{
    "\x89"
    "DPM\r\n\x1a\n",
    8};
constexpr uint32_t kVersion = 1;
constexpr size_t kChunkHeaderSize = 24;
constexpr uint32_t kFirstChunkSplits = 256;
constexpr uint32_t kMaxChunkSplits = 16384;
constexpr int kZstdLevel = 12;
// Bounds on a chunk's decompressed size, so that a corrupt header cannot ask for more memory
// than real content of that size would need.
constexpr uint64_t kMaxRawChunk = uint64_t{1} << 31;
constexpr uint64_t kMaxQuantized = uint64_t{1} << 31;
// zstd's densest block is an RLE block: 4 bytes (header and the byte) for at most 128 KiB, so no
// frame decompresses to more than 32768 times its size.
constexpr uint64_t kMaxZstdRatio = 32768;
// The longest varint the reader takes (ByteReader::varint: 64 bits, 7 per byte).
constexpr double kMaxVarint = 10;

uint32_t crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

void put_chunk(std::string& out, std::string_view tag, std::string_view raw, bool compress) {
  std::string stored;
  if (compress) {
    stored.resize(ZSTD_compressBound(raw.size()));
    const size_t n =
        ZSTD_compress(stored.data(), stored.size(), raw.data(), raw.size(), kZstdLevel);
    stored.resize(ZSTD_isError(n) ? 0 : n);
    if (ZSTD_isError(n)) compress = false;
  }
  if (!compress) stored.assign(raw);
  ByteWriter h;
  h.bytes.append(tag);
  h.put<uint32_t>(compress ? 1u : 0u);
  h.put<uint32_t>(static_cast<uint32_t>(stored.size()));
  h.put<uint32_t>(static_cast<uint32_t>(raw.size()));
  h.put<uint32_t>(crc32(stored));
  h.put<uint32_t>(0);
  out += h.bytes;
  out += stored;
}

struct DStreamFree {
  void operator()(ZSTD_DStream* d) const { ZSTD_freeDStream(d); }
};

// One zstd frame that must hold exactly `raw` bytes, decompressed into `out` as it arrives: the
// buffer grows with what the frame really produces, so a frame that claims more than it holds
// costs only what it holds. Empty on success, else what is wrong.
std::string inflate(std::string_view frame, uint64_t raw, std::string& out) {
  std::unique_ptr<ZSTD_DStream, DStreamFree> stream(ZSTD_createDStream());
  if (!stream || ZSTD_isError(ZSTD_initDStream(stream.get()))) return "no memory for zstd";
  ZSTD_inBuffer in{frame.data(), frame.size(), 0};
  out.clear();
  size_t produced = 0;
  char spill;  // where output beyond `raw` would go: any is an error
  for (;;) {
    if (produced == out.size() && out.size() < raw)
      out.resize(std::min<uint64_t>(raw, std::max<uint64_t>(2 * out.size(), 1 << 20)));
    const bool full = produced == out.size();
    ZSTD_outBuffer o{full ? &spill : out.data() + produced, full ? 1 : out.size() - produced, 0};
    const size_t consumed = in.pos;
    const size_t left = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(left)) return ZSTD_getErrorName(left);
    if (full && o.pos > 0) return "it holds more bytes than its header says";
    produced += o.pos;
    if (left == 0) break;  // the frame is complete
    if (o.pos == 0 && in.pos == consumed) return "the frame is cut short";
  }
  if (produced != raw) return "it holds fewer bytes than its header says";
  if (in.pos != in.size) return "bytes after its zstd frame";
  return {};
}

// Position q-values (docs/FORMAT.md "Positions"): grid integers, or float bits when lossless.
struct Grid {
  std::array<double, 3> origin;
  double step;
  bool lossless;

  int64_t q(float p, int c) const {
    if (lossless) return std::bit_cast<uint32_t>(p);
    return std::llround((p - origin[c]) / step);
  }
  float p(int64_t q, int c) const {
    if (lossless) return std::bit_cast<float>(static_cast<uint32_t>(q));
    return static_cast<float>(origin[c] + static_cast<double>(q) * step);
  }
  // Residual → value, wrapping modulo 2^32 when lossless.
  int64_t add(int64_t prediction, int64_t residual) const {
    const uint64_t sum = static_cast<uint64_t>(prediction) + static_cast<uint64_t>(residual);
    return lossless ? static_cast<int64_t>(static_cast<uint32_t>(sum)) : static_cast<int64_t>(sum);
  }
  int64_t residual(int64_t value, int64_t prediction) const {
    const uint64_t diff = static_cast<uint64_t>(value) - static_cast<uint64_t>(prediction);
    return lossless ? static_cast<int32_t>(static_cast<uint32_t>(diff))
                    : static_cast<int64_t>(diff);
  }
};

Grid grid_of(const ProgressiveMesh& mesh) {
  return {mesh.bbox_min, mesh.quant_step, mesh.lossless};
}

// The prediction of vertex v's coordinate c at step t from values already known.
int64_t predict(const ProgressiveMesh& mesh, const Grid& g, uint32_t v, size_t t, int c) {
  auto q = [&](uint32_t u, size_t s) { return g.q(mesh.positions[s][size_t{u} * 3 + c], c); };
  if (v < mesh.base_vertex_count) {
    if (t > 0) return q(v, t - 1);
    return v > 0 ? q(v - 1, 0) : 0;
  }
  const uint32_t p = mesh.parent[v - mesh.base_vertex_count];
  if (t == 0) return q(p, 0);
  return g.add(q(v, t - 1), g.residual(q(p, t), q(p, t - 1)));
}

void write_positions(ByteWriter& w, const ProgressiveMesh& mesh, uint32_t begin, uint32_t end) {
  const Grid g = grid_of(mesh);
  for (size_t t = 0; t < mesh.step_count(); ++t)
    for (uint32_t v = begin; v < end; ++v)
      for (int c = 0; c < 3; ++c)
        w.svarint(
            g.residual(g.q(mesh.positions[t][size_t{v} * 3 + c], c), predict(mesh, g, v, t, c)));
  for (const auto& field : mesh.fields)
    for (const auto& values : field)
      for (uint32_t v = begin; v < end; ++v) w.put<float>(values[v]);
}

// Attribute deltas continue across chunks (docs/FORMAT.md).
struct Deltas {
  int64_t vertex_index = 0, node_id = 0, element_id = 0, face_index = 0;
};

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

std::string head_payload(const ProgressiveMesh& mesh) {
  ByteWriter w;
  w.put<uint32_t>(mesh.full_vertex_count);
  w.put<uint32_t>(mesh.full_face_count);
  w.put<uint32_t>(mesh.base_vertex_count);
  w.put<uint32_t>(mesh.base_face_count);
  w.put<uint32_t>(mesh.full_split_count);
  w.put<uint32_t>(static_cast<uint32_t>(mesh.step_count()));
  w.put<uint32_t>(static_cast<uint32_t>(mesh.field_names.size()));
  w.put<uint32_t>(mesh.lossless ? 1u : 0u);
  for (double x : mesh.bbox_min) w.put<double>(x);
  for (double x : mesh.bbox_max) w.put<double>(x);
  w.put<double>(mesh.quant_step);
  w.put<double>(mesh.max_error);
  w.put<double>(mesh.base_error);
  for (double t : mesh.times) w.put<double>(t);
  w.put<uint32_t>(static_cast<uint32_t>(mesh.key_steps.size()));
  for (size_t k : mesh.key_steps) w.put<uint32_t>(static_cast<uint32_t>(k));
  for (const std::string& name : mesh.field_names) w.text(name);
  w.text(mesh.note);
  return std::move(w.bytes);
}

}  // namespace

bool looks_like_dpm(std::string_view head) { return head.substr(0, kMagic.size()) == kMagic; }

std::string encode_dpm(const ProgressiveMesh& mesh) {
  std::string out(kMagic);
  ByteWriter version;
  version.put<uint32_t>(kVersion);
  out += version.bytes;
  put_chunk(out, "HEAD", head_payload(mesh), false);

  Deltas d;
  {
    ByteWriter w;
    for (uint32_t v = 0; v < mesh.base_vertex_count; ++v) write_vertex_attributes(w, mesh, v, d);
    for (const Face& face : mesh.base_faces) {
      w.put<uint8_t>(static_cast<uint8_t>(face.degree()));
      for (int c = 0; c < face.degree(); ++c) w.varint(face.v[c]);
    }
    for (uint32_t f = 0; f < mesh.base_face_count; ++f) write_face_attributes(w, mesh, f, d);
    write_positions(w, mesh, 0, mesh.base_vertex_count);
    put_chunk(out, "BASE", w.bytes, true);
  }

  uint32_t face_count = mesh.base_face_count;
  uint32_t chunk = kFirstChunkSplits;
  for (uint32_t first = 0; first < mesh.split_count();
       first += chunk, chunk = std::min(chunk * 2, kMaxChunkSplits)) {
    const uint32_t last = std::min(mesh.split_count(), first + chunk);
    ByteWriter w;
    w.put<uint32_t>(first);
    w.put<uint32_t>(last - first);
    const uint32_t first_face = face_count;
    for (uint32_t i = first; i < last; ++i) {
      const uint32_t v0 = mesh.base_vertex_count + i;
      w.varint(v0 - 1 - mesh.parent[i]);
      w.put<float>(mesh.error[i]);
      w.put<uint8_t>(static_cast<uint8_t>(mesh.wing_start[i + 1] - mesh.wing_start[i]));
      uint32_t created = 0;
      for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
        const SplitWing& wing = mesh.wings[k];
        w.put<uint8_t>(wing.flags);
        w.varint(v0 - 1 - wing.vertex);
        if (wing.was_triangle())
          ++created;
        else
          w.varint(face_count - 1 - wing.face);
      }
      w.varint(mesh.moved_start[i + 1] - mesh.moved_start[i]);
      for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
        w.varint(face_count - 1 - mesh.moved_faces[m]);
      face_count += created;
    }
    for (uint32_t i = first; i < last; ++i)
      write_vertex_attributes(w, mesh, mesh.base_vertex_count + i, d);
    for (uint32_t f = first_face; f < face_count; ++f) write_face_attributes(w, mesh, f, d);
    write_positions(w, mesh, mesh.base_vertex_count + first, mesh.base_vertex_count + last);
    put_chunk(out, "SPLT", w.bytes, true);
  }
  put_chunk(out, "END ", {}, false);
  return out;
}

Status write_dpm(const std::string& path, const ProgressiveMesh& mesh) {
  if (!mesh.complete) return Status::error(path + ": cannot write a partial progressive mesh");
  return write_file_atomically(path, encode_dpm(mesh));
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

class Decoder {
 public:
  Decoder(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  Result<ProgressiveMesh> run() {
    if (bytes_.size() < kMagic.size() + 4 || !looks_like_dpm(bytes_))
      return fail(0, "not a .dpm file (no DPM signature)");
    uint32_t version;
    std::memcpy(&version, bytes_.data() + kMagic.size(), 4);
    if (version != kVersion)
      return fail(kMagic.size(), "version " + std::to_string(version) +
                                     " is not supported (this dynpm reads version 1)");
    pos_ = kMagic.size() + 4;

    std::string payload;
    DYNPM_RETURN_IF_ERROR(expect_chunk("HEAD", payload, "the header"));
    DYNPM_RETURN_IF_ERROR(parse_head(payload));
    DYNPM_RETURN_IF_ERROR(expect_chunk("BASE", payload, "the base mesh"));
    DYNPM_RETURN_IF_ERROR(parse_base(payload));
    for (;;) {
      std::string tag;
      auto got = next_chunk(tag, payload);
      if (!got) return got.status();
      if (!*got) {  // a prefix: keep what has arrived
        mesh_.complete = false;
        break;
      }
      if (tag == "END ") {
        if (mesh_.split_count() != mesh_.full_split_count)
          return fail(chunk_start_, "END after " + std::to_string(mesh_.split_count()) + " of " +
                                        std::to_string(mesh_.full_split_count) + " splits");
        if (pos_ != bytes_.size()) return fail(pos_, "bytes after the END chunk");
        break;
      }
      if (tag != "SPLT") return fail(chunk_start_, "unexpected chunk '" + tag + "'");
      DYNPM_RETURN_IF_ERROR(parse_splits(payload));
    }
    return std::move(mesh_);
  }

 private:
  Status fail(size_t at, const std::string& what) const {
    return Status::error(name_ + ": byte " + std::to_string(at) + ": " + what);
  }

  // false: the file ends inside this chunk (a prefix).
  Result<bool> next_chunk(std::string& tag, std::string& payload) {
    chunk_start_ = pos_;
    if (bytes_.size() - pos_ < kChunkHeaderSize) return false;
    ByteReader h(bytes_.substr(pos_, kChunkHeaderSize));
    tag.assign(bytes_.substr(pos_, 4));
    h.get<uint32_t>();
    const uint32_t flags = h.get<uint32_t>();
    const uint32_t stored = h.get<uint32_t>();
    const uint32_t raw = h.get<uint32_t>();
    const uint32_t crc = h.get<uint32_t>();
    if (tag != "HEAD" && tag != "BASE" && tag != "SPLT" && tag != "END ")
      return fail(pos_, "unknown chunk tag (not HEAD, BASE, SPLT or END)");
    if (flags > 1) return fail(pos_ + 4, "unknown chunk flags " + std::to_string(flags));
    if (bytes_.size() - pos_ - kChunkHeaderSize < stored) return false;
    const std::string_view body = bytes_.substr(pos_ + kChunkHeaderSize, stored);
    if (crc32(body) != crc)
      return fail(pos_, tag + " chunk checksum mismatch (the file is damaged)");
    if (flags == 0) {
      if (raw != stored) return fail(pos_ + 12, "an uncompressed chunk's sizes differ");
      payload.assign(body);
    } else {
      // Before any allocation: what the chunk says it holds against what it can hold.
      if (tag == "HEAD" || tag == "END ")
        return fail(pos_ + 4, "a compressed " + tag + " chunk (only BASE and SPLT may be)");
      const double limit = std::min(payload_limit(tag), double(kMaxRawChunk));
      if (raw > limit)
        return fail(pos_ + 12, "the " + tag + " chunk claims " + std::to_string(raw) +
                                   " bytes; the header's counts allow at most " +
                                   std::to_string(uint64_t(limit)));
      if (raw > uint64_t{stored} * kMaxZstdRatio)
        return fail(pos_ + 12, "the " + tag + " chunk claims " + std::to_string(raw) +
                                   " bytes, more than " + std::to_string(stored) +
                                   " compressed bytes can hold");
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
  // longest encoding the reader accepts (docs/FORMAT.md). A split's moved faces are bounded only
  // by the face count, which makes the SPLT bound loose but still a bound.
  double payload_limit(const std::string& tag) const {
    const ProgressiveMesh& m = mesh_;
    const double steps = double(m.times.size()), fields = double(m.field_names.size());
    const double per_vertex = 2 * kMaxVarint + steps * (3 * kMaxVarint + 4 * fields);
    const double per_face_attributes = 3 * kMaxVarint;
    if (tag == "BASE")
      return m.base_vertex_count * per_vertex +
             m.base_face_count * (1 + 4 * kMaxVarint + per_face_attributes);
    if (tag != "SPLT") return 0;
    const double splits = double(m.full_split_count) - double(m.split_count());
    const double per_split = kMaxVarint + 4 + 1 + 4 * (1 + 2 * kMaxVarint) + kMaxVarint +
                             kMaxVarint * m.full_face_count + per_vertex + 4 * per_face_attributes;
    return 8 + splits * per_split;
  }

  Status expect_chunk(const char* tag, std::string& payload, const char* what) {
    std::string got;
    auto ok = next_chunk(got, payload);
    if (!ok) return ok.status();
    if (!*ok)
      return fail(chunk_start_, std::string("the file ends before ") + what + " is complete");
    if (got != tag)
      return fail(chunk_start_, std::string("expected the ") + tag + " chunk, found '" + got + "'");
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
    if (!(std::isfinite(m.max_error) && m.max_error >= 0 && std::isfinite(m.base_error) &&
          m.base_error >= 0))
      return bad(r, "the header's error bounds are not finite numbers ≥ 0");
    m.times.resize(steps);
    for (double& t : m.times) t = r.get<double>();
    for (double t : m.times)
      if (!std::isfinite(t)) return bad(r, "a step's time is not finite");
    const uint32_t keys = r.get<uint32_t>();
    if (!r.can_hold(keys, 4)) return bad(r, "the key-step count is not valid");
    for (uint32_t k = 0; k < keys; ++k) m.key_steps.push_back(r.get<uint32_t>());
    if (!r.can_hold(fields, 2)) return bad(r, "the field count is not valid");
    for (uint32_t f = 0; f < fields; ++f) m.field_names.push_back(r.text());
    m.note = r.text();
    if (!r.ok()) return bad(r, "the header is too short");
    if (uint64_t{fields} * steps > (uint64_t{1} << 24)) return bad(r, "too many fields × steps");
    // Field values come with vertices: a model without base vertices has none (its splits
    // cannot apply either, each needs a parent).
    if (fields > 0 && m.base_vertex_count == 0)
      return bad(r, "fields are declared for a model without base vertices");
    m.positions.resize(steps);
    return {};
  }

  Status read_vertex_attributes(ByteReader& r, uint32_t count) {
    for (uint32_t k = 0; k < count; ++k) {
      d_.vertex_index += r.svarint();
      d_.node_id += r.svarint();
      if (d_.vertex_index < 0 || d_.vertex_index >= mesh_.full_vertex_count)
        return bad(r, "a vertex's original index is out of range");
      mesh_.vertex_original_index.push_back(static_cast<uint32_t>(d_.vertex_index));
      mesh_.node_ids.push_back(d_.node_id);
    }
    return r.ok() ? Status{} : bad(r, "vertex attributes are cut short");
  }

  Status read_face_attributes(ByteReader& r, uint32_t count) {
    for (uint32_t k = 0; k < count; ++k) {
      const int64_t part = r.svarint();
      d_.element_id += r.svarint();
      d_.face_index += r.svarint();
      if (part < INT32_MIN || part > INT32_MAX) return bad(r, "a part id is out of range");
      if (d_.face_index < 0 || d_.face_index >= mesh_.full_face_count)
        return bad(r, "a face's original index is out of range");
      mesh_.part_ids.push_back(static_cast<int32_t>(part));
      mesh_.element_ids.push_back(d_.element_id);
      mesh_.face_original_index.push_back(static_cast<uint32_t>(d_.face_index));
    }
    return r.ok() ? Status{} : bad(r, "face attributes are cut short");
  }

  Status read_positions(ByteReader& r, uint32_t begin, uint32_t end) {
    const size_t steps = mesh_.step_count();
    if (!r.can_hold(uint64_t{end - begin} * steps * 3, 1)) return bad(r, "positions are cut short");
    const Grid g = grid_of(mesh_);
    for (auto& xyz : mesh_.positions) xyz.resize(size_t{end} * 3);
    for (size_t t = 0; t < steps; ++t)
      for (uint32_t v = begin; v < end; ++v)
        for (int c = 0; c < 3; ++c) {
          const int64_t q = g.add(predict(mesh_, g, v, t, c), r.svarint());
          if (!g.lossless && (q < -int64_t(kMaxQuantized) || q > int64_t(kMaxQuantized)))
            return bad(r, "a position is far outside the bounding box");
          mesh_.positions[t][size_t{v} * 3 + c] = g.p(q, c);
        }
    if (!r.can_hold(uint64_t{end - begin} * steps * mesh_.field_names.size(), 4))
      return bad(r, "field values are cut short");
    // Allocated once the base mesh's values have arrived, which proves they are in the file.
    if (mesh_.fields.size() != mesh_.field_names.size())
      mesh_.fields.assign(mesh_.field_names.size(), std::vector<std::vector<float>>(steps));
    for (auto& field : mesh_.fields)
      for (auto& values : field) {
        values.resize(end);
        for (uint32_t v = begin; v < end; ++v) values[v] = r.get<float>();
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
    if (r.remaining() != 0) return bad(r, "unexpected bytes after the base mesh");
    faces_ = m.base_faces;
    face_count_ = m.base_face_count;
    return {};
  }

  Status parse_splits(std::string_view payload) {
    ByteReader r(payload);
    ProgressiveMesh& m = mesh_;
    const uint32_t first = r.get<uint32_t>();
    const uint32_t n = r.get<uint32_t>();
    if (!r.ok() || first != m.split_count())
      return bad(r, "splits out of order (expected split " + std::to_string(m.split_count()) + ")");
    if (n == 0 || n > m.full_split_count - first || !r.can_hold(n, 7))
      return bad(r, "the split count is not valid");
    uint32_t face_count = face_count_;
    for (uint32_t i = first; i < first + n; ++i) {
      const uint32_t v0 = m.base_vertex_count + i;
      const uint64_t parent_delta = r.varint();
      if (parent_delta >= v0) return bad(r, "split " + std::to_string(i) + ": parent out of range");
      m.parent.push_back(static_cast<uint32_t>(v0 - 1 - parent_delta));
      const float error = r.get<float>();
      if (!std::isfinite(error) || error < 0)
        return bad(r, "split " + std::to_string(i) + ": error is not valid");
      m.error.push_back(error);
      const uint8_t wings = r.get<uint8_t>();
      if (wings > 4) return bad(r, "split " + std::to_string(i) + ": more than 4 wings");
      uint32_t created = 0;
      for (uint8_t k = 0; k < wings; ++k) {
        SplitWing w;
        w.flags = r.get<uint8_t>();
        if (w.flags >> 4) return bad(r, "split " + std::to_string(i) + ": unknown wing flags");
        const uint64_t dv = r.varint();
        if (dv >= v0) return bad(r, "split " + std::to_string(i) + ": wing vertex out of range");
        w.vertex = static_cast<uint32_t>(v0 - 1 - dv);
        if (w.was_triangle()) {
          w.face = face_count + created++;
        } else {
          const uint64_t df = r.varint();
          if (df >= face_count)
            return bad(r, "split " + std::to_string(i) + ": wing face out of range");
          w.face = static_cast<uint32_t>(face_count - 1 - df);
        }
        m.wings.push_back(w);
      }
      m.wing_start.push_back(static_cast<uint32_t>(m.wings.size()));
      const uint64_t moved = r.varint();
      if (!r.can_hold(moved, 1))
        return bad(r, "split " + std::to_string(i) + ": moved faces cut short");
      for (uint64_t k = 0; k < moved; ++k) {
        const uint64_t df = r.varint();
        if (df >= face_count)
          return bad(r, "split " + std::to_string(i) + ": moved face out of range");
        m.moved_faces.push_back(static_cast<uint32_t>(face_count - 1 - df));
      }
      m.moved_start.push_back(static_cast<uint32_t>(m.moved_faces.size()));
      if (!r.ok()) return bad(r, "split records are cut short");
      face_count += created;
    }
    if (face_count > m.full_face_count)
      return bad(r, "splits create more faces than the header says");
    DYNPM_RETURN_IF_ERROR(read_vertex_attributes(r, n));
    DYNPM_RETURN_IF_ERROR(read_face_attributes(r, face_count - face_count_));
    DYNPM_RETURN_IF_ERROR(
        read_positions(r, m.base_vertex_count + first, m.base_vertex_count + first + n));
    if (r.remaining() != 0) return bad(r, "unexpected bytes after the splits");
    // Replay the splits on the faces: a record that does not fit is an error here, so the
    // navigator can apply them unchecked.
    faces_.resize(face_count);
    for (uint32_t i = first; i < first + n; ++i) {
      std::string problem;
      if (!apply_split(m, i, faces_, face_count_, &problem)) return fail(payload_start_, problem);
    }
    return {};
  }

  std::string_view bytes_;
  std::string name_;
  size_t pos_ = 0, chunk_start_ = 0, payload_start_ = 0;
  ProgressiveMesh mesh_;
  Deltas d_;
  std::vector<Face> faces_;  // the decode-time replay
  uint32_t face_count_ = 0;
};

}  // namespace

Result<ProgressiveMesh> decode_dpm(std::string_view bytes, const std::string& name) {
  return Decoder(bytes, name).run();
}

Result<ProgressiveMesh> read_dpm(const std::string& path) {
  auto bytes = read_file(path);
  if (!bytes) return bytes.status();
  return decode_dpm(*bytes, path);
}

}  // namespace dynpm
