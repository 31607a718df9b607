// dynpm/core.h — one topology, many geometries.
//
// A crash or forming result is ONE face list over a fixed set of nodes and m arrays of node
// positions, one per time step (Wundrak et al. 2006, §2: A = {V_0, …, V_m-1}), never m meshes.
//
//   Topology     #F faces × 4 corner slots, kNoVertex in slot 3 for triangles (fixed stride,
//                no arity array: FE shells are triangles and quads); per face a part id (FE
//                "PID") and the original element number; per vertex the original node number.
//   FrameSource  yields the #V × xyz float positions of time step t on demand, so a 5 M-node ×
//                100-step result never has to sit in memory whole.
//   Frames       the in-memory FrameSource: one contiguous xyz array per step, plus step times.
//   Animation    Topology + Frames + scalar result fields per step, per node or per element.
//   Adjacency    derived on demand: vertex → faces, unique edges → faces (CSR), vertex kinds.
//   validate()   (M1) manifold with boundary, (M2) inner-vertex valence ≥ 3, (M3) face degree
//                ≥ 3, indices in range, no repeated corner, finite positions, equal step sizes.
//                Every problem is returned with its location; non-manifold edges and vertices
//                are accepted and reported as features the simplifier must keep.
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

#include "dynpm/result.h"

namespace dynpm {

inline constexpr uint32_t kNoVertex = 0xffffffffu;  // empty 4th corner of a triangle
inline constexpr uint32_t kNoIndex = 0xffffffffu;   // "no face / vertex / step" in reports

// A triangle (a, b, c, kNoVertex) or a quad (a, b, c, d); corners in counter-clockwise order
// seen from the front. Edges join consecutive corners; a quad's diagonals are not edges.
struct Face {
  std::array<uint32_t, 4> v{kNoVertex, kNoVertex, kNoVertex, kNoVertex};

  bool is_triangle() const { return v[3] == kNoVertex; }
  // Number of used corner slots: 3 or 4 in a valid mesh, fewer if (M3) is broken.
  int degree() const {
    return (v[0] != kNoVertex) + (v[1] != kNoVertex) + (v[2] != kNoVertex) + (v[3] != kNoVertex);
  }
  bool contains(uint32_t vertex) const;
  bool operator==(const Face&) const = default;
};

// A part's name as the input gives it: an LS-DYNA part title, an Exodus element block name, an
// OBJ group or object name. Made by clean_part_name(), so it is valid UTF-8 of 1 … 255 bytes
// without control characters (names come from untrusted files and are shown in a browser).
struct PartName {
  int32_t id = 0;
  std::string name;
  bool operator==(const PartName&) const = default;
};
inline constexpr size_t kMaxPartName = 255;
// `raw` as a part name: blanks and NULs at either end removed (fixed-width title fields), bytes
// that are not UTF-8 and control characters each as U+FFFD, cut to kMaxPartName bytes at a
// character boundary; "" when nothing is left (the part then has its id only).
std::string clean_part_name(std::string_view raw);
// Whether `name` is what clean_part_name() makes: 1 … kMaxPartName bytes of UTF-8 with no
// control character and no blank at either end (the .dpm readers' check).
bool is_clean_part_name(std::string_view name);

// The connectivity shared by every time step. The per-face and per-vertex arrays are parallel
// to faces and to the vertex range [0, vertex_count); validate() checks that they are.
struct Topology {
  uint32_t vertex_count = 0;
  std::vector<Face> faces;
  std::vector<int32_t> part_ids;     // #F, FE part (PID); 0 where the input has none
  std::vector<int64_t> element_ids;  // #F, original element number
  std::vector<int64_t> node_ids;     // #V, original node number
  // The parts that have a name, ascending id, each once (parts without one are absent).
  std::vector<PartName> part_names;

  // A topology of n vertices numbered 1..n, with no faces yet.
  static Topology with_vertices(uint32_t n);
  // Appends a face; element_id 0 means "the next number after the last face's".
  void add_triangle(uint32_t a, uint32_t b, uint32_t c, int32_t part = 0, int64_t element_id = 0);
  void add_quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d, int32_t part = 0,
                int64_t element_id = 0);
  void add_face(const Face& face, int32_t part = 0, int64_t element_id = 0);
  // Room for `count` faces in all, so that a reader's add_face() calls do not grow the arrays.
  void reserve_faces(size_t count);

