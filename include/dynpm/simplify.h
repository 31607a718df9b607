// dynpm/simplify.h — mixed triangle/quad half-edge collapse with quadrics over key steps.
//
// Wundrak, Henn & Stork 2006 (§2, §3), after Hoppe 1996 (progressive meshes) and Garland &
// Heckbert 1997 (quadric error metrics). Where each part lives in src/simplify/:
//
//   quadrics (quadrics.h): Q[t][v] = Σ area · plane² over the faces of v in key step t (a skew
//     quad's plane is quad_plane(): the mean of its corner normals through its centroid), plus
//     constraint planes perpendicular to boundary and feature edges
//     + regularize · (area of v's faces) · |p − p_t(v)|², the shape term (not counted in w)
//   field term (field_term.h, FieldTerm::squared(), form FieldForm): per vertex, key step t and
//     cost field f, kSpread: the interval I[t][v][f] = [lo, hi] of the values v stands for (an
//     element field: the values of v's faces), e = spread(I[t][v0][f] ∪ I[t][v1][f]) / range_f;
//     kAttributes / kQuadric: an attribute quadric (values scaled by range_f) at v1's position,
//     e² its area-weighted mean at v1's own value / at the optimal value
//     F[t](v0, v1) = Σ_f (weight_f · diagonal · e_f)²
//   cost (worst_over_key_steps(), paper method (1*)), with w the total plane weight:
//     G[t] = max((Q[t][v0] + Q[t][v1])(p_t(v1)) / (w[t][v0] + w[t][v1]),
//                Q[t][v0](p_t(v1)) / w[t][v0])
//     the second term is the cost floor: never less than v0's own RMS distance at its new place
//     (with optimal placement: (Q[t][v0] + Q[t][v1]) / w at the minimiser, no floor)
//     FieldCombine::kAdd:   error = max over key steps t of sqrt(G[t] + F[t]) / diagonal
//     FieldCombine::kScale: error = max(max_t sqrt(G[t]) / diagonal, kFieldGeometryFloor)
//                                   · (1 + f) + max(0, f − kFieldJumpAllowance) · kFieldJumpLength
//                           with f = max_t sqrt(F[t]) / diagonal
//     without cost fields both are max_t sqrt(G[t]) / diagonal
//   legality (legality.h): CollapseRules::allows(), every rule, cheapest first
//   the loop (simplifier.cpp, Simplifier::run() and advance(), line for line; with islands,
//   each island runs it with a queue of its own, and its collapses are told in key order at the
//   end: SimplifyOptions::island_min_vertices, islands.h; with regions, each region runs it up to
//   a common key bucket per round, its borders frozen, and one queue takes over for the rest:
//   SimplifyOptions::region_min_vertices, regions.h):
//     rate_all_edges()                           every edge once, for its cheaper direction
//                                                (an island: its own, when it opens)
//     loop:
//       if stop_reached(): done, target reached
//       if queue empty:
//         if not rated_again: rate_all_edges() (an island: its own), rated_again = true,
//           continue
//         done: no legal collapse remains
//       entry = pop the cheapest
//       if stale(entry): continue                v0 or v1 changed since it was rated
//       if rounds and locked(entry): defer it, continue      (independent rounds, below)
//       if entry.error > max_error: done, target reached
//       if not allows(entry.v0, entry.v1):       legality on pop, on the mesh as it is now
//         rejected[entry.v0] = 1                 re-rated when its surroundings change
//         if not entry.one_way: push entry.v1 → entry.v0 at its own cost
//         continue
//       error = cost(entry.v0, entry.v1)         as rated (the heap keeps it as float)
//       collapse(entry.v0, entry.v1, error):     Q[t][v1] += Q[t][v0], I[t][v1] ∪= I[t][v0];
//                                                re-rate the edges of v1 and of rejected
//                                                vertices around it; drop the stale entries
//                                                once the heap has doubled
//       rated_again = false
//       if rounds: lock the corners of v1's faces; when the round's quota is done, or the
//         queue is empty, unlock all and push the deferred entries back
//
// The half-edge collapse v0 → v1, its wings and the vertex split that undoes it are drawn and
// defined in split_record.h.
//
// Legality: a table says which vertex kind may collapse into which, and along which kind of
// edge; then no collapse across a quad's diagonal, (P2) boundary, (P3) size, no sheet's or
// part's last face deleted between two boundary or feature edges (a rib off its T-joint), (P1*)
// second-order neighbours, and a geometric check in every key step.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dynpm/core.h"
#include "dynpm/split_record.h"

