// dynpm/eval.h — how far apart two surfaces are: the Metro-style Hausdorff distance
// (Cignoni, Rocchini, Scopigno 1998) that the paper's Tables 1–3 report.
//
//   for each direction (A → B, then B → A):
//     sample the first surface: every vertex, points along every edge, and points on the faces
//       in proportion to area (≈ 10 per face of the larger mesh by default)
//     for each sample p: d(p) = distance to the closest point of the other surface (a BVH)
//     one-sided max = max d(p) over all samples; mean and RMS over the face samples
//   Hausdorff = max of the two one-sided maxima; percentages are of a reference diagonal
//
// Shapes: a topology is #F faces × 4 corner slots (kNoVertex in slot 3 for a triangle);
// positions are one time step, 3 · #V floats (x0 y0 z0 x1 …). Quads are measured as four
// triangles through their centroid (the paper's §5 star triangulation); the mesh itself is
// never changed. Results are deterministic for a given seed, whatever the number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "dynpm/core.h"

namespace dynpm {

using Point3 = std::array<double, 3>;

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection, §5.1.5).
// Degenerate triangles (a segment or a point) are handled.
Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b,
                                 const Point3& c);

// One triangle of the measured surface: a mesh triangle, or one of the four triangles of a quad
// (a, b, centroid), (b, c, centroid), … with centroid = float((a + b + c + d) / 4 in double).
struct SurfaceTriangle {
  std::array<float, 3> a, b, c;
  uint32_t face = kNoIndex;  // the topology face it belongs to
};

// The triangles of one step of a mesh, quads star-triangulated, in face order (a quad's four
// triangles follow its corners). Faces with fewer than 3 corners are skipped. Indices must be in
// range and positions hold 3 · vertex_count floats (asserted).
std::vector<SurfaceTriangle> surface_triangles(const Topology& topology,
                                               std::span<const float> positions);
// The same into `out`, replacing its contents (its memory is reused).
void surface_triangles(const Topology& topology, std::span<const float> positions,
                       std::vector<SurfaceTriangle>& out);

// A bounding-volume hierarchy over triangles for exact closest-point queries: binned-SAH build
// (a quad's four triangles stay together in one leaf), nodes flattened depth first, traversal
// nearest child first and pruned by the best distance so far. Immutable after build; queries
// may run from many threads at once.
class TriangleBvh {
 public:
  struct Hit {
    double squared_distance = std::numeric_limits<double>::infinity();
    Point3 point{0, 0, 0};         // closest point on the surface
    uint32_t triangle = kNoIndex;  // index into the triangles given to the constructor
    uint32_t face = kNoIndex;      // that triangle's topology face
    // The point's barycentric coordinates on that triangle: point ≈ w0·a + w1·b + w2·c, each
    // ≥ 0, summing to 1 (a degenerate triangle: its nearest corner's weight is 1 where the
    // plane's solve fails). A field on the surface is interpolated with them.
    std::array<double, 3> weights{1, 0, 0};
  };

  TriangleBvh() = default;
  // Builds on up to `threads` threads (0: all cores); the tree is the same for any count.
  // Consecutive triangles of one face (up to 4: a quad's star) form one item of the build.
  explicit TriangleBvh(std::span<const SurfaceTriangle> triangles, unsigned threads = 0);

  // New positions for the same triangles (same count, same faces, same order as given to the
  // constructor): the tree is kept and its boxes are recomputed bottom up, in place, so answers
  // stay exact. Returns false, leaving the tree to be rebuilt, when the boxes grew so much
  // that queries would slow down (their summed area over 1.5× what a fresh build had then).
  bool refit(std::span<const SurfaceTriangle> triangles);

  // The closest point of all triangles to p, or a Hit with triangle == kNoIndex if none is
  // closer than sqrt(max_squared_distance). Coordinates must be finite.
  Hit closest(const Point3& p,
              double max_squared_distance = std::numeric_limits<double>::infinity()) const;

  // No tree is deeper than this (the build halves ranges below a fixed depth).
  static constexpr size_t kMaxDepth = 96;