  size_t face_count() const { return faces.size(); }
  size_t triangle_count() const;
  size_t quad_count() const;
  // Distinct part ids, ascending.
  std::vector<int32_t> parts() const;
  // The name of part `id`, "" when it has none.
  std::string_view part_name(int32_t id) const;
  // Sets part `id`'s name (clean_part_name() of `raw`; nothing when that is ""), keeping
  // part_names sorted by id.
  void set_part_name(int32_t id, std::string_view raw);
  // Frees the faces and their part and element ids, capacity and all (28 B a face), for a
  // caller done with them; the vertex count, node ids and part names stay (a FrameSource may
  // name vertices by their ids).
  void release_faces();
};

// Where a result field lives: one value per vertex (a solver's nodal result) or one per face
// (an element result: shell plastic strain, stress, thickness).
enum class FieldLocation : uint8_t { kNode = 0, kElement = 1 };
const char* to_string(FieldLocation location);  // "node", "element"

// What a result field is: its name as the input gives it ("PEEQ", "S_MISES", "thickness"),
// where it lives and its unit ("" when the input names none).
struct FieldInfo {
  std::string name;
  FieldLocation location = FieldLocation::kNode;
  std::string unit;
  bool operator==(const FieldInfo&) const = default;
};

// Positions of every vertex at time step t, read on demand.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual uint32_t vertex_count() const = 0;
  virtual size_t step_count() const = 0;
  virtual double step_time(size_t t) const = 0;
  // Fills out (3 · vertex_count floats: x0 y0 z0 x1 …) with step t. Sources that read files
  // return an error naming the file and place; in-memory sources never fail.
  virtual Status read_step(size_t t, std::span<float> out) const = 0;
  // Number of xyz floats step t holds, when a source can know it without reading the step.
  virtual size_t step_float_count(size_t /*t*/) const { return size_t{vertex_count()} * 3; }
  // True when read_step() and read_field() may run on several threads at once (the source keeps
  // no state between reads); for_each_step() then decodes several steps at a time.
  virtual bool parallel_reads() const { return false; }

  // Scalar result fields the source can deliver at every step (plastic strain, von Mises
  // stress, thickness, |V| …), per node or per element, read one step at a time like the
  // positions.
  virtual std::vector<FieldInfo> fields() const { return {}; }
  // The names of fields(), in order.
  std::vector<std::string> field_names() const;
  // Fills out with field `field` (an index into fields()) at step t: vertex_count() floats for
  // a node field, one per face of the source's topology (in its face order) for an element field.
  virtual Status read_field(size_t field, size_t t, std::span<float> out) const;
};

// All steps in memory, one contiguous xyz array per step.
class Frames final : public FrameSource {
 public:
  Frames() = default;
  explicit Frames(uint32_t vertex_count) : vertex_count_(vertex_count) {}

  // Appends a step. Its size is not asserted: validate() reports a step whose vertex count
  // differs, so readers can hand over what the file said and let validation name the problem.
  void add_step(std::vector<float> xyz, double time);
  std::span<const float> step(size_t t) const { return steps_[t]; }
  std::span<float> step(size_t t) { return steps_[t]; }
  void set_vertex_count(uint32_t n) { vertex_count_ = n; }

  uint32_t vertex_count() const override { return vertex_count_; }
  size_t step_count() const override { return steps_.size(); }
  double step_time(size_t t) const override { return times_[t]; }
  Status read_step(size_t t, std::span<float> out) const override;
  size_t step_float_count(size_t t) const override { return steps_[t].size(); }
  bool parallel_reads() const override { return true; }

 private:
  uint32_t vertex_count_ = 0;
  std::vector<std::vector<float>> steps_;
  std::vector<double> times_;
};

// A scalar result (plastic strain, von Mises stress, …) at every step.
struct ScalarField {
  std::string name;
  std::vector<std::vector<float>> steps;  // #steps × (#V for a node field, #F for an element one)
  FieldLocation location = FieldLocation::kNode;
  std::string unit;

  FieldInfo info() const { return {name, location, unit}; }
};

struct Animation {
  Topology topology;
  Frames frames;
  std::vector<ScalarField> fields;

  size_t step_count() const { return frames.step_count(); }
};

// An animation whose steps stay where they are (on disk) until asked for.
struct AnimationStream {
  Topology topology;
  std::unique_ptr<FrameSource> frames;
  std::vector<std::string> warnings;  // reader notes the caller may show (never printed by src/)
};

