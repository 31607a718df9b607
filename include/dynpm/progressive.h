// dynpm/progressive.h — the dynamic progressive mesh: a base mesh, a stream of vertex splits,
// positions of every vertex at every time step; and its file, .dpm (docs/FORMAT.md).
//
//   ProgressiveMesh            what build_progressive_mesh() (pipeline.h) makes and read_dpm()
//                              gives back; Navigator (lod.h) shows it at any level and time
//   write_dpm() / read_dpm()   the chunked, checksummed, zstd-compressed file; any prefix of
//                              the file is a coarser animation
//
// The split record (paper §4: vsp(p0, vl, vr, tl, tr)) is drawn and defined in split_record.h;
// ProgressiveMesh keeps it as a structure of arrays under the same names. Half-edge collapses keep
// positions original, so one position per vertex per step serves every level of detail.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dynpm/core.h"
#include "dynpm/split_record.h"

namespace dynpm {

// A result field of a progressive mesh (docs/FORMAT.md, "Fields: FDEF and FLDS"): its values
// at every step in the progressive numbering, and how much a level of detail may differ from them.
struct ProgressiveField {
  FieldInfo info;
  double min = 0, max = 0;  // smallest and largest value over every step
  bool lossless = false;
  double quant_step = 0;  // quantization grid spacing (0: lossless)
  double max_error = 0;   // bound on a stored value's error, absolute
  // Field error of a level (the largest spread of the values one present vertex or face stands
  // for, over every step), as a fraction of max − min: the base mesh's, and the level's right
  // after split i. Never increases along the stream.
  float base_error = 0;
  std::vector<float> error;  // #splits
  // values[t]: one value per vertex (node field) or per face (element field) present, at step t.
  std::vector<std::vector<float>> values;

  size_t count_per_step(uint32_t vertices, uint32_t faces) const {
    return info.location == FieldLocation::kElement ? faces : vertices;
  }
};

// How a vertex or face shows the values of the original ones it stands for at a coarse level.
enum class FieldAggregate : uint8_t {
  kMaxAbs,  // the value of largest magnitude, with its sign: a peak is never hidden (default)
  kMean,    // the mean of the values it stands for
};

// One member of a family file (docs/FORMAT.md "Variants: VARI"): variants of one mesh share the
// hierarchy, and each has its own steps, which point into the file's stored steps (a step equal
// in several variants, such as a DOE's undeformed step 0, is stored once).
struct MeshVariant {
  std::string name;             // the input's file name without folder and extension
  std::string source;           // the input's file name, without folder
  std::vector<double> times;    // per step of the variant
  std::vector<uint32_t> steps;  // per step of the variant: the stored step that holds it
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
  // Splits, structure of arrays (the fields are defined in split_record.h): split i creates
  // vertex base_vertex_count + i.
  std::vector<uint32_t> parent;          // #splits: v1, the vertex split i starts from
  std::vector<float> error;              // #splits: error of the mesh right after split i
  std::vector<uint32_t> wing_start{0};   // #splits + 1: split i's wings are [wing_start[i], [i+1])
  std::vector<SplitWing> wings;          // all splits' wings, split after split
  std::vector<uint32_t> moved_start{0};  // #splits + 1: split i's moved faces, as wing_start
  std::vector<uint32_t> moved_faces;     // all splits' moved faces: v1 → v0 when split

  // Attributes in the progressive numbering (vertices/faces present in this file).
  std::vector<uint32_t> vertex_original_index;  // position in the input's vertex order
  std::vector<int64_t> node_ids;
  std::vector<uint32_t> face_original_index;  // position in the input's face order
  std::vector<int32_t> part_ids;
  std::vector<int64_t> element_ids;
  // The parts' names (docs/FORMAT.md "Part names: PART"), ascending id; parts without one are
  // absent, and a file without the PART chunk has none.
  std::vector<PartName> part_names;
  // The variants of a family file, in the order the inputs were given; empty for one model. The
  // steps below are then the stored steps, which select_variant() turns into one variant's.
  std::vector<MeshVariant> variants;

  // positions[t]: xyz of every vertex present, at step t.
  std::vector<std::vector<float>> positions;
  // Result fields, and for each face a split re-creates the face that stands for it while the
  // split is undone (its heir; kNoIndex for base faces). Heirs are set when a field is per element.
  std::vector<ProgressiveField> fields;
  std::vector<uint32_t> face_heir;