namespace dynpm {

enum class Placement {
  kHalfEdge,  // v1 keeps its original position (the paper; positions never re-stored)
  kOptimal,   // full-edge collapse to the quadric minimiser (QSlim), the better endpoint when the
              // system is ill-conditioned; needs every step to be a key step
};

// What the field term measures per vertex and key step (docs/simplify.md, "Fields in the cost",
// where the three are measured against each other).
enum class FieldForm {
  kSpread,      // the spread (max − min) of the values a vertex stands for: what the max
                // aggregate can show
  kAttributes,  // an attribute quadric (Hoppe 1999's memory-efficient form) at v1's own value,
                // as meshoptimizer's simplifyWithAttributes
  kQuadric,     // the attribute quadric at its optimal value (Garland–Heckbert 1998)
};
// How the field term and the geometric error make one cost.
enum class FieldCombine {
  kAdd,    // sqrt(geometric² + field²): a field change of the whole range costs like weight
           // diagonals of distance
  kScale,  // max(geometric, kFieldGeometryFloor) · (1 + field): the field scales each
           // collapse's own geometric error, by 1 + weight for a change of the whole range
};
// Under FieldCombine::kScale a geometric error below this (in diagonals) counts as this: where
// the surface is flat to within the floats' precision, the field alone orders the collapses.
inline constexpr double kFieldGeometryFloor = 1e-6;
// Under FieldCombine::kScale a field term f beyond this (half of one field's range at the default
// weight 3) also counts as a length: kFieldJumpLength diagonals for each unit beyond. Scaling
// alone never defers a collapse whose geometric error is near zero, however large the jump it
// merges (a flat wall across a plastic hinge); measured in docs/simplify.md "Fields in the cost".
inline constexpr double kFieldJumpAllowance = 1.5;
inline constexpr double kFieldJumpLength = 0.01;

// Defaults of SimplifyOptions::field_weight and ::regularize (docs/simplify.md, where they are
// measured).
inline constexpr double kDefaultFieldWeight = 3;  // under FieldCombine::kScale
inline constexpr double kDefaultRegularize = 0;

struct SimplifyOptions {
  // Stop conditions: the simplifier stops at the first one reached. With none set, it runs
  // until no legal collapse remains.
  std::optional<uint32_t> target_vertices;  // vertices in faces
  std::optional<size_t> target_faces;
  std::optional<double> target_ratio;  // of the input's vertices in faces, in (0, 1]
  std::optional<double> max_error;     // in units of the bounding-box diagonal

  Placement placement = Placement::kHalfEdge;

  // Time steps whose geometry rates collapses (paper method 1*: cost = max over them). Empty
  // means every step.
  std::vector<size_t> key_steps;

  // A collapse that turns a moved face's normal by more than this, in any key step, is
  // rejected (foldovers); so is one that leaves a face without area or a quad non-convex.
  double max_normal_rotation_degrees = 90.0;
  // Weight of the planes through boundary and feature edges, perpendicular to their faces,
  // relative to the area-weighted face planes (each constraint plane weighs
  // boundary_weight · |edge|²). VCG calls this BoundaryQuadricWeight.
  double boundary_weight = 1.0;

  // Result fields in the cost (docs/simplify.md, "Fields in the cost"): per key step, the
  // spread of each field's values that v1 stands for after the collapse (field_form), in parts
  // of the field's range (over the key steps) times the weight, scales the collapse's own
  // geometric error by 1 + that (field_combine kScale; kAdd adds it as weight × the
  // bounding-box diagonal of distance, the cost before 2026-12-02 at weight 0.01). Empty
  // field_weights: every field of the input at field_weight; otherwise only the fields named,
  // each at its own weight or, without one, at field_weight. field_weight 0 and no field named:
  // the geometry-only cost, byte for byte.
  struct FieldWeight {
    std::string name;
    std::optional<double> weight;
  };
  std::vector<FieldWeight> field_weights;
  double field_weight = kDefaultFieldWeight;
  FieldForm field_form = FieldForm::kSpread;
  FieldCombine field_combine = FieldCombine::kScale;
  // Shape regularizer: an isotropic quadric per vertex and key step, weighted regularize × the
  // area of its faces, so that among collapses of (near) equal geometric error the one that
  // moves v0's faces least wins: flat regions stay well shaped instead of turning into slivers
  // and fans. Not part of the planes' weight w. 0: off.
  double regularize = kDefaultRegularize;

