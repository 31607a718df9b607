// The C++ reader's verdict on many .dpm files in one process, for viewer/test/conformance.test.mjs
// (a dynpm process per file would take minutes on a thousand mutants):
//   dpm_verdicts FILE...
// prints one line per file: "error <message>", or "counts" and the counts `dynpm info --json`
// prints, as name=value pairs, then field_list=NAME:LOCATION:COUNT,… (each field's name with
// bytes other than A-Z a-z 0-9 _ . - as %XX, node or element, its values per step present; empty
// without fields), then part_list=ID:NAME,… (the PART chunk's names, escaped alike), then
// selective=V/F/Q,… (the selective navigator's active mesh on three closed sets of splits:
// selective_counts()), then values=HASH@T (values_hash()). Test-only; reads with read_dpm() as
// `dynpm info` does.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "dynpm/lod.h"
#include "dynpm/progressive.h"

namespace {

std::string escaped(const std::string& name) {
  std::string out;
  for (unsigned char c : name) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
        c == '.' || c == '-') {
      out += char(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

// Vertices, faces and quads of the selective navigator's mesh for every other split (closed
// under the face creators' dependencies), the first half of the splits, and the last split with
// what it needs: out of stream order on any file the reader accepts, damaged ones too.
std::string selective_counts(const dynpm::ProgressiveMesh& m) {
  using namespace dynpm;
  const uint32_t n = m.split_count();
  const SplitDependencies deps = derive_split_dependencies(m);
  SelectiveNavigator nav(m, deps);
  std::vector<uint8_t> wanted(n, 0);
  std::vector<uint32_t> stack;
  std::string out;
  auto show = [&] {
    nav.set_active(wanted);
    const SelectiveMesh shown = nav.active_mesh();
    out += (out.empty() ? "" : ",") + std::to_string(shown.vertices.size()) + "/" +
           std::to_string(shown.faces.size()) + "/" + std::to_string(shown.topology.quad_count());
  };
  for (uint32_t i = 0; i < n; ++i) wanted[i] = i % 2;
  close_under_dependencies(deps, wanted);
  show();
  std::fill(wanted.begin(), wanted.end(), uint8_t{0});
  std::fill_n(wanted.begin(), n / 2, uint8_t{1});
  show();
  std::fill(wanted.begin(), wanted.end(), uint8_t{0});
  if (n > 0) add_with_dependencies(deps, wanted, n - 1, stack);
  show();
  return out;
}

// FNV-1a over the bytes of `values` as stored (little-endian float bits; ids as their int64
// bytes, in pairs of words).
uint32_t fnv1a(uint32_t hash, std::span<const float> values) {
  for (float v : values) {
    const uint32_t word = std::bit_cast<uint32_t>(v);
    for (int k = 0; k < 4; ++k) hash = (hash ^ ((word >> (8 * k)) & 0xff)) * 16777619u;
  }
  return hash;
}

// What the file decodes to at its last step T: a hash of every present vertex's position (in
// progressive order), then of each field's values, then of the node and element ids (int64
// little-endian), as hex, "@T"; "-" without steps.
std::string values_hash(const dynpm::ProgressiveMesh& m) {
  if (m.positions.empty()) return "-";
  const size_t t = m.positions.size() - 1;
  uint32_t hash = fnv1a(2166136261u, m.positions[t]);
  for (const dynpm::ProgressiveField& f : m.fields)
    if (t < f.values.size()) hash = fnv1a(hash, f.values[t]);
  for (const auto* ids : {&m.node_ids, &m.element_ids})
    hash = fnv1a(hash, std::span(reinterpret_cast<const float*>(ids->data()), ids->size() * 2));
  char hex[16];
  std::snprintf(hex, sizeof hex, "%08x", hash);
  return std::string(hex) + "@" + std::to_string(t);
}

// The message on one line: a name it quotes may hold any byte, and a line break in it would give
// the next files' verdicts to the wrong files (it did: differential fuzzing, 2026-12-06).
std::string one_line(const std::string& message) {
  std::string out;
  for (char c : message)
    out += c == '\n' ? std::string("\\n") : c == '\r' ? std::string("\\r") : std::string(1, c);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynpm;
  for (int i = 1; i < argc; ++i) {
    auto mesh = read_dpm(argv[i]);
    if (!mesh) {
      std::printf("error %s\n", one_line(mesh.message()).c_str());
      continue;
    }
    const ProgressiveMesh& m = *mesh;
    Navigator nav(m);
    nav.set_level(m.split_count());
    const Topology full = nav.topology();
    std::printf(
        "counts complete=%d vertices=%u faces=%u vertices_present=%u faces_present=%zu "
        "quads_present=%zu triangles_present=%zu base_vertices=%u base_faces=%u splits=%u "
        "steps=%zu key_steps=%zu fields=%zu parts=%zu lossless=%d",
        m.complete, m.full_vertex_count, m.full_face_count, m.vertex_count(), full.faces.size(),
        full.quad_count(), full.triangle_count(), m.base_vertex_count, m.base_face_count,
        m.split_count(), m.step_count(), m.key_steps.size(), m.fields.size(), full.parts().size(),
        m.lossless);
    std::string list;
    for (const ProgressiveField& f : m.fields)
      list += (list.empty() ? "" : ",") + escaped(f.info.name) + ":" + to_string(f.info.location) +
              ":" + std::to_string(f.values.empty() ? 0 : f.values[0].size());
    std::printf(" field_list=%s", list.c_str());
    std::string parts;
    for (const PartName& p : m.part_names)
      parts += (parts.empty() ? "" : ",") + std::to_string(p.id) + ":" + escaped(p.name);
    std::printf(" part_list=%s selective=%s values=%s\n", parts.c_str(),
                selective_counts(m).c_str(), values_hash(m).c_str());
  }
  return 0;
}
