// split_records_dump IN.dpm [OUT.json]: the compact split records of a .dpm's splits, measured
// against version 1's records (varints and f32 errors, zstd level 12 per chunk), with decode
// speeds; and, with OUT.json, the sections and the arrays they must decode to, for the browser
// decoder's test (viewer/test/split_records.test.mjs).
#include <zstd.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>

#include "dynpm/progressive.h"
#include "progressive/bytes.h"
#include "progressive/split_records_coding.h"
#include "split_records_base.h"

using namespace dynpm;
using namespace dynpm::progressive;

namespace {

struct Chunk {
  uint32_t first, count;
  std::string records, attributes;          // version 2
  std::string old_records, old_attributes;  // version 1, zstd-compressed
};

std::string zstd(const std::string& raw) {
  std::string out(ZSTD_compressBound(raw.size()), '\0');
  out.resize(ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 12));
  return out;
}

// Version 1's SPLT records and attributes of splits [first, last) (dpm_write.cpp before).
void old_chunk(const ProgressiveMesh& m, Chunk& c, uint32_t& face_count, int64_t (&d)[4]) {
  ByteWriter r, a;
  const uint32_t first_face = face_count;
  for (uint32_t i = c.first; i < c.first + c.count; ++i) {
    const uint32_t v0 = m.base_vertex_count + i;
    r.varint(v0 - 1 - m.parent[i]);
    r.put<float>(m.error[i]);
    r.put<uint8_t>(static_cast<uint8_t>(m.wing_start[i + 1] - m.wing_start[i]));
    uint32_t created = 0;
    for (uint32_t k = m.wing_start[i]; k < m.wing_start[i + 1]; ++k) {
      r.put<uint8_t>(m.wings[k].flags);
      r.varint(v0 - 1 - m.wings[k].vertex);
      if (m.wings[k].was_triangle())
        ++created;
      else
        r.varint(face_count - 1 - m.wings[k].face);
    }
    r.varint(m.moved_start[i + 1] - m.moved_start[i]);
    for (uint32_t k = m.moved_start[i]; k < m.moved_start[i + 1]; ++k)
      r.varint(face_count - 1 - m.moved_faces[k]);
    face_count += created;
  }
  for (uint32_t v = m.base_vertex_count + c.first; v < m.base_vertex_count + c.first + c.count;
       ++v) {
    a.svarint(int64_t{m.vertex_original_index[v]} - d[0]);
    a.svarint(m.node_ids[v] - d[1]);
    d[0] = m.vertex_original_index[v], d[1] = m.node_ids[v];
  }
  for (uint32_t f = first_face; f < face_count; ++f) {
    a.svarint(m.part_ids[f]);
    a.svarint(m.element_ids[f] - d[2]);
    a.svarint(int64_t{m.face_original_index[f]} - d[3]);
    d[2] = m.element_ids[f], d[3] = m.face_original_index[f];
  }
  c.old_records = zstd(r.bytes);
  c.old_attributes = zstd(a.bytes);
}

// Version 1's decode of the records alone: inflate, parse, replay on the faces (dpm_read.cpp).
double old_decode_seconds(const ProgressiveMesh& m, const std::vector<Chunk>& chunks) {
  const std::clock_t start = std::clock();  // CPU time: the machine may be shared
  std::vector<Face> faces = m.base_faces;
  faces.resize(m.full_face_count);
  uint32_t face_count = m.base_face_count;
  ProgressiveMesh d = m;  // only its split arrays are rebuilt
  d.parent.clear(), d.error.clear(), d.wings.clear(), d.moved_faces.clear();
  d.wing_start = {0}, d.moved_start = {0};
  for (const Chunk& c : chunks) {
    std::string raw(ZSTD_getFrameContentSize(c.old_records.data(), c.old_records.size()), '\0');
    ZSTD_decompress(raw.data(), raw.size(), c.old_records.data(), c.old_records.size());
    ByteReader r(raw);
    uint32_t fc = face_count;
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      const uint32_t v0 = m.base_vertex_count + i;
      d.parent.push_back(static_cast<uint32_t>(v0 - 1 - r.varint()));
      d.error.push_back(r.get<float>());
      const uint8_t wings = r.get<uint8_t>();
      uint32_t created = 0;
      for (uint8_t k = 0; k < wings; ++k) {
        SplitWing w;
        w.flags = r.get<uint8_t>();
        w.vertex = static_cast<uint32_t>(v0 - 1 - r.varint());
        w.face = w.was_triangle() ? fc + created++ : static_cast<uint32_t>(fc - 1 - r.varint());
        d.wings.push_back(w);
      }
      d.wing_start.push_back(static_cast<uint32_t>(d.wings.size()));
      for (uint64_t k = r.varint(); k > 0; --k)
        d.moved_faces.push_back(static_cast<uint32_t>(fc - 1 - r.varint()));
      d.moved_start.push_back(static_cast<uint32_t>(d.moved_faces.size()));
      fc += created;
    }
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      std::string problem;
      if (!apply_split(d, i, faces, face_count, &problem))
        std::fprintf(stderr, "%s\n", problem.c_str());
    }
  }
  return double(std::clock() - start) / CLOCKS_PER_SEC;
}

