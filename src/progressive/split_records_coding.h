// The records and attributes sections of a SPLT (docs/FORMAT.md "Split records", "Split
// attributes"): everything a split brings that is not a position, range-coded relative to the
// mesh as the earlier splits left it. The decoder applies each split as it decodes it, keeping
// every vertex's faces, so that
//   a quad wing is an index into its parent's triangles, and a bit for its wing vertex,
//   a triangle wing's vertex an index into the parent's neighbours, those on the frontier
//   between the moved faces and the others first (rarely: an escape),
//   the moved faces a bit per face of the parent,
//   the error a step down a grid of 16 values per octave,
//   ids and original indices a difference from those of the split's neighbourhood.
// The browser's twin is viewer/src/dpm/split_records.js. Internal to dynpm_progressive.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/list_pool.h"
#include "core/prefetch.h"
#include "dpm_read_fields.h"    // PayloadError
#include "dynpm/progressive.h"  // prepare_split_records()
#include "index_sets.h"
#include "range_coder.h"

namespace dynpm::progressive {

// Split errors on the file's grid (docs/FORMAT.md "Split records"): code 0 is 0, code c ≥ 1 is
// P · (16 + (c−1) mod 16) · 2^((c−1) div 16 − 44), P the reference (the power of two at or above
// HEAD's base_error). Exact in f64 and f32, so both decoders get the same floats.
inline constexpr uint32_t kErrorStepsPerOctave = 16;
inline constexpr uint32_t kErrorOctaves = 40;
inline constexpr uint32_t kTopErrorCode = kErrorStepsPerOctave * kErrorOctaves + 1;  // value P
// HEAD's base_error is at most 2^1000 (FORMAT.md "HEAD"): the grid needs a power of two P ≥ it,
// times 31, to be finite.
inline constexpr double kMaxBaseError = 0x1p1000;
double error_reference(double base_error);
float error_of_code(uint32_t code, double reference);
// The smallest code whose value is ≥ e (kTopErrorCode when none is below it).
uint32_t error_code_at_least(double e, double reference);

// The models of both sections, continued from one SPLT to the next, and the mesh as the splits
// so far left it (the faces and each vertex's faces in ascending order): the encoder and the
// decoder keep the same one. Made from the base mesh; the caller keeps it across chunks.
class RecordModels {
 public:
  // kFull: room for the full mesh from the start (the encoder's; a file's header is not trusted
  // that far), kGrow: growing as the splits come.
  enum class Room { kGrow, kFull };
  explicit RecordModels(const ProgressiveMesh& base, Room room = Room::kGrow);

  // The faces after the splits coded so far (face_count() of them); apply_split() checked them.
  const std::vector<Face>& faces() const { return faces_; }
  uint32_t face_count() const { return face_count_; }

  // Records.
  UnsignedModel parent, wing_count, quad_face, neighbour, far_vertex, error_step;
  std::array<BitModel, 48> was_triangle{};  // by candidates, wing count and wing number
  BitModel quad_side, quad_slot_end, quad_follows;
  std::array<BitModel, 2> tri_follows{};  // no face to predict from / one
  std::array<BitModel, 2> tri_slot{};     // slot 0? then slot 1 or 2
  std::array<BitModel, 12> moved{};  // triangle? × beside a moved face? × moved so far (0, 1, 2+)
  SignedModel parent_step;
  // Attributes.
  SignedModel vertex_index, node_id, part, face_index, element_id;
  BitModel same_part;

  // The encoder knows the parents to come: their fans and faces are asked for ahead of split i
  // (ListPool::prefetch_ahead()).
  void prefetch_fans_ahead(const ProgressiveMesh& mesh, uint32_t i, uint32_t last) const {
    vertex_faces_.prefetch_ahead(std::span(mesh.parent).first(last), i, 4, [&](uint32_t f) {
      if (f < faces_.size()) prefetch(&faces_[f]);
    });
  }

  // The mesh (internal to the coding).
  std::vector<Face> faces_;
  uint32_t face_count_ = 0;
  ListPool vertex_faces_;  // per vertex: its faces, ascending
  VertexMarks near_v0_;    // the corners of the faces the current split moved so far
  FreeIndices free_vertices_, free_faces_;  // original indices not yet given
  double error_reference_ = 1;
  uint32_t error_code_ = kTopErrorCode;  // the last split's (first: the base's)
  uint32_t last_parent_ = kNoVertex;     // the last split's
  // Lists a split's coding fills, kept between splits for their memory (a million splits
  // would otherwise allocate and free several lists each).
  struct Scratch {
    std::vector<uint32_t> moved, quads, triangles, beside, near, rest;
    std::vector<uint32_t> edge_ends, edge_uses, used;  // MovedFan's
  } scratch_;
};

// Called after split i was applied to models.faces(): the positions' stencils are read there.
using AfterSplit = std::function<void(uint32_t i)>;

// Which sections encode_split_records() codes. The two have models of their own: two walks,
// each with RecordModels of its own, give the bytes of one walk that codes both, and can run on
// two threads.
enum class SplitSections { kBoth, kRecords, kAttributes };

// The records and attributes sections of splits [first, last) of a prepared mesh (a section not
// asked for is empty). An error when a record does not fit the mesh (a bug of the builder, not of
// a file).
Result<std::pair<std::string, std::string>> encode_split_records(
    const ProgressiveMesh& mesh, uint32_t first, uint32_t last, RecordModels& models,
    const AfterSplit& after_split, SplitSections sections = SplitSections::kBoth);

// Decodes splits [first, first + count) from the two sections into mesh's split and attribute
// arrays (parent, error, wing_start, wings, moved_start, moved_faces, vertex_original_index,
// node_ids, face_original_index, part_ids, element_ids), applying each split to
// models.faces() with apply_split()'s checks. mesh holds HEAD's counts, the base mesh and its
// attributes, and the splits before `first`. The problem's offset is 0 (the section's start).
std::optional<PayloadError> decode_split_records(std::string_view records,
                                                 std::string_view attributes, uint32_t first,
                                                 uint32_t count, ProgressiveMesh& mesh,
                                                 RecordModels& models,
                                                 const AfterSplit& after_split);

// Bytes each part of the coding takes over all splits (one stream per part, the same models),
// in the order of kRecordPartNames. For measurements (tests/split_records_dump).
inline constexpr int kRecordParts = 14;
inline constexpr std::array<const char*, kRecordParts> kRecordPartNames = {
    "parent",          "wing count",    "wing kind", "quad wing face", "quad wing bits",
    "triangle vertex", "triangle bits", "moved",     "errors",         "vertex index",
    "node id",         "face index",    "face part", "element id"};
Result<std::array<size_t, kRecordParts>> split_record_part_bytes(const ProgressiveMesh& mesh);

}  // namespace dynpm::progressive