// Reads every step of a stream into memory.
Result<Animation> load_all_steps(AnimationStream stream);

// One pass over `steps` of `frames`: use(i, xyz) gets steps[i] on the calling thread, in the
// order given. Up to `threads` steps (0: one per hardware thread) are read at once, each into
// its own buffer of 3 · vertex_count floats, when the source allows parallel reads; what use()
// sees does not depend on `threads`. The first error, of a read or of use() in that order,
// ends the pass.
Status for_each_step(const FrameSource& frames, std::span<const size_t> steps, unsigned threads,
                     const std::function<Status(size_t, std::span<const float>)>& use);

// ---------------------------------------------------------------------------------------------
// Derived connectivity

struct Edge {
  uint32_t a = 0, b = 0;  // a < b
};

// What the neighbourhood of a vertex looks like; flags combine.
enum VertexKind : uint8_t {
  kInteriorVertex = 0,
  kBoundaryVertex = 1 << 0,      // on an edge with one face
  kOnNonManifoldEdge = 1 << 1,   // on an edge with three or more faces (a T-joint of shells)
  kNonManifoldFan = 1 << 2,      // its faces form more than one fan (bow-tie, pinched shells)
  kUnreferencedVertex = 1 << 3,  // in no face
};

// Vertex → faces and edge → faces in compressed rows; built in O(#F) from a topology whose
// indices are in range (validate() first for untrusted input). Immutable: rebuild after edits.
class Adjacency {
 public:
  static Adjacency build(const Topology& topology);

  uint32_t vertex_count() const { return static_cast<uint32_t>(vertex_face_start_.size() - 1); }
  std::span<const uint32_t> faces_of_vertex(uint32_t v) const;

  size_t edge_count() const { return edges_.size(); }
  Edge edge(size_t e) const { return edges_[e]; }
  std::span<const uint32_t> faces_of_edge(size_t e) const;
  std::optional<size_t> find_edge(uint32_t a, uint32_t b) const;
  // Edges are grouped by their smaller vertex: the edges (v, w) with v < w.
  std::span<const Edge> edges_from(uint32_t v) const;

  uint8_t vertex_kind(uint32_t v) const { return vertex_kind_[v]; }
  // Vertices the simplifier must keep in place or slide only along their feature: those on a
  // non-manifold edge and those with a non-manifold fan.
  bool is_feature_vertex(uint32_t v) const {
    return (vertex_kind_[v] & (kOnNonManifoldEdge | kNonManifoldFan)) != 0;
  }
  // The memory its arrays hold.
  uint64_t bytes() const;

 private:
  std::vector<uint32_t> vertex_face_start_, vertex_faces_;
  std::vector<uint32_t> vertex_edge_start_;  // edges_ grouped by smaller vertex
  std::vector<Edge> edges_;
  std::vector<uint32_t> edge_face_start_, edge_faces_;
  std::vector<uint8_t> vertex_kind_;
};

// Counts that describe a mesh's shape; the simplifier's invariants are stated in these terms.
struct TopologyStats {
  size_t vertices = 0, referenced_vertices = 0, faces = 0, triangles = 0, quads = 0;
  size_t edges = 0, boundary_edges = 0, boundary_loops = 0;
  size_t non_manifold_edges = 0, non_manifold_vertices = 0, components = 0, parts = 0;
  int64_t euler_characteristic = 0;  // V − E + F over referenced vertices
};
TopologyStats topology_stats(const Topology& topology, const Adjacency& adjacency);

// ---------------------------------------------------------------------------------------------
// Validation

enum class ProblemKind {
  kArraySize,                // part/element/node id arrays not parallel to faces/vertices
  kIndexOutOfRange,          // a corner names a vertex ≥ vertex_count
  kFaceDegree,               // (M3) fewer than 3 corners
  kRepeatedVertex,           // a corner appears twice in one face
  kDuplicateFace,            // two faces over the same vertex set
  kNonManifoldEdge,          // (M1) an edge with 3+ faces: accepted, kept as a feature
  kNonManifoldVertex,        // (M1) a vertex with several fans: accepted, kept as a feature
  kInnerValence,             // (M2) an inner vertex with fewer than 3 neighbours
  kInconsistentOrientation,  // two faces walk their shared edge the same way
  kUnreferencedVertex,       // a vertex in no face
  kStepVertexCount,          // a time step has another vertex count
  kNonFinitePosition,        // NaN or Inf coordinate
  kZeroAreaFace,             // a face whose corners lie on a line or coincide (at some step)
  kFieldSize,                // a scalar field has the wrong number of steps or values
  kUnreadableStep,           // a FrameSource failed to deliver a step
  kNoSteps,                  // an animation without any time step
};

