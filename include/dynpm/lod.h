// dynpm/lod.h — the navigator: a progressive mesh at any resolution and any time step.
//
// It holds the current faces (a prefix of the face numbering) and applies or undoes the splits
// between the old and the new level in place, so changing resolution costs time proportional
// to the change. Positions need no work per level: half-edge collapses keep original positions,
// so vertex v has the same position at every level where it exists.
//
// Selective refinement (docs/selective.md): SplitDependencies says which earlier splits each
// split needs, derived from the split records alone; SelectiveNavigator holds any set of splits
// closed under them (out of stream order), and RefineTargets turns a request — a box, a sphere,
// parts, a field threshold, a displacement threshold, at one step — into the splits it wants.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm {

// Shows a ProgressiveMesh at any resolution and time. Holds the current faces; resolution
// changes apply or undo only the splits between the old and the new level.
class Navigator {
 public:
  explicit Navigator(const ProgressiveMesh& mesh);  // starts at the base mesh

  const ProgressiveMesh& mesh() const { return *mesh_; }
  uint32_t level() const { return level_; }  // splits applied
  uint32_t vertex_count() const { return mesh_->base_vertex_count + level_; }
  uint32_t face_count() const { return face_count_; }
  double error() const { return mesh_->level_error(level_); }

  // Clamped to [base_vertex_count, mesh.vertex_count()].
  void set_vertex_count(uint32_t n);
  void set_level(uint32_t k);
  // The coarsest level whose error is ≤ e (absolute units).
  void set_error(double e);

  // Current faces: [0, face_count()).
  std::span<const Face> faces() const { return {faces_.data(), face_count_}; }
  // xyz of vertices [0, vertex_count()) at time step t; fractional t interpolates linearly
  // between the neighbouring steps. out.size() ≥ 3 · vertex_count().
  void positions(double t, std::span<float> out) const;
  // Geomorph towards this level from the coarser level `from`: vertices created after `from`
  // start at their ancestor's position at that level (alpha 0) and reach their own (alpha 1).
  void geomorph(uint32_t from, double alpha, double t, std::span<float> out) const;
  // The values of result field `field` at step t shown at this level (docs/FORMAT.md, "Shown
  // values"): each present vertex (node field) or face (element field) shows the aggregate of the
  // original values it stands for. out.size() ≥ vertex_count() or face_count().
  void field_values(size_t field, size_t t, std::span<float> out,
                    FieldAggregate aggregate = FieldAggregate::kMaxAbs) const;
  // The field error of this level, a fraction of the field's range (ProgressiveField::error).
  double field_error(size_t field) const;

  // The vertex that v is merged into at level k (v itself if it exists there).
  uint32_t ancestor(uint32_t v, uint32_t k) const;

  // The current mesh as a Topology over vertices [0, vertex_count()), with part and element
  // ids and node ids; faces in progressive order.
  Topology topology() const;

 private:
  const ProgressiveMesh* mesh_;
  std::vector<Face> faces_;  // every face the mesh holds; [0, face_count_) are current
  uint32_t level_ = 0;
  uint32_t face_count_ = 0;
  // What splits [0, learned_) write besides their records, learned from the faces the first
  // time each is applied, so that later applies and undos only store (navigator.cpp): 1 B per
  // moved face, 5 B per wing.
  uint32_t learned_ = 0;
  std::vector<uint8_t> moved_slot_;      // per moved face: the parent's slot
  std::vector<uint8_t> wing_slots_;      // per wing, split applied: v1's slot | w's slot << 2
  std::vector<uint32_t> wing_opposite_;  // per wing: the fourth corner (kNoVertex: a triangle)
};

// The fully refined mesh in the input's vertex and face order (what build read), with
// positions at step t: the round-trip check and "extract" at full resolution use it.
struct OriginalOrder {
  Topology topology;
  std::vector<uint32_t> vertex_of_original;  // input vertex index → progressive vertex
  std::vector<uint32_t> face_of_original;    // input face index → progressive face
};
Result<OriginalOrder> original_order(const Navigator& full);