  bool complete = true;  // false: read from a prefix of a file, or read with limits
  // The file ended before END while the reader still wanted splits: it holds fewer than it
  // promises (also when read with limits: `limited` may be true as well).
  bool prefix = false;
  // Read with DpmReadLimits: fewer splits than the file holds, or the steps after
  // `steps_read − 1` not decoded (their positions and field values are empty).
  bool limited = false;
  size_t steps_read = 0;

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
// `face_count` is also where the split's re-created triangles go (their progressive face ids
// follow it): out of stream order (SelectiveNavigator, lod.h) the caller passes
// face_count_after(i), so one definition of a split serves both orders.
bool apply_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                 uint32_t& face_count, std::string* problem = nullptr);
void undo_split(const ProgressiveMesh& mesh, uint32_t i, std::span<Face> faces,
                uint32_t& face_count);

// The merges that undoing split i makes in FORMAT.md's "Shown values" pass: merge(into, from)
// for its new vertex into its parent (node fields), or for each face it re-creates, the last
// first, into its heir (element fields). `face_end` is the face count after split i; returns the
// count before it. Navigator::field_values() and the build's field errors walk the same pass.
template <class Merge>
uint32_t merge_undone_split(const ProgressiveMesh& mesh, uint32_t i, bool per_face,
                            uint32_t face_end, Merge&& merge) {
  if (!per_face) {
    merge(mesh.parent[i], mesh.base_vertex_count + i);
    return face_end;
  }
  uint32_t created = 0;
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
    created += mesh.wings[k].was_triangle();
  for (uint32_t g = face_end; g-- > face_end - created;) merge(mesh.face_heir[g], g);
  return face_end - created;
}

// Positions are quantized here (unless lossless), so that what the file holds and what the
// navigator shows agree: call before use when the mesh did not come from read_dpm().
void quantize_positions(ProgressiveMesh& mesh);
// quantize_positions() in two parts, for a caller that streams the steps: the grid (quant_step
// and max_error, from bbox_min, bbox_max and max_error; nothing when lossless), then one step's
// positions onto it.
void set_position_grid(ProgressiveMesh& mesh);
void quantize_step(const ProgressiveMesh& mesh, std::span<float> xyz);

// Rounds the split errors up onto the file's grid (never below the true error, never
// increasing; the base's too) and lists each split's moved faces in ascending order, as the file
// keeps them (docs/FORMAT.md "Split records"): the build applies it with quantize_positions(), so
// the mesh written equals the mesh read.
void prepare_split_records(ProgressiveMesh& mesh);

// Sets each field's grid from `bound` (a fraction of the field's range; docs/FORMAT.md,
// "Fields: FDEF and FLDS") and rounds its values to it, or makes it lossless (float32 exact),
// so that what the file holds and what the navigator shows agree.
void quantize_fields(ProgressiveMesh& mesh, double bound, bool lossless);

// The variant `which` names: its name, or its index from 0 in the order the inputs were given.
// An error lists the variants.
Result<size_t> find_variant(const ProgressiveMesh& mesh, std::string_view which);
// Makes `mesh` the one animation of variant `index` (< variants.size()): its times, its steps'
// positions and field values (shared stored steps copied), its key steps; variants is left empty.
// A mesh read up to a step (DpmReadLimits::last_step and variant) keeps the variant's steps whose
// stored step was read.
void select_variant(ProgressiveMesh& mesh, size_t index);

// The file (docs/FORMAT.md). Written to a temporary name and renamed.
Status write_dpm(const std::string& path, const ProgressiveMesh& mesh);
// An error when the mesh's records do not fit its own faces or were not prepared
// (prepare_split_records): a bug of whoever made the mesh, not of a file. The positions and
// fields are coded on up to `threads` threads (0: one per hardware thread); the bytes do not
// depend on it.
Result<std::string> encode_dpm(const ProgressiveMesh& mesh, unsigned threads = 0);
// encode_dpm() with the positions given one step at a time, so that no caller need hold every
// step's positions ('dynpm build' streams them from its input: docs/build.md). `mesh` holds all
// else (its positions are not read; its grid and bounding box are set, as quantize_positions()
// sets them) and outlives the encoder. The bytes are encode_dpm()'s on any thread count.
class DpmStepEncoder {
 public:
  // The records' chunks, coded before the first step; an error as encode_dpm()'s.
  // `coded_splits`, if set, hears how many splits are coded (records and attributes together, the
  // last call with every split) after each chunk, on the caller's thread.
  static Result<DpmStepEncoder> start(const ProgressiveMesh& mesh, unsigned threads = 0,
                                      const std::function<void(uint32_t)>& coded_splits = {});
  // The next step's positions (steps 0, 1, … in order): every vertex, in the progressive
  // numbering, on the grid (as quantize_positions() leaves them).
  void add_step(std::span<const float> xyz);
  // The same from a step as read: xyz in the input's numbering, not yet on the grid, and
  // progressive_of[v] input vertex v's number in the mesh. Put on the grid as quantize_step()
  // would, renumbered and checked in one pass; an error when a coordinate is not finite.
  Status add_input_step(std::span<const float> xyz, std::span<const uint32_t> progressive_of);
  // The file, once every step was given; with a THMB chunk before END when `thumbnail_png` is
  // not empty (the bytes with_thumbnail() would give, without copying the file once more).
  Result<std::string> finish(std::string_view thumbnail_png = {});