enum class Severity {
  kError,    // the mesh cannot be processed
  kFeature,  // accepted; the simplifier keeps it (non-manifold edges and vertices)
  kWarning,  // processed, but worth knowing
};

struct Problem {
  ProblemKind kind;
  Severity severity;
  uint32_t face = kNoIndex;
  uint32_t vertex = kNoIndex;
  uint32_t step = kNoIndex;
  std::string message;  // names the rule and the location, e.g. "face 12: vertex 7 repeated"
};

inline constexpr size_t kProblemKindCount = static_cast<size_t>(ProblemKind::kNoSteps) + 1;

// Every problem found. So that a file full of NaNs cannot exhaust memory, the list keeps the
// first kMaxListedPerKind problems of each kind; count() always gives the full number.
struct ValidationReport {
  static constexpr size_t kMaxListedPerKind = 1000;

  std::vector<Problem> problems;
  std::array<size_t, kProblemKindCount> totals{};
  std::array<size_t, 3> severity_totals{};

  void add(Problem problem);
  bool ok() const { return count(Severity::kError) == 0; }
  size_t count(ProblemKind kind) const { return totals[static_cast<size_t>(kind)]; }
  size_t count(Severity severity) const { return severity_totals[static_cast<size_t>(severity)]; }
};

// Checks connectivity and, when given, every time step (up to four read and checked at once on
// the hardware's threads where the source allows parallel reads; the report is the same either
// way) and the fields.
ValidationReport validate(const Topology& topology, const FrameSource* frames = nullptr,
                          std::span<const ScalarField> fields = {});
// The same, handing back the adjacency it built for a caller that needs one too (empty when a
// face is out of range or repeats a corner, where no adjacency of the whole mesh exists).
ValidationReport validate(const Topology& topology, std::optional<Adjacency>& adjacency,
                          const FrameSource* frames = nullptr,
                          std::span<const ScalarField> fields = {});
inline ValidationReport validate(const Animation& animation) {
  return validate(animation.topology, &animation.frames, animation.fields);
}

// The proof that validate() found no error in a topology (its faces, its vertex count and the
// sizes of its id arrays), so that simplify() and build_dpm(), handed it
// (SimplifyOptions::checked), do not check the same mesh again. Only check_topology() makes one.
// It keeps a fingerprint of what it checked, never a reference: a proof of other faces (another
// topology, or this one changed since) proves nothing, and the mesh is checked as without it.
// It also carries the adjacency the check built, for the simplifier to take instead of building
// it again (about 0.5 s at a million faces).
class ValidationProof {
 public:
  bool proves(const Topology& topology) const { return fingerprint_ == fingerprint(topology); }
  // The adjacency of the checked topology, the first time it is asked for by any copy of this
  // proof (then nullopt: its memory goes with the taker).
  std::optional<Adjacency> take_adjacency() const;
  // The memory of the adjacency it still carries (0 once taken): held now, but given back before
  // the simplifier's peak, so a memory check before the work may count it as available.
  uint64_t adjacency_bytes() const { return *adjacency_ ? (*adjacency_)->bytes() : 0; }

 private:
  friend ValidationReport check_topology(const Topology&, std::optional<ValidationProof>&);
  ValidationProof(uint64_t fingerprint, std::optional<Adjacency> adjacency);
  static uint64_t fingerprint(const Topology& topology);
  uint64_t fingerprint_;
  std::shared_ptr<std::optional<Adjacency>> adjacency_;  // shared by the copies
};
// validate(topology), with the proof in `proof` when it found no error (else empty).
ValidationReport check_topology(const Topology& topology, std::optional<ValidationProof>& proof);

const char* to_string(ProblemKind kind);
const char* to_string(Severity severity);

// ---------------------------------------------------------------------------------------------
// Geometry helpers

struct BoundingBox {
  std::array<float, 3> min{0, 0, 0}, max{0, 0, 0};
  bool empty = true;

  void extend(std::span<const float> xyz);  // a whole step's positions
  void extend(const BoundingBox& other);
  double diagonal() const;
};

