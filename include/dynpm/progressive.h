// dynpm/progressive.h — the dynamic progressive mesh: a base mesh, a stream of vertex splits,
// positions of every vertex at every time step; and its file, .dpm (docs/FORMAT.md).
//
//   ProgressiveMesh            what build_progressive_mesh() (pipeline.h) makes and read_dpm()
//                              gives back; Navigator (lod.h) shows it at any level and time
//   write_dpm() / read_dpm()   the chunked, checksummed, zstd-compressed file; any prefix of
//                              the file is a coarser animation
//
// The split record (paper §4: vsp(p0, vl, vr, tl, tr)) is, per split: the parent vertex, the
// wings — each a face of the collapsed edge with its wing vertex, whether it was a triangle
// (re-created) or a quad (turned back from a triangle), the orientation and v0's corner slot —
// and the faces that move from the parent to the new vertex (docs/FORMAT.md says why they are
// listed). Half-edge collapses keep positions original, so one position per vertex per step
// serves every level of detail.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dynpm/core.h"

namespace dynpm {

// One wing of a split: a face of the edge (v0, v1) before the collapse.
struct SplitWing {
  uint32_t face = 0;    // a re-created triangle's new face id, or the quad's face id
  uint32_t vertex = 0;  // w: v0's other neighbour in the face
  uint8_t flags = 0;    // kWasTriangle | kV1FollowsV0 | slot << kSlotShift (docs/FORMAT.md)

  static constexpr uint8_t kWasTriangle = 1;
  static constexpr uint8_t kV1FollowsV0 = 2;
  static constexpr int kSlotShift = 2;
  bool was_triangle() const { return (flags & kWasTriangle) != 0; }
  bool v1_follows_v0() const { return (flags & kV1FollowsV0) != 0; }
  int v0_slot() const { return (flags >> kSlotShift) & 3; }
};

// A decoded (or freshly built) progressive animation. Vertex and face arrays are in the
// progressive numbering; a prefix of a file holds the base and the first split_count() splits.
struct ProgressiveMesh {
  // Counts of the complete mesh (what the file promises; a prefix holds fewer splits).
  uint32_t full_vertex_count = 0;
  uint32_t full_face_count = 0;
  uint32_t full_split_count = 0;
  uint32_t base_vertex_count = 0;
  uint32_t base_face_count = 0;

  std::vector<double> times;      // per step
  std::vector<size_t> key_steps;  // the steps that rated the collapses
  std::array<double, 3> bbox_min{}, bbox_max{};
  bool lossless = false;
  double quant_step = 0;  // quantization grid spacing (0: lossless)
  double max_error = 0;   // bound on any stored position's error, absolute
  double base_error = 0;  // simplification error of the base mesh, absolute
  std::string note;       // provenance

  std::vector<Face> base_faces;  // base_face_count faces
  // Splits, structure of arrays: split i creates vertex base_vertex_count + i.
  std::vector<uint32_t> parent;         // per split
  std::vector<float> error;             // per split: error of the mesh right after it
  std::vector<uint32_t> wing_start{0};  // CSR into wings (split_count + 1)
  std::vector<SplitWing> wings;
  std::vector<uint32_t> moved_start{0};  // CSR into moved_faces
  std::vector<uint32_t> moved_faces;

  // Attributes in the progressive numbering (vertices/faces present in this file).
  std::vector<uint32_t> vertex_original_index;  // position in the input's vertex order
  std::vector<int64_t> node_ids;
  std::vector<uint32_t> face_original_index;  // position in the input's face order
  std::vector<int32_t> part_ids;
  std::vector<int64_t> element_ids;

  // positions[t]: xyz of every vertex present, at step t.
  std::vector<std::vector<float>> positions;
  std::vector<std::string> field_names;
  std::vector<std::vector<std::vector<float>>> fields;  // [field][step][vertex]

  bool complete = true;  // false: read from a prefix of a file

  size_t step_count() const { return times.size(); }
  uint32_t split_count() const { return static_cast<uint32_t>(parent.size()); }
  uint32_t vertex_count() const { return base_vertex_count + split_count(); }
  // Faces present after the first k splits.
  uint32_t face_count_after(uint32_t k) const;
  // The error of the level with the first k splits applied.
  double level_error(uint32_t k) const { return k == 0 ? base_error : error[k - 1]; }
  double diagonal() const;
};

// Split i re-creates vertex base_vertex_count + i in `faces`, whose first face_count entries are
// the current faces (the vector holds room for every face of the mesh); undo_split() is its
// inverse. With `problem` set, apply_split() first checks that the record fits the faces and
// returns false with a description instead of changing them (decoders of untrusted files).
bool apply_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                 uint32_t& face_count, std::string* problem = nullptr);
void undo_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                uint32_t& face_count);

// Positions are quantized here (unless lossless), so that what the file holds and what the
// navigator shows agree: call before use when the mesh did not come from read_dpm().
void quantize_positions(ProgressiveMesh& mesh);

// The file (docs/FORMAT.md). Written to a temporary name and renamed.
Status write_dpm(const std::string& path, const ProgressiveMesh& mesh);
std::string encode_dpm(const ProgressiveMesh& mesh);
// Reads a whole file or a prefix of one (then complete == false). Errors name the file and
// byte offset.
Result<ProgressiveMesh> read_dpm(const std::string& path);
Result<ProgressiveMesh> decode_dpm(std::string_view bytes, const std::string& name);
// The magic bytes, for format detection.
bool looks_like_dpm(std::string_view head);

}  // namespace dynpm