  DpmStepEncoder(DpmStepEncoder&&) noexcept;
  DpmStepEncoder& operator=(DpmStepEncoder&&) noexcept;
  ~DpmStepEncoder();

 private:
  struct State;
  explicit DpmStepEncoder(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

// What a reader needs of a file (docs/FORMAT.md "SPLT payload"): the splits up to one level and
// the steps up to one step. The rest is not decoded, nor read from disk when it lies after the
// last split needed. The level is known once HEAD is read: a vertex count, a fraction of the full
// vertex count, or the coarsest level whose error is at most `error` (absolute). A coarse vertex
// shows the peak of the values it stands for, which come with the finer splits: when the file has
// result fields and `fields` is set, every split is read (positions still only of the steps up
// to last_step); without `fields` the field chunks are checked but not decoded.
struct DpmReadLimits {
  bool fields = true;
  std::optional<uint32_t> vertices;
  std::optional<double> ratio;
  std::optional<double> error;
  bool error_of_diagonal = false;  // `error` is a fraction of the bounding-box diagonal
  // Without `variant`: in stored steps (a family's steps as HEAD lists them).
  std::optional<size_t> last_step;
  // A family file's variant (its name or index, as find_variant() takes them): last_step then
  // counts that variant's steps, and only the stored steps they need are decoded — those up to
  // the last of them, as each stored step is predicted from the one before (docs/family.md "How
  // it is built"), so one pass reads what select_variant() will show. The mesh still lists every
  // variant. A name the family lacks is an error; a file that is not a family ignores it.
  std::optional<std::string> variant;
};

// The splits a reader with `limits` (vertices or ratio; neither: all) keeps, from the counts of
// HEAD that `mesh` holds: at least the base mesh, at most the whole stream.
uint32_t splits_for_limits(const ProgressiveMesh& mesh, const DpmReadLimits& limits);

// Reads a whole file or a prefix of one (then complete == false, prefix == true), or only what
// `limits` asks for (then limited == true). Errors name the file and byte offset.
Result<ProgressiveMesh> read_dpm(const std::string& path, const DpmReadLimits& limits = {});
Result<ProgressiveMesh> decode_dpm(std::string_view bytes, const std::string& name,
                                   const DpmReadLimits& limits = {});
// The thumbnail (docs/FORMAT.md "Thumbnail: THMB"): an optional chunk just before END that holds
// a small PNG picture of the model for catalogues; the model's readers skip it. The file's bytes
// with that chunk added, or replacing the one it has; an error when the bytes are not a complete
// .dpm (they must end with END).
Result<std::string> with_thumbnail(std::string_view dpm_bytes, std::string_view png,
                                   const std::string& name);
// The THMB payload of a file, found by reading the chunk headers only (seeking past payloads);
// nullopt when the file has none. Every header is read up to END, so a file that ends early (a
// copy still being written) is an error, found without decoding a chunk.
Result<std::optional<std::string>> read_dpm_thumbnail(const std::string& path);

// The magic bytes, for format detection.
bool looks_like_dpm(std::string_view head);

}  // namespace dynpm