// The number of splits of the coarsest level whose error is ≤ e (absolute units).
uint32_t level_of_error(const ProgressiveMesh& mesh, double e);

// ---------------------------------------------------------------------------------------------
// Selective refinement

// What each split needs before it (docs/selective.md "Dependencies"): split i reads the faces
// holding its parent right before it in the stream (the parent's whole fan) and writes its moved
// and wing faces; i depends on the last earlier writer of each face it reads, a writer on every
// reader of the face since its previous writer, and i on the split that made its parent. Every
// dependency is an earlier split, so every prefix of the stream is closed, and so is any union
// of closed sets.
struct SplitDependencies {
  std::vector<uint32_t> dep_start{0};  // #splits + 1: split i's are deps[dep_start[i], [i+1])
  std::vector<uint32_t> deps;          // ascending within a split, each smaller than it
  std::vector<uint32_t> faces_after;   // #splits + 1: face_count_after(i) for every i
  std::vector<uint32_t> last_writer;   // per face: the last split changing it, or kNoIndex

  uint32_t split_count() const { return static_cast<uint32_t>(dep_start.size() - 1); }
  std::span<const uint32_t> of(uint32_t i) const {
    return {deps.data() + dep_start[i], deps.data() + dep_start[i + 1]};
  }
  size_t max_count() const;
  double mean_count() const;
};
// What split i is taken to read besides the faces it writes: the parent's whole fan (the first
// design), only the fan's faces on a wing edge (v1, w) (Hoppe's neighbour faces), or nothing
// more (then i also needs the splits that made its wing vertices).
// kFaceCreators drops the read-after-write order on whole faces (a split moves a corner by
// value, so the corner moves of one face commute): i needs the splits that made its parent and
// its triangle wings' vertices, of every face it writes the split that created it and the one
// that made it a quad, and of every face on a quad wing's triangle's sides at v1 its creator
// (docs/selective.md "Face creators", "Narrower: what a wing reads"). Dependencies then point to
// earlier splits too, but a closed set no longer leaves every face as the stream did (only as its
// applied writers make it). The default, as in the viewer's decoder
// (viewer/src/dpm/split_dependencies.js): both must choose the same splits.
enum class SplitReads : uint8_t { kFan, kWingEdges, kWritten, kFaceCreators };
// One pass over the splits in stream order (works on a prefix of a file as well). kFan and
// kWingEdges replay groups of whole connected components on up to `threads` threads (0: one per
// hardware thread) when there are several of about equal size: the same result on any count.
SplitDependencies derive_split_dependencies(const ProgressiveMesh& mesh,
                                            SplitReads reads = SplitReads::kFaceCreators,
                                            unsigned threads = 1);
// Adds to `splits` (one flag per split) everything its flagged splits depend on, transitively.
// Splits below `closed_prefix` count as flagged and closed already (a prefix is closed).
void close_under_dependencies(const SplitDependencies& deps, std::vector<uint8_t>& splits,
                              uint32_t closed_prefix = 0);
// Flags split i and everything it depends on that `splits` (closed) lacks; returns how many
// splits it flagged. `stack`: scratch space, reused between calls.
uint32_t add_with_dependencies(const SplitDependencies& deps, std::vector<uint8_t>& splits,
                               uint32_t i, std::vector<uint32_t>& stack);

// The mesh of a SelectiveNavigator in the agreed output order (docs/selective.md "Output"):
// existing vertices ascending by progressive id, active faces ascending by progressive face id,
// each face's corners in slot order, renumbered to the compact vertex order.
struct SelectiveMesh {
  std::vector<uint32_t> vertices;  // progressive vertex ids, ascending
  std::vector<uint32_t> faces;     // progressive face ids, ascending
  Topology topology;               // over vertices.size() vertices, with part/element/node ids
};

