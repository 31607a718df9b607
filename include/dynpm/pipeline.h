// dynpm/pipeline.h — the library's whole jobs, each joining several modules:
// build_progressive_mesh() (simplify → progressive) and evaluate_levels() (lod → eval).
//
// build: animation → simplifier → collapse record → progressive mesh.
// The simplifier runs to the end (until no legal collapse remains) with a listener that keeps
// every collapse. Reversed, the collapses are the vertex splits; vertices are renumbered so the
// base mesh holds 0…b−1 and split i creates vertex b+i, faces so the base holds the first ones
// and each split's re-created triangles take the next numbers (docs/FORMAT.md). Every step's
// positions are then read once more through the FrameSource, in that order: kept in memory
// (build_progressive_mesh) or coded into the file as they come (build_dpm, a few steps held at a
// time).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dynpm/eval.h"
#include "dynpm/progressive.h"
#include "dynpm/simplify.h"

namespace dynpm {

// The thumbnail a catalogue shows ('dynpm serve'; render_thumbnail() below).
struct ThumbnailOptions {
  uint32_t width = 256, height = 192;
  double ratio = 0.05;  // the level drawn: this fraction of the vertices (at least the base mesh)
};

struct BuildOptions {
  // Key steps, placement limits, features, threads and the proof that the caller checked the
  // mesh (SimplifyOptions::checked) as for simplify(). Placement must be
  // kHalfEdge (positions stay original, one per vertex per step serves every level); stop
  // conditions are ignored: the build collapses until no legal collapse remains.
  SimplifyOptions simplify;
  bool lossless = false;
  // Bound on a stored position's error, in bounding-box diagonals (docs/FORMAT.md).
  double max_position_error = 1.0 / (1 << 18);
  // Bound on a stored field value's error, a fraction of the field's range (docs/FORMAT.md,
  // "Fields"); lossless keeps them float32 exact.
  double field_bound = 0.001;
  std::string note;
  // A family file's variants (family.h: FamilySteps::variants()), written as its VARI chunk;
  // empty for one model.
  std::vector<MeshVariant> variants;
  // The bounding box of every step's positions, when the caller has it (choose_key_steps() with
  // auto:K or paper measures it in its pass over the steps): the grid needs it before the last
  // pass. Unset: the simplifier's, when every step is a key step, else a pass of its own.
  std::optional<BoundingBox> all_steps_box;
  // The simplifier's phases (SimplifyOptions::progress), then "recording the splits" (with the
  // result fields), and "gathering positions" (steps; build_dpm: "coding the splits", then
  // "encoding positions" (steps), "thumbnail" and "encoding"). May be empty. simplify.progress is
  // ignored: this one is passed down.
  ProgressCallback progress;
  // build_dpm(): the thumbnail to store in the file (its THMB chunk), drawn from the build's own
  // records and positions once the steps are coded (phase "thumbnail"): the picture
  // add_thumbnail() draws from the file's bytes, without decoding them.
  std::optional<ThumbnailOptions> thumbnail;
};

// About how many bytes build_dpm() takes at its peak, for `vertices` vertices, `faces` faces,
// `steps` steps, `key_steps` key steps and `threads` (0: every core), with result fields holding
// `field_values_per_step` values per step in all (a node field counts the vertices, an element
// field the faces), and key-step quadrics held for at most `quadric_vertices` vertices at once
// (quadric_vertices_held(); more than `vertices`: every vertex); a field in the cost adds the
// simplifier's own. Fitted to measured peaks (src/pipeline/build_memory.cpp says which;
// docs/build.md).
uint64_t build_memory_estimate(uint64_t vertices, uint64_t faces, uint64_t steps,
                               uint64_t key_steps, unsigned threads = 0,
                               uint64_t field_values_per_step = 0,
                               uint64_t quadric_vertices = UINT64_MAX);

// Simplifies the animation to the end and records the progressive mesh, with every step's
// positions (read once each, through the FrameSource) and the source's scalar fields.
Result<ProgressiveMesh> build_progressive_mesh(const Topology& topology, const FrameSource& frames,
                                               const BuildOptions& options);

// build_progressive_mesh() and encode_dpm() in one, the steps' positions coded as they are read
// instead of held: the same bytes, in the memory of a few steps (build_memory_estimate()).
struct BuiltFile {
  ProgressiveMesh mesh;  // all but the positions (empty): what a report of the build needs
  std::string bytes;     // the .dpm file
};
Result<BuiltFile> build_dpm(const Topology& topology, const FrameSource& frames,
                            const BuildOptions& options);
// The same, for a caller done with the input's faces: Topology::release_faces() once the splits
// are recorded, before the coding's peak.
Result<BuiltFile> build_dpm(Topology&& topology, const FrameSource& frames,
                            const BuildOptions& options);

// ---------------------------------------------------------------------------------------------
// The thumbnail a catalogue shows ('dynpm serve'), which 'dynpm build' stores in the file's THMB
// chunk (docs/FORMAT.md "Thumbnail: THMB").
// What render_thumbnail() needs of a file: its level at `ratio`, every step, no fields.
DpmReadLimits thumbnail_read_limits(const ThumbnailOptions& options = {});
// A PNG of `mesh` (read with thumbnail_read_limits()) at its finest level and last step read:
// the viewer's first view (its up axis, from +x −y +z on a z-up model), orthographic, flat
// shaded, each part in the viewer's colour for it, on the viewer's background.
std::string render_thumbnail(const ProgressiveMesh& mesh, const ThumbnailOptions& options = {});
// The .dpm's bytes with the thumbnail of the model they hold (with_thumbnail()).
Result<std::string> add_thumbnail(std::string_view dpm_bytes, const std::string& name,
                                  const ThumbnailOptions& options = {});

// ---------------------------------------------------------------------------------------------
// evaluate_levels(): the paper's Table 2 — a progressive mesh against the animation it was built
// from, at several resolutions and time steps.
//
//   for each ratio r (ascending): the model at round(r % of the full vertex count) vertices,
//     at least 1 (the navigator clamps to the levels the model holds) → one row
//   for each measured step t (every step, or only the chosen ones):
//     the original at t: its triangles and closest-point BVH built once, for every row
//     the original at t against each row's level at t: two-sided Hausdorff (dynpm/eval.h), and
//       for each field, the field error at the same samples and the peak ratio
//     a chosen step's distances fill its column; the max column keeps each value's largest
//
// Field error: the largest |original value − level's shown value| at corresponding surface
// points (FieldPair in dynpm/eval.h), in % of the field's range over every step of the original
// (ProgressiveField::max − min). Peak ratio: max |shown value| over the level / max |original
// value| at that step (1: the peak is kept; 1 when the original is 0 everywhere).
//
// Every distance is in % of one reference length (by default the model's bounding-box diagonal
// over all steps, which is the original's within the position bound), so that the columns
// compare like with like, as hausdorff_steps() does for step sequences.

struct LevelsOptions {
  // Resolutions in % of the full vertex count, each in (0, 100]; sorted, duplicates dropped.
  std::vector<double> ratios;
  // The table's steps, each < the step count; sorted, duplicates dropped. Empty: the first,
  // middle and last.
  std::vector<size_t> steps;
  // The max column over every step of the animation (true) or over `steps` only.
  bool max_over_all_steps = true;
  // Sampling, seed and threads; reference_diagonal 0 means the model's diagonal.
  HausdorffOptions hausdorff;
  // Result fields to measure, by name: each must be in the original and in the model, at the
  // same location. The level shows each with `aggregate` (Navigator::field_values).
  std::vector<std::string> fields;
  FieldAggregate aggregate = FieldAggregate::kMaxAbs;
  // The field error's facing correspondence (HausdorffOptions::field_facing_reach) in % of the
  // reference diagonal; 0: the closest point alone (docs/eval.md, "Facing correspondence").
  double field_facing_reach_pct = kDefaultFacingReachPct;
  static constexpr double kDefaultFacingReachPct = 1;
  // Names the model in messages ("rail.dpm was built from another mesh: …").
  std::string model_name = "the model";
  // Called with (steps measured, steps to measure) before each step and once at the end. May be
  // empty.
  std::function<void(size_t, size_t)> progress;
};

// One cell of the table: the original against one level at one step.
struct LevelDistance {
  double hausdorff_pct = 0, mean_pct = 0, rms_pct = 0;  // % of the reference diagonal
  double diagonal = 0;                                  // the reference diagonal itself
  // One per LevelsOptions::fields: the field error in % of the field's range, the peak ratio.
  // In LevelRow::max: the largest field error over the measured steps, and the peak ratio
  // farthest below 1 (the smallest). peak_gap_pct: how far the largest |value| shown lies below
  // the original's, in % of the field's range (≤ the stored bound when the peak is kept; the
  // ratio alone cannot say so for a step whose peak is small); in max, the largest.
  std::vector<double> field_error_pct, peak_ratio, peak_gap_pct;
  // The field error two other ways, in % of the range (max: the largest): at the closest point
  // alone (the measure before the facing correspondence), and per original node against the
  // value its representative at the level shows (Navigator::ancestor; NaN for element fields).
  std::vector<double> field_error_nearest_pct, field_error_node_pct;
  // The mean field error over the surface (FieldDistance::mean), % of the range; in max the
  // largest over the steps.
  std::vector<double> field_error_mean_pct;
  std::vector<Point3> field_error_at;  // the sample of field_error_pct (in max: its step's)
  // field_error_pct where the original does not pass through itself at the step (no
  // self_crossing_faces()), NaN where it does; in max the largest over such steps (NaN if
  // none). Reported beside field_error_pct, never instead (docs/eval.md, "Sheets through each
  // other"). Empty without fields.
  std::vector<double> field_error_untangled_pct;
};

// One row of the table: one resolution.
struct LevelRow {
  double ratio = 0;       // as requested, % of the full vertex count
  uint32_t vertices = 0;  // the level's vertex count (what the model holds nearest)
  uint32_t faces = 0;     // the level's face count
  uint32_t level = 0;     // splits applied
  double error = 0;       // the level's simplification error, absolute (Navigator::error)
  std::vector<LevelDistance> steps;  // one per LevelsTable::steps, in that order
  LevelDistance max;    // each value's max over the measured steps (diagonal: at max_step)
  size_t max_step = 0;  // the measured step of the largest Hausdorff distance
};

struct LevelsTable {
  std::vector<size_t> steps;         // the chosen steps (the columns), ascending
  double reference_diagonal = 0;     // the length every percentage is of
  std::vector<double> field_ranges;  // per field: max − min over every step, what % are of
  // With fields: the measured steps where the original passes through itself, ascending, and
  // the number of its faces that do (self_crossing_faces()).
  std::vector<std::pair<size_t, uint32_t>> crossings;
  std::vector<LevelRow> rows;  // one per distinct ratio, ascending
};

// An error if `model` was not built from this animation: other vertex, face or step counts. The
// message names the model as `model_name`.
Status check_built_from(const Topology& original, const FrameSource& frames,
                        const ProgressiveMesh& model, const std::string& model_name);

// Measures `model` against the original animation (topology and steps). Errors: the model was
// built from another animation (check_built_from), a step out of range, a step that cannot be
// read, a distance that cannot be measured ("step 3, 120 vertices: …"), a field missing from the
// original or the model. Reads each measured step of the original once and builds its
// closest-point structure once for every row; one measurement (distance and fields) per row and
// measured step.
Result<LevelsTable> evaluate_levels(const Topology& original, const FrameSource& frames,
                                    const ProgressiveMesh& model, const LevelsOptions& options);

// ---------------------------------------------------------------------------------------------
// Families (docs/family.md): variants of one mesh — the same node and element ids, as a DOE over
// thicknesses, materials or load cases makes — built into one hierarchy. The variants' steps are
// one step sequence to the simplifier (so the cost is the max over every variant's key steps, the
// paper's (1*) across variants), each distinct step stored once.

// One input of a family.
struct FamilyMember {
  std::string name;    // the input's file name without folder and extension (unique)
  std::string source;  // the input's file name, without folder (for messages and the VARI chunk)
  const Topology* topology = nullptr;
  const FrameSource* frames = nullptr;
  // Its mesh was compared with the first member's already (check_same_mesh() of the two), and
  // its faces may have been released since: check_same_mesh() then checks its name and fields.
  bool mesh_checked = false;
};

// An error naming the first difference between a member's mesh and the first member's: vertex or
// face count, the node at a vertex, a face's element id, corners (as node ids) or part, the
// result fields; or two members of one name. Cheap: nothing is read but the topologies.
Status check_same_mesh(std::span<const FamilyMember> members);

// The family's distinct steps as one FrameSource: stored step k is one member's step — the first
// member's in reverse order (so that its undeformed step comes last, next to the others' first
// steps, which the file predicts from it), then the others' in order — a step equal to one stored
// before it (positions and every field value, compared exactly, after a hash finds the candidates)
// not stored again. The members' sources must outlive it.
class FamilySteps final : public FrameSource {
 public:
  // Reads every step of every member once, up to `threads` at once (0: one per hardware
  // thread) where its source allows (and a step whose hash matches a stored one, and that
  // candidate, once more); calls check_same_mesh() first. `progress`: ("comparing the
  // variants' steps", done, total).
  static Result<std::unique_ptr<FamilySteps>> make(std::span<const FamilyMember> members,
                                                   const ProgressCallback& progress = {},
                                                   unsigned threads = 0);
  // Per member: its name, source, times and for each step the stored step holding it.
  const std::vector<MeshVariant>& variants() const { return variants_; }

  uint32_t vertex_count() const override;
  size_t step_count() const override { return stored_.size(); }
  double step_time(size_t t) const override;
  Status read_step(size_t t, std::span<float> out) const override;
  size_t step_float_count(size_t t) const override;
  bool parallel_reads() const override;
  std::vector<FieldInfo> fields() const override;
  Status read_field(size_t field, size_t t, std::span<float> out) const override;

 private:
  struct Stored {
    size_t member, step;
  };
  void order_for_prediction();
  std::vector<FamilyMember> members_;
  std::vector<Stored> stored_;
  std::vector<MeshVariant> variants_;
};

}  // namespace dynpm