  // The memory of a run of queries. Samples come in runs of close neighbours: a query with a
  // cursor tests the previous answer's leaf first, then climbs towards the root, entering only
  // the sibling subtrees that may hold something closer, and stops at the first ancestor whose
  // clearance (a lower bound on the distance to every triangle outside it, remembered from
  // earlier queries less the distance travelled since: box distances are 1-Lipschitz) shows
  // that nothing outside can beat the best so far. One cursor per thread; the answer is the
  // same as without one.
  struct Cursor {
    uint32_t leaf = kNoIndex;      // the previous answer's leaf
    uint32_t triangle = kNoIndex;  // the previous answer (leaf order)
    Point3 last{0, 0, 0};          // the previous query point
    double travel = 0;             // length of the path of query points so far
    // Indexed by depth of the leaf's ancestors (0: the root), stamped with `travel` (value +
    // travel when measured, so value now ≥ stamped − travel): clearance[d] bounds the distance
    // to everything outside the ancestor at depth d (−∞: unknown), sibling[d] to the subtree
    // of the other child of the ancestor at depth d − 1.
    std::array<double, kMaxDepth> clearance;
    std::array<double, kMaxDepth> sibling;
  };
  // Without weights, Hit::weights is left at {1, 0, 0} (a distance alone does not need them).
  // With `enough` > 0 the search stops at the first triangle it meets that is nearer than
  // sqrt(enough), the previous answer's triangle tested first: the hit is then that one, not
  // necessarily the closest (a sample that cannot raise a maximum needs no more); the cursor
  // moves to it all the same.
  Hit closest(const Point3& p, Cursor& cursor, bool with_weights = true, double enough = 0) const;

  // Every triangle closer to p than sqrt(max_squared_distance), with its closest point and
  // weights, appended to `out` in no set order.
  void within(const Point3& p, double max_squared_distance, std::vector<Hit>& out) const;
  // Every triangle in a leaf whose box overlaps the box [lo, hi] (a superset of the triangles
  // that do), as indices given to the constructor, appended to `out` in no set order. Defined
  // in self_crossing.cpp, its one user.
  void overlapping(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                   std::vector<uint32_t>& out) const;

  size_t triangle_count() const { return triangles_.size(); }
  size_t node_count() const { return nodes_.size(); }
  bool empty() const { return triangles_.empty(); }

  // Flattened node: a leaf holds triangles [first, first + count) in leaf order; an inner
  // node (count == 0) has its left child right after it and its right child at `first`.
  struct Node {
    std::array<float, 3> lo, hi;
    uint32_t first = 0;
    uint32_t count = 0;
  };

 private:
  struct Best;
  // `tested`: a triangle already in `best`, not tested again.
  void descend(const Point3& p, uint32_t node, Best& best, double enough = 0,
               uint32_t tested = kNoIndex) const;
  Hit hit(const Best& best, bool with_weights = true) const;

  std::vector<Node> nodes_;
  std::vector<uint32_t> parent_;            // per node; kNoIndex for the root
  std::vector<uint8_t> depth_;              // per node; 0 for the root
  std::vector<SurfaceTriangle> triangles_;  // in leaf order
  std::vector<uint32_t> leaf_of_;           // per triangle in leaf order: its leaf node
  std::vector<uint32_t> original_;          // leaf order → index given to the constructor
  std::vector<uint32_t> leaf_position_;     // index given to the constructor → leaf order
  double box_area_ = 0;                     // summed half areas of the boxes after the build
};

// ---------------------------------------------------------------------------------------------
// Hausdorff distance