std::string base64(const std::string& s) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < s.size(); i += 3) {
    uint32_t n = uint32_t(uint8_t(s[i])) << 16;
    if (i + 1 < s.size()) n |= uint32_t(uint8_t(s[i + 1])) << 8;
    if (i + 2 < s.size()) n |= uint8_t(s[i + 2]);
    out += k[n >> 18], out += k[(n >> 12) & 63];
    out += i + 1 < s.size() ? k[(n >> 6) & 63] : '=';
    out += i + 2 < s.size() ? k[n & 63] : '=';
  }
  return out;
}

template <class V, class F>
void array(std::ofstream& o, const char* name, const V& v, F f) {
  o << "\"" << name << "\":[";
  for (size_t k = 0; k < v.size(); ++k) o << (k ? "," : "") << f(v[k]);
  o << "],\n";
}

void write_json(const std::string& path, const ProgressiveMesh& m,
                const std::vector<Chunk>& chunks) {
  std::ofstream o(path);
  o.precision(17);
  auto same = [](auto x) { return x; };
  o << "{\"baseError\":" << m.base_error << ",\"vertexCount\":" << m.full_vertex_count
    << ",\"faceCount\":" << m.full_face_count << ",\"baseVertexCount\":" << m.base_vertex_count
    << ",\"baseFaceCount\":" << m.base_face_count << ",\"splitCount\":" << m.split_count() << ",\n";
  std::vector<int64_t> corners;
  for (const Face& f : m.base_faces)
    for (uint32_t v : f.v) corners.push_back(v == kNoVertex ? -1 : int64_t{v});
  array(o, "baseCorners", corners, same);
  array(o, "parent", m.parent, same);
  array(o, "error", m.error, [](float e) { return double(e); });
  array(o, "wingStart", m.wing_start, same);
  array(o, "wingFace", m.wings, [](const SplitWing& w) { return w.face; });
  array(o, "wingVertex", m.wings, [](const SplitWing& w) { return w.vertex; });
  array(o, "wingFlags", m.wings, [](const SplitWing& w) { return int(w.flags); });
  array(o, "movedStart", m.moved_start, same);
  array(o, "movedFaces", m.moved_faces, same);
  array(o, "vertexOriginal", m.vertex_original_index, same);
  array(o, "nodeId", m.node_ids, same);
  array(o, "faceOriginal", m.face_original_index, same);
  array(o, "partId", m.part_ids, same);
  array(o, "elementId", m.element_ids, same);
  o << "\"chunks\":[";
  for (size_t k = 0; k < chunks.size(); ++k)
    o << (k ? ",\n" : "") << "{\"first\":" << chunks[k].first << ",\"count\":" << chunks[k].count
      << ",\"records\":\"" << base64(chunks[k].records) << "\",\"attributes\":\""
      << base64(chunks[k].attributes) << "\"}";
  o << "]}\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: split_records_dump IN.dpm [OUT.json]\n");
    return 2;
  }
  auto read = read_dpm(argv[1]);
  if (!read.ok()) {
    std::fprintf(stderr, "%s\n", read.message().c_str());
    return 1;
  }
  ProgressiveMesh pm = std::move(read).value();
  prepare_split_records(pm);

  std::vector<Chunk> chunks;
  RecordModels models(pm);
  uint32_t face_count = pm.base_face_count;
  int64_t deltas[4] = {0, 0, 0, 0};
  {  // version 1's attribute deltas continue from the base mesh's last ones
    const uint32_t b = pm.base_vertex_count, f = pm.base_face_count;
    if (b) deltas[0] = pm.vertex_original_index[b - 1], deltas[1] = pm.node_ids[b - 1];
    if (f) deltas[2] = pm.element_ids[f - 1], deltas[3] = pm.face_original_index[f - 1];
  }
  for (uint32_t first = 0, n = 256; first < pm.split_count();
       first += n, n = std::min(2 * n, 16384u)) {
    Chunk c{first, std::min(pm.split_count(), first + n) - first, {}, {}, {}, {}};
    auto s = encode_split_records(pm, first, first + c.count, models, {});
    if (!s.ok()) {
      std::fprintf(stderr, "%s\n", s.message().c_str());
      return 1;
    }
    c.records = s->first, c.attributes = s->second;
    old_chunk(pm, c, face_count, deltas);
    chunks.push_back(std::move(c));
  }
  size_t rec = 0, attr = 0, old_rec = 0, old_attr = 0;
  for (const Chunk& c : chunks)
    rec += c.records.size(), attr += c.attributes.size(), old_rec += c.old_records.size(),
        old_attr += c.old_attributes.size();
  const double V = pm.full_vertex_count;
  std::printf("%s: V %u, splits %u, steps %zu\n", argv[1], pm.full_vertex_count, pm.split_count(),
              pm.step_count());
  std::printf("B/vertex  v1 (zstd): records %.2f attributes %.2f total %.2f\n", old_rec / V,
              old_attr / V, (old_rec + old_attr) / V);
  std::printf("B/vertex  range-coded: records %.3f attributes %.3f total %.3f\n", rec / V, attr / V,
              (rec + attr) / V);
  auto parts = split_record_part_bytes(pm);
  if (parts.ok()) {
    std::printf("parts B/vertex:");
    for (int p = 0; p < kRecordParts; ++p)
      std::printf("%s %s %.3f", p ? "," : "", kRecordPartNames[p], (*parts)[p] / V);
    // The groups of docs/BENCHMARKS.md's table: parent / wings / moved / errors / ids.
    auto sum = [&](int from, int to) {
      size_t bytes = 0;
      for (int p = from; p < to; ++p) bytes += (*parts)[p];
      return bytes / V;
    };
    std::printf(
        "\ngroups B/vertex: parent %.3f wings %.3f moved %.3f errors %.3f vertex ids %.3f"
        " face ids %.3f\n",
        sum(0, 1), sum(1, 7), sum(7, 8), sum(8, 9), sum(9, 11), sum(11, 14));
  }
  // Decode speeds: the records (and v2's attributes) into the arrays, each split replayed.
  const double old_s = old_decode_seconds(pm, chunks);
  ProgressiveMesh back = test::base_level_of(pm);
  const std::clock_t start = std::clock();  // CPU time: the machine may be shared
  RecordModels decode_models(back);
  for (const Chunk& c : chunks)
    if (auto e = decode_split_records(c.records, c.attributes, c.first, c.count, back,
                                      decode_models, {})) {
      std::fprintf(stderr, "decode: %s\n", e->what.c_str());
      return 1;
    }
  const double new_s = double(std::clock() - start) / CLOCKS_PER_SEC;
  std::printf("decode: v1 records %.2f M splits/s, v2 records+attributes %.2f M splits/s\n",
              pm.split_count() / old_s / 1e6, pm.split_count() / new_s / 1e6);
  if (back.parent != pm.parent || back.moved_faces != pm.moved_faces ||
      back.node_ids != pm.node_ids || back.element_ids != pm.element_ids) {
    std::fprintf(stderr, "decode: arrays differ\n");
    return 1;
  }
  if (argc > 2) write_json(argv[2], pm, chunks);
  return 0;
}