  // Independent rounds (docs/selective.md "Independent rounds"): collapses are taken in
  // rounds; within one, no collapse touches a vertex of a face the round has already changed,
  // so that the splits of a round never depend on one another and the dependency chains of
  // selective refinement cross at most one split per round. A round ends after this fraction of
  // the vertices alive at its start. 0: off (every collapse in cost order, the default).
  double independent_rounds = 0;

  // Features: their vertices only slide along them, or stay (docs/simplify.md).
  bool keep_part_boundaries = true;  // edges between faces of different part ids
  std::vector<uint32_t> locked_vertices;
  std::vector<Edge> feature_edges;  // user feature lines (vertex pairs joined by an edge)

  // The proof that the caller's check_topology() found no error in this topology: the mesh is
  // then not checked again (no "checking the mesh" phase). Without one, or with a proof of other
  // faces, simplify() checks it itself.
  std::optional<ValidationProof> checked;
  // Test mode: validate() the whole mesh after every collapse and fail at the first problem
  // (with islands: after every round of them).
  bool check_every_collapse = false;
  unsigned threads = 0;  // 0: one per hardware thread
  // Islands (docs/simplify.md "Islands"): without optimal placement or independent rounds, a
  // mesh of at least this many vertices in faces and of several connected components (where
  // regions do not apply, below) is cut into islands of whole components, each simplified with a
  // queue of its own on any free thread (to its end, or with a vertex or face target until its key
  // is past a bound of the cut: islands.h CutBound); the collapses are told in the order of their
  // keys (island by island where keys tie) up to the stop condition. The result does not depend on
  // the thread count. UINT32_MAX: never.
  uint32_t island_min_vertices = uint32_t{1} << 16;
  // With islands: at most this many run, and hold their key-step quadrics, at once (0: 2 ×
  // threads). Fewer take less memory with many key steps and change no collapse.
  unsigned islands_at_once = 0;
  // Regions (docs/simplify.md "Regions"): without independent rounds (nor optimal placement with
  // a listener), a mesh of at least this many vertices in faces, a quarter of them or more in one
  // connected component, simplified to a stop condition, is cut by space into 8 regions that
  // collapse in key order on any free thread, each with a queue of its own and the corners of
  // faces across a cut frozen, up to a share of the stop's work (regions.h kRegionShare); then
  // one queue goes on over the whole mesh. The result does not depend on the thread count.
  // UINT32_MAX: never.
  uint32_t region_min_vertices = uint32_t{1} << 16;
  // Phases "checking the mesh" (faces; not with a proof in `checked`), "reading key steps" (steps),
  // "quadrics" (vertices) and "collapsing" (vertices removed, of those to remove; it ends at the
  // collapses made). May be empty.
  ProgressCallback progress;
};

// What one collapse did. Spans stay valid only during the listener call.
struct CollapseRecord {
  uint32_t v0 = kNoVertex;  // removed
  uint32_t v1 = kNoVertex;  // kept
  // The faces of the edge (split_record.h), in the input's numbering: face ids and wing
  // vertices are the input's.
  std::array<SplitWing, 4> wings{};
  uint8_t wing_count = 0;                 // 1 at a boundary, 2 inside, 3+ at a T-joint
  std::span<const uint32_t> moved_faces;  // faces of v0 (not holding v1) that now hold v1
  double error = 0;                       // of this collapse, in bounding-box diagonals
  uint32_t round = 0;  // SimplifyOptions::independent_rounds: its round (from 1); 0 without
  // Placement::kOptimal: v1's new position in each key step (xyz per step); empty otherwise.
  std::span<const float> v1_new_positions;
};

class CollapseListener {
 public:
  virtual ~CollapseListener() = default;
  virtual void on_collapse(const CollapseRecord& record) = 0;
};

struct SimplifyResult {
  Topology topology;                      // live faces in input order, vertices renumbered
  std::vector<uint32_t> original_vertex;  // new vertex → input vertex
  // Positions in every key step (xyz per vertex), only for Placement::kOptimal, where v1 moves.
  std::vector<std::vector<float>> key_step_positions;
  std::vector<size_t> key_steps;
  BoundingBox key_step_box;  // of every key step's positions (the error's unit is its diagonal)
  size_t collapses = 0;
  size_t islands = 1;           // SimplifyOptions::island_min_vertices: 1 is the whole mesh
  size_t regions = 0;           // SimplifyOptions::region_min_vertices: 0 without
  size_t region_collapses = 0;  // of `collapses`, those the regions made
  // The most vertices whose key-step quadrics were held at once: with islands, those of the
  // islands at work (at most 2 × threads of them), else every vertex.
  size_t quadric_vertices_held = 0;
  // ≥ collapses: with islands and a stop condition, those the islands made past the cut too.
  size_t collapses_made = 0;
  double max_error = 0;         // largest collapse error done, in diagonals
  bool target_reached = false;  // false: no legal collapse remained first
  std::string stop_reason;
};

// A field of `frames` the cost uses, with its weight (SimplifyOptions::field_weights).
struct CostField {
  size_t field = 0;  // index into frames.fields()
  double weight = 0;
};
// The fields the cost uses, weight 0 left out. Error: a named field the input does not have (the
// message lists those it has), a negative or non-finite weight.
Result<std::vector<CostField>> cost_fields(const SimplifyOptions& options,
                                           const FrameSource& frames);

// Simplifies the animation; the input is not changed. Errors: invalid input (validate()
// errors, unless SimplifyOptions::checked proves there are none), unreadable steps, options that
// cannot hold (optimal placement without every step as a key step), or, in test mode, the first
// collapse after which validation fails.
Result<SimplifyResult> simplify(const Topology& topology, const FrameSource& frames,
                                const SimplifyOptions& options,
                                CollapseListener* listener = nullptr);

// The vertices of each island simplify() will cut the mesh into, largest first (every vertex,
// in faces or not, counts in its component's island); empty when it will make no islands (one
// component, or regions: those hold every vertex's quadrics). For memory estimates before the
// work: one pass over the faces.
std::vector<size_t> island_vertex_counts(const Topology& topology, const SimplifyOptions& options);
// At most how many vertices' key-step quadrics simplify() will hold at once
// (SimplifyResult::quadric_vertices_held): with islands, those of the largest islands that run
// at once (SimplifyOptions::islands_at_once), else every vertex.
size_t quadric_vertices_held(const Topology& topology, const SimplifyOptions& options);
size_t quadric_vertices_held(std::span<const size_t> island_vertex_counts,
                             const SimplifyOptions& options, uint32_t vertex_count);

}  // namespace dynpm