struct HausdorffOptions {
  // Area samples on each surface = samples_per_face × the face count of the larger mesh
  // (Metro's default is ≈ 10 per face), unless face_samples is set.
  double samples_per_face = 10;
  // If > 0: the number of area samples on each surface (Metro's -n), overriding the above.
  uint64_t face_samples = 0;
  // The mean and RMS are taken over every K-th area sample of a surface, K the least that
  // leaves at most this many (0: over all of them). Every area sample still counts for the
  // maximum, but one that cannot raise it — its previous answer's triangle is already nearer
  // than the largest distance so far — needs no search. A mean over a million samples has a
  // standard error of a thousandth of the distances' spread, and on a 1 M-face mesh the
  // search for every one of 10 M samples is most of the time (docs/eval.md).
  uint64_t mean_samples = uint64_t{1} << 20;
  // Metro also samples the vertices and the edges, where maxima often sit (corners, creases).
  // Edge samples are spaced like the area samples: sqrt(area / face samples) apart.
  bool sample_vertices = true;
  bool sample_edges = true;
  // Seeds the sampling; equal seeds give equal results on any machine and thread count.
  uint64_t seed = 1;
  // Percentages are of this length; 0 means the diagonal of A's bounding box (over all steps
  // in hausdorff_steps). Pass the original's diagonal when A is not the original.
  double reference_diagonal = 0;
  // Worker threads; 0 means std::thread::hardware_concurrency().
  unsigned threads = 0;
  // Without fields, the samples of a direction whose other surface has at least this many
  // triangles are measured in space order rather than in the order they are drawn in (a level's
  // faces in progressive order scatter them): the queries then find the tree in the caches.
  // Every result is the same either way; below about 64 Ki triangles the tree fits in the
  // caches and the reordering only costs.
  size_t space_order_triangles = size_t{1} << 16;
  // The field error's correspondence tolerance, absolute: points of the other surface within
  // this distance of the closest one are as good a match for a sample, and its field error is
  // the smallest difference among them. Where two sheets touch (a crash fold's contact), the
  // closest point may lie on the wrong sheet by less than the positions' stored bound; pass that
  // bound here. 0: the closest point alone.
  double field_tolerance = 0;
  // The field error's facing correspondence, absolute (docs/eval.md, "Facing correspondence"):
  // > 0, a sample is matched to the closest point of the other surface whose triangle faces
  // the sample's way (normals less than 90° apart) if one lies within this much farther than
  // the closest point overall, else to the closest point. Where a fold's sheets touch, the
  // closest point may lie on the other sheet, which faces the other way. 0: the closest point
  // alone. FieldDistance holds both measures.
  double field_facing_reach = 0;
};

// Distances from samples on one surface to the other surface.
struct OneSidedDistance {
  double max = 0;          // over every sample (vertices, edges, faces)
  double mean = 0;         // over the area samples: the area-weighted mean distance
  double rms = 0;          // over the area samples: root of the area-weighted mean squared distance
  Point3 max_at{0, 0, 0};  // the sample where the max was found
  uint64_t vertex_samples = 0, edge_samples = 0, face_samples = 0;
};

// The field error (issue 18): a scalar field on each surface compared at the same samples as
// the distance. For a sample p on one surface, the field's value at p (a node field
// interpolated linearly over p's triangle, a quad's centroid carrying the mean of its corners;
// an element field constant per face) against its value at p's closest point on the other
// surface, interpolated there likewise from the closest point's barycentric coordinates (or
// the best of the points within HausdorffOptions::field_tolerance of it). An element field has
// no value at a vertex or on an edge, so its error uses the area samples only.
struct SurfaceField {
  FieldLocation location = FieldLocation::kNode;
  std::span<const float> values;  // one per vertex (node) or per face (element) of the topology
};
struct FieldPair {
  SurfaceField a, b;  // the field on A and on B
};
// Largest |value on one surface − value at the corresponding point of the other|, absolute:
// the facing correspondence when HausdorffOptions::field_facing_reach > 0, else the closest
// point; the `nearest` values are always the closest point's (the measure before facing).
struct FieldDistance {
  double a_to_b = 0, b_to_a = 0;
  double max = 0;          // the two-sided field error: max(a_to_b, b_to_a)
  Point3 max_at{0, 0, 0};  // the sample where it was found
  double nearest_a_to_b = 0, nearest_b_to_a = 0, nearest = 0;
  // The mean |difference| over the area samples of both directions (an area-weighted mean, as
  // HausdorffResult::mean), at the facing match (the closest point without a facing reach),
  // without the position tolerance's search.
  double mean = 0;
};

struct HausdorffResult {
  OneSidedDistance a_to_b;            // samples on A, distances to B
  OneSidedDistance b_to_a;            // samples on B, distances to A
  double hausdorff = 0;               // two-sided: max(a_to_b.max, b_to_a.max)
  double mean = 0;                    // two-sided: (a_to_b.mean + b_to_a.mean) / 2
  double rms = 0;                     // two-sided: sqrt((a_to_b.rms² + b_to_a.rms²) / 2)
  double diagonal = 0;                // the reference length of the percentages
  std::vector<FieldDistance> fields;  // one per FieldPair measured

  double percent(double distance) const { return diagonal > 0 ? 100.0 * distance / diagonal : 0.0; }
};

// ---------------------------------------------------------------------------------------------
// Measuring one mesh many times (eval: every level against the original at every step): the
// work that depends on the topology only is done once, the work of one step (triangles, BVH)
// once per step, whatever the number of meshes it is measured against.