// A progressive mesh with any dependency-closed set of splits applied. Changing the set undoes
// the splits leaving it (descending) and applies those joining it (ascending): time proportional
// to the change plus one pass over the split flags.
class SelectiveNavigator {
 public:
  // Starts at the base mesh. Both must outlive the navigator.
  SelectiveNavigator(const ProgressiveMesh& mesh, const SplitDependencies& deps);

  const ProgressiveMesh& mesh() const { return *mesh_; }
  // `wanted`: one flag per split, closed under the dependencies (asserted in debug builds).
  void set_active(std::span<const uint8_t> wanted);
  bool split_active(uint32_t i) const { return split_active_[i] != 0; }
  bool face_active(uint32_t f) const { return face_active_[f] != 0; }
  bool vertex_exists(uint32_t v) const {
    return v < mesh_->base_vertex_count || split_active_[v - mesh_->base_vertex_count];
  }
  uint32_t vertex_count() const { return mesh_->base_vertex_count + active_splits_; }
  uint32_t face_count() const { return active_faces_; }
  // Splits applied and undone by the last set_active().
  uint32_t last_applied() const { return last_applied_; }
  uint32_t last_undone() const { return last_undone_; }
  // Every face slot by progressive id; only those with face_active() are in the mesh.
  std::span<const Face> face_slots() const { return faces_; }
  SelectiveMesh active_mesh() const;
  // The values field `field` shows at step t, one per vertex (node field) or face (element
  // field) of active_mesh(): a missing vertex's values merge into its nearest existing ancestor,
  // a missing face's into its heir (FORMAT.md "Shown values"), so no peak is hidden.
  std::vector<float> field_values(size_t field, size_t t, const SelectiveMesh& shown,
                                  FieldAggregate aggregate = FieldAggregate::kMaxAbs) const;

 private:
  void apply(uint32_t i);
  void undo(uint32_t i);

  const ProgressiveMesh* mesh_;
  const SplitDependencies* deps_;
  std::vector<Face> faces_;  // by progressive face id
  std::vector<uint8_t> split_active_, face_active_;
  uint32_t active_splits_ = 0, active_faces_ = 0;
  uint32_t last_applied_ = 0, last_undone_ = 0;
};

// A camera and a pixel tolerance (docs/selective.md "View-dependent"): the request
// view:EYE=x,y,z;AT=x,y,z;UP=x,y,z;FOV=deg;W=px;H=px;PX=p;BUDGET=n (UP, W, BUDGET optional).
struct ViewRequest {
  std::array<double, 3> eye{}, at{}, up{0, 0, 1};
  double fov = 45;       // vertical field of view, degrees
  double width = 0;      // viewport, pixels (0: as high as wide)
  double height = 1080;  // viewport, pixels
  double pixels = 1;     // tolerance: splits whose screen error exceeds it are wanted
  uint64_t budget = 0;   // at most this many vertices (0: no budget), up to one closure
};
// Bounding spheres of each split's final descendants at fractional step t (x, y, z, r per
// split), bottom-up over the vertex hierarchy (Hoppe 1997): once per step.
std::vector<float> split_spheres(const ProgressiveMesh& mesh, double t);
// The camera's frustum and projection, normalised once per request.
class ViewFrustum {
 public:
  explicit ViewFrustum(const ViewRequest& view);
  // The screen-space error in pixels of leaving a split with error `error` and bounding sphere
  // (x, y, z, r) unapplied: error / distance · H / (2 tan(fov/2)), the distance from the eye to
  // the sphere's surface (infinite inside it); −1 when the sphere is outside the frustum.
  double screen_error(const float* sphere, double error) const;

 private:
  std::array<double, 3> eye_;
  std::array<std::array<double, 3>, 5> inward_;  // near (at the eye), top, bottom, right, left
  double scale_;                                 // H / (2 tan(fov/2))
};