namespace dynpm {

// Which time steps rate the collapses (paper §3 and Table 3). A crash result changes little
// from one step to the next, so a few well-chosen steps rate almost as well as all of them, at
// a fraction of the time and memory.
struct KeyStepRule {
  enum class Kind {
    kAll,       // every step
    kPaper,     // first, last, and the step in between farthest from the first (paper §3)
    kAuto,      // `count` steps, greedily: start with the first, then always add the step
                // farthest from those chosen (largest vertex displacement)
    kExplicit,  // the given steps
  };
  Kind kind = Kind::kAll;
  size_t count = 3;           // kAuto
  std::vector<size_t> steps;  // kExplicit
};

// "all", "paper", "auto:K" or a list "0,12,24".
Result<KeyStepRule> parse_key_step_rule(const std::string& text);

struct KeyStepChoice {
  std::vector<size_t> steps;         // ascending
  std::vector<std::string> reasons;  // one line per chosen step, for the user
  // The bounding box of every step's positions, when the choice read every step (auto:K and
  // paper): the build needs it before its last pass (BuildOptions::all_steps_box).
  std::optional<BoundingBox> all_steps_box;
};

// Reads the steps it needs through the FrameSource (each step once, whatever the rule; up to
// `threads` at once, 0: one per hardware thread, with the same choice on any count).
// Distances between steps are the largest vertex displacement, measured on at most
// kMaxProbeVertices vertices spread evenly over the mesh, so that a 5 M-node, 100-step result
// is compared in bounded memory. Reports phase "choosing key steps" (steps read). Once `stop`
// (when given) is set, it reads no further step and returns an error: a caller that reads the
// steps while it checks the faces gives up the reading when the check fails.
inline constexpr uint32_t kMaxProbeVertices = 65536;
Result<KeyStepChoice> choose_key_steps(const FrameSource& frames, const KeyStepRule& rule,
                                       unsigned threads = 0, const ProgressCallback& progress = {},
                                       const std::atomic<bool>* stop = nullptr);

}  // namespace dynpm