// A topology checked, and its sample places listed: the vertices in a face, every edge once.
struct SurfaceTopology {
  const Topology* topology = nullptr;  // not owned: must outlive this
  std::vector<uint32_t> vertices;      // ascending
  std::vector<Edge> edges;             // grouped by smaller vertex
};
// Errors: a mesh without faces, a face with fewer than 3 corners, a corner out of range; the
// message starts with `name`.
Result<SurfaceTopology> prepare_topology(const char* name, const Topology& topology);

// One step of a prepared topology: its positions, triangles, their BVH, area and edge length.
struct Surface {
  const SurfaceTopology* topology = nullptr;  // not owned: must outlive this
  std::vector<float> positions;
  std::vector<SurfaceTriangle> triangles;  // surface_triangles()
  TriangleBvh bvh;
  double area = 0, edge_length = 0;  // sums over the triangles and the edges
};
// Errors: positions not 3 · vertex_count floats, a non-finite coordinate. The BVH is built on
// up to `threads` threads (0: all cores).
Result<Surface> prepare_surface(const char* name, const SurfaceTopology& topology,
                                std::span<const float> positions, unsigned threads = 0);
// The same surface at another step: the same result as prepare_surface() on these positions,
// made in place in the memory of the last step (no allocation) with the BVH refitted rather
// than rebuilt (TriangleBvh::refit()). Errors as prepare_surface(); on error the surface is
// unusable until the next successful update.
Status update_surface(const char* name, Surface& surface, std::span<const float> positions,
                      unsigned threads = 0);

// The faces of one step of a surface that pass through another face sharing no vertex with
// them, ascending: a sheet through a sheet, as a crash run without a contact definition lets
// happen (docs/eval.md, "Sheets through each other"). Two faces cross where an edge of one's
// triangles (a quad's star) pierces a triangle of the other; coplanar overlaps are not
// counted. There a sample's closest point may lie on the crossing sheet however close the
// level is, so the field error measures the crossing, not the level.
std::vector<uint32_t> self_crossing_faces(const Surface& surface);
// A against B, prepared; the same numbers as hausdorff() below on the same positions. With
// fields, result.fields holds one FieldDistance per FieldPair. Errors: a field with the wrong
// number of values or a non-finite value.
Result<HausdorffResult> hausdorff(const Surface& a, const Surface& b,
                                  const HausdorffOptions& options,
                                  std::span<const FieldPair> fields = {});

// A against B at one step each. Errors (not asserts, the inputs may come from files): positions
// not 3 · vertex_count floats, a corner out of range or a face with fewer than 3 corners, a
// non-finite coordinate, a mesh without any face.
Result<HausdorffResult> hausdorff(const Topology& a_topology, std::span<const float> a_positions,
                                  const Topology& b_topology, std::span<const float> b_positions,
                                  const HausdorffOptions& options = {});

// A value over the steps of an animation.
struct OverSteps {
  double mean = 0, max = 0;
};

struct HausdorffSteps {
  std::vector<HausdorffResult> steps;  // step t: A at t against B at t
  double diagonal = 0;                 // every step's percentages use this one length
  // Over the steps, of each step's value.
  OverSteps hausdorff, mean, rms, a_to_b_max, b_to_a_max;
};

struct StepsOptions {
  HausdorffOptions hausdorff;
  // Called after each step (done, total); may be empty. src/ never prints: the caller may.
  std::function<void(size_t, size_t)> progress;
};

// Every step t of A against step t of B. If one side has a single step it is compared with every
// step of the other; otherwise the step counts must be equal. Every step is sampled with
// options.seed, so step t's distances equal hausdorff() on the two steps' positions. The default
// reference diagonal is that of A's bounding box over all steps. Steps are read one at a time
// (two position arrays in memory); each step's samples run in parallel.
Result<HausdorffSteps> hausdorff_steps(const Topology& a_topology, const FrameSource& a_frames,
                                       const Topology& b_topology, const FrameSource& b_frames,
                                       const StepsOptions& options = {});

// The steps seen as one result: max over steps for maxima (with where), mean over steps for
// means, root of the mean square over steps for RMS values, sample counts summed.
HausdorffResult as_one_result(const HausdorffSteps& steps);

}  // namespace dynpm