// ---------------------------------------------------------------------------------------------
// Files

// The bytes of a regular file; errors name the file and the cause (missing, a directory, …).
Result<std::string> read_file(const std::string& path);
// A regular file's bytes mapped read-only: pages come from disk when touched, so a reader that
// stops early reads only what it looked at (a .dpm read to a coarse level). A file replaced by
// rename while mapped stays readable (its old inode); one truncated in place is not supported.
class MappedFile {
 public:
  static Result<MappedFile> open(const std::string& path);
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();
  std::string_view bytes() const { return {static_cast<const char*>(data_), size_}; }

 private:
  MappedFile() = default;
  void* data_ = nullptr;
  size_t size_ = 0;
};
// The first up-to-n bytes of a file (for format signatures and header comments).
Result<std::string> read_file_head(const std::string& path, size_t n);
// Writes bytes to "<path>.tmp-<pid>-<n>" beside path, flushes, and renames it over path. On any
// failure the temporary file is removed and path is left as it was. Removes path's stale
// temporaries first (remove_stale_temporaries) and syncs the folder after, unless path is itself
// a staged file of this process (StagedOutputs), whose commit does both for all its targets.
Status write_file_atomically(const std::string& path, std::string_view bytes);
// Removes what killed runs left beside path: its temporary files ("<path>.tmp-<pid>-<n>",
// "<stem>.tmp-<pid><ext>" and the latter's own "….tmp-<pid>-<n>") whose process is gone from this
// machine and that were last written more than a minute ago (a writer on another machine sharing
// the folder is still writing, or has only just finished). Returns how many were removed; errors
// are ignored.
size_t remove_stale_temporaries(const std::string& path);
// True when no process with this id runs on this machine (kill(pid, 0) gives ESRCH); a live
// process, or another user's (EPERM), has not ended: what it left is not ours to remove.
bool process_has_ended(long pid);
// The same for many targets (the files of a multi-file output): each folder is listed once.
size_t remove_stale_temporaries(std::span<const std::string> paths);
// How many folder listings remove_stale_temporaries has made in this process (tests check that a
// multi-file output lists its folder once, not once per file).
size_t stale_temporary_scans();
// fsync of the folder holding path, so a rename into it survives a power cut (best effort).
void sync_directory_of(const std::string& path);

// ---------------------------------------------------------------------------------------------
// Memory

// For main(): asks the C library to map arrays of 1 MB and more on their own and to return them
// to the system when freed. glibc otherwise raises that limit after the first such array is
// freed, and later step buffers and adjacency arrays stay with the process once freed: about
// 60 B per vertex more at the simplifier's peak. Process-wide; does nothing on other C libraries.
void return_freed_arrays_to_the_system();

// Huge pages: where the kernel gives transparent huge pages only to memory that asks for them
// (its "madvise" mode, Debian's default), glibc asks when its glibc.malloc.hugetlb tunable is 1,
// and it reads its tunables only at start-up; so the tool starts itself again with it
// (cli/huge_pages.h). On 2 MiB pages a build takes a quarter to a third less time: its arrays
// are filled with 512 times fewer page faults (docs/BENCHMARKS.md "Huge pages").
// The GLIBC_TUNABLES value to start again with, given the present one (nullptr: unset) and the
// first line of /sys/kernel/mm/transparent_hugepage/enabled; nullopt when not to start again:
// the kernel's mode is another, or the tunable is set already (glibc.malloc.hugetlb=0 is how to
// opt out).
std::optional<std::string> tunables_with_huge_pages(const char* tunables,
                                                    std::string_view kernel_mode);

// The memory this process can still take, in bytes: the least of the free memory
// (MemAvailable), what the address-space limit (RLIMIT_AS, `ulimit -v`) leaves above the address
// space already used, and what the cgroup's limit leaves (v2 memory.max − memory.current, v1
// memory.limit_in_bytes − memory.usage_in_bytes). 0 when none of them can be read.
uint64_t available_memory_bytes();

// ---------------------------------------------------------------------------------------------
// Progress

// How a long job tells how far it is: the phase ("collapsing"), the work done and the work in
// all, in the phase's own items (steps, vertices). A phase ends with done == total. Called on
// the caller's thread, at most every few thousand items; may be empty (nobody listens).
using ProgressCallback = std::function<void(std::string_view phase, size_t done, size_t total)>;

}  // namespace dynpm