// One refine request (docs/selective.md "Requests"), as the CLI's --refine and the viewer write
// it: box:X0,Y0,Z0,X1,Y1,Z1  sphere:X,Y,Z,R  part:3,7  field:NAME>V  field:NAME<V  moved:>D
// view:EYE=…;AT=…;FOV=…;H=…;PX=…
struct RefineTarget {
  enum class Kind : uint8_t { kBox, kSphere, kPart, kField, kMoved, kView };
  Kind kind = Kind::kBox;
  std::array<double, 6> box{};  // kBox: min xyz, max xyz; kSphere: centre xyz, radius
  std::vector<int32_t> parts;   // kPart
  std::string field;            // kField: the field's name
  bool above = true;            // kField: value > threshold (else <)
  double threshold = 0;         // kField: the value; kMoved: the distance from step 0
  ViewRequest view;             // kView
};
// Errors name the request and what is wrong with it.
Result<RefineTarget> parse_refine_target(std::string_view text);

// The resolution outside the refined regions: a fraction of the vertices ("5%"), a vertex count
// ("20000") or the coarsest level with error at most E ("error:0.01", absolute).
struct ElsewhereLevel {
  std::optional<double> ratio;
  std::optional<uint64_t> vertices;
  std::optional<double> error;
};
Result<ElsewhereLevel> parse_elsewhere(std::string_view text);
// The number of stream splits that level applies.
uint32_t elsewhere_splits(const ProgressiveMesh& mesh, const ElsewhereLevel& level);

// Turns targets into wanted splits at a (fractional) step, on a complete progressive mesh.
class RefineTargets {
 public:
  RefineTargets(const ProgressiveMesh& mesh, const SplitDependencies& deps);
  // Flags (in `splits`, one per split) the splits `target` wants at step t: those creating a
  // vertex it selects, and the last writer of every face all of whose corners it selects, so
  // that such a face has its original corners. Not closed: see close_under_dependencies().
  // Fails when the target names a field or a part the mesh does not have.
  Status mark(const RefineTarget& target, double t, std::vector<uint8_t>& splits) const;
  // The vertices and faces of the fully refined mesh a target selects at step t (flags by
  // progressive id): a region's faces are those with every corner selected, a part's or an
  // element field's vertices the corners of its faces.
  Status select(const RefineTarget& target, double t, std::vector<uint8_t>& vertices,
                std::vector<uint8_t>& faces) const;
  // prefix(elsewhere) ∪ closure(targets): what SelectiveNavigator::set_active() takes. A view
  // with a budget comes last: its splits join by decreasing screen error, each with its closure,
  // while the vertices are fewer than the budget.
  Result<std::vector<uint8_t>> request(const ElsewhereLevel& elsewhere,
                                       std::span<const RefineTarget> targets, double t) const;
  // The splits a view wants at step t and their screen errors, by decreasing error (ties by
  // index): those whose sphere meets the frustum with a screen error above the tolerance.
  std::vector<std::pair<double, uint32_t>> view_splits(const ViewRequest& view, double t) const;

 private:
  // The order a budget takes the view's splits in: larger screen error first, then lower index.
  static bool before(const std::pair<double, uint32_t>& a, const std::pair<double, uint32_t>& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  }
  std::vector<std::pair<double, uint32_t>> view_candidates(const ViewRequest& view, double t) const;
  // Adds a view's splits to the closed set `splits`, within its budget.
  void add_view(const ViewRequest& view, double t, std::vector<uint8_t>& splits) const;
  const ProgressiveMesh* mesh_;
  const SplitDependencies* deps_;
  std::vector<Face> full_faces_;  // the fully refined mesh, by progressive face id
  // split_spheres() of the last step a view asked for (not thread-safe, as the navigator).
  mutable std::vector<float> spheres_;
  mutable double spheres_step_ = -1;
};

}  // namespace dynpm
