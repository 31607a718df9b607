// Exact closest-point queries on a triangulated surface: the measuring half of the Metro-style
// Hausdorff distance (hausdorff.cpp and sample_jobs.cpp are the sampling half).
// closest_point_on_triangle() follows Ericson, Real-Time Collision Detection (2005), §5.1.5:
// the plane of the triangle is cut into seven Voronoi regions (three vertices, three edges, the
// face) and p's region is found from six dot products, without a square root.
// TriangleBvh is a bounding-volume hierarchy built top down by the surface area heuristic
// (MacDonald and Booth 1990) evaluated in 16 bins along the longest axis of the centroids
// (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"). Nodes are
// stored depth first in one array, a left child right after its parent. A query descends into
// the nearer child first and skips every box farther away than the best triangle so far, so
// the answer is the exact minimum over all triangles: pruning only skips boxes that cannot hold
// anything closer. Samples come in runs of close neighbours, so a query may start from the
// previous answer's leaf (a Cursor) and climb towards the root: the leaf's distance bounds the
// search at once, and box distances remembered from earlier queries let the climb stop early.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <exception>
#include <thread>

#include "dynpm/eval.h"

namespace dynpm {
namespace {

inline Point3 sub(const Point3& a, const Point3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot(const Point3& a, const Point3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Point3 along(const Point3& a, const Point3& d, double t) {
  return {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
}
inline Point3 to_point(const std::array<float, 3>& f) { return {f[0], f[1], f[2]}; }

Point3 closest_point_on_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Point3 ab = sub(b, a);
  const double length2 = dot(ab, ab);
  if (length2 <= 0) return a;
  return along(a, ab, std::clamp(dot(sub(p, a), ab) / length2, 0.0, 1.0));
}

double squared_distance(const Point3& a, const Point3& b) {
  const Point3 d = sub(a, b);
  return dot(d, d);
}

// A degenerate triangle has no face region: its closest point lies on one of its sides.
Point3 closest_point_on_sides(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  Point3 best = closest_point_on_segment(p, a, b);
  for (const Point3& q : {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
    if (squared_distance(p, q) < squared_distance(p, best)) best = q;
  return best;
}

// Barycentric coordinates of q, a point of triangle (a, b, c), from the 2 × 2 normal equations
// of q − a = v·(b − a) + w·(c − a), clamped to the triangle against rounding. A degenerate
// triangle (no plane) gives its corner nearest to q.
std::array<double, 3> barycentric(const Point3& q, const Point3& a, const Point3& b,
                                  const Point3& c) {
  const Point3 e0 = sub(b, a), e1 = sub(c, a), e2 = sub(q, a);
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
  const double denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 1e-12 * d00 * d11)) {
    const double da = squared_distance(q, a), db = squared_distance(q, b),
                 dc = squared_distance(q, c);
    if (da <= db && da <= dc) return {1, 0, 0};
    return db <= dc ? std::array<double, 3>{0, 1, 0} : std::array<double, 3>{0, 0, 1};
  }
  const double d20 = dot(e2, e0), d21 = dot(e2, e1);
  const double v = std::max(0.0, (d11 * d20 - d01 * d21) / denominator);
  const double w = std::max(0.0, (d00 * d21 - d01 * d20) / denominator);
  const double u = std::max(0.0, 1 - v - w), sum = u + v + w;
  return {u / sum, v / sum, w / sum};
}

double squared_distance_to_box(const Point3& p, const TriangleBvh::Node& node) {
  // Branch-free: the gap along an axis is lo − p below the box, p − hi above it, else 0.
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double below = double(node.lo[k]) - p[k], above = p[k] - double(node.hi[k]);
    const double gap = std::max(std::max(below, above), 0.0);
    d2 += gap * gap;
  }
  return d2;
}

struct Box {
  std::array<float, 3> lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  static constexpr float kInf = std::numeric_limits<float>::infinity();

  void extend(const std::array<float, 3>& p) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  void extend(const Box& b) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
  }
  bool empty() const { return lo[0] > hi[0]; }
  // Half the surface area: the SAH only compares areas.
  double half_area() const {
    if (empty()) return 0;
    const double x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return x * y + y * z + z * x;
  }
};

double half_area(const TriangleBvh::Node& n) { return Box{n.lo, n.hi}.half_area(); }

// Top-down binned-SAH construction over items: runs of up to four consecutive triangles of one
// face (a quad's star, which no split would separate usefully), or single triangles. The items'
// boxes sit in one array that is partitioned in place, so every pass over a node's range reads
// memory in order; a child's bounds come from its parent's bins, so each level costs one binning
// pass and one partition. Large subtrees are built on their own threads into their own node
// arrays and spliced in afterwards: the tree is the same whatever the number of threads.
class BvhBuilder {
 public:
  static constexpr int kBins = 16;
  static constexpr uint32_t kMaxLeafTriangles = 8;  // a leaf never holds more (unless one item)
  static constexpr double kTraversalCost = 1.0;     // relative to one triangle test
  // Deeper than this, splits halve the range (median of the centroids), so no input can make
  // the tree deeper than kSahDepth + log2(#items) and overflow a query's stack.
  static constexpr int kSahDepth = 40;
  static_assert(kSahDepth + 34 < TriangleBvh::kMaxDepth);
  static constexpr uint32_t kParallelMinimum = 1u << 15;  // smaller subtrees: one thread

  struct Item {
    Box box;
    std::array<float, 3> centroid;
    uint32_t first;  // its triangles: [first, first + count) of the input
    uint32_t count;
  };

  BvhBuilder(std::span<const SurfaceTriangle> triangles, unsigned threads) {
    for (uint32_t i = 0; i < triangles.size();) {
      Item item;
      item.first = i;
      item.count = 0;
      do {
        const SurfaceTriangle& t = triangles[i];
        item.box.extend(t.a), item.box.extend(t.b), item.box.extend(t.c);
        ++item.count, ++i;
      } while (i < triangles.size() && item.count < 4 && triangles[i].face != kNoIndex &&
               triangles[i].face == triangles[item.first].face);
      for (int k = 0; k < 3; ++k) item.centroid[k] = 0.5f * (item.box.lo[k] + item.box.hi[k]);
      items_.push_back(item);
    }
    Range all{0, static_cast<uint32_t>(items_.size()), 0, Box(), Box()};
    bounds(all);
    while ((1u << spawn_depth_) < threads) ++spawn_depth_;  // one subtree per thread
    nodes.reserve(items_.size());
    build(all, 0, nodes);
    // Leaves hold item ranges so far: turn them into ranges of triangles in leaf order.
    std::vector<uint32_t> item_start(items_.size() + 1, 0);
    for (size_t i = 0; i < items_.size(); ++i) {
      item_start[i + 1] = item_start[i] + items_[i].count;
      for (uint32_t t = 0; t < items_[i].count; ++t) order.push_back(items_[i].first + t);
    }
    for (TriangleBvh::Node& n : nodes) {
      if (n.count == 0) continue;
      const uint32_t begin = n.first, end = n.first + n.count;
      n.first = item_start[begin];
      n.count = item_start[end] - item_start[begin];
    }
  }

  std::vector<TriangleBvh::Node> nodes;
  std::vector<uint32_t> order;  // leaf order → input triangle

 private:
  struct Range {
    uint32_t begin, end;  // items
    uint32_t triangles;
    Box box, centre_box;  // of the items, and of their centroids
  };

  // Appends the subtree over items_[r.begin, r.end) to `out`, depth first.
  void build(const Range& r, int depth, std::vector<TriangleBvh::Node>& out) {
    const uint32_t index = static_cast<uint32_t>(out.size());
    out.push_back({r.box.lo, r.box.hi, r.begin, r.end - r.begin});
    if (r.end - r.begin == 1) return;
    Range left, right;
    const bool may_be_leaf = r.triangles <= kMaxLeafTriangles;
    if (depth < kSahDepth ? !split(r, may_be_leaf, left, right)
                          : may_be_leaf || !median_split(r, left, right))
      return;  // a leaf
    if (depth < spawn_depth_ && r.end - r.begin >= kParallelMinimum) {
      // An exception in either half (std::bad_alloc) reaches the caller once both have ended,
      // as with parallel_for(); a thread that throws would end the process.
      std::vector<TriangleBvh::Node> right_nodes;
      std::exception_ptr right_failed;
      std::thread worker([&] {
        try {
          build(right, depth + 1, right_nodes);
        } catch (...) {
          right_failed = std::current_exception();
        }
      });
      try {
        build(left, depth + 1, out);
      } catch (...) {
        worker.join();
        throw;
      }
      worker.join();
      if (right_failed) std::rethrow_exception(right_failed);
      const uint32_t offset = static_cast<uint32_t>(out.size());
      for (TriangleBvh::Node n : right_nodes) {
        if (n.count == 0) n.first += offset;
        out.push_back(n);
      }
      out[index].first = offset;
    } else {
      build(left, depth + 1, out);  // the left child lands at index + 1
      out[index].first = static_cast<uint32_t>(out.size());
      build(right, depth + 1, out);
    }
    out[index].count = 0;
  }

  static int longest_axis(const Box& b) {
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (b.hi[k] - b.lo[k] > b.hi[axis] - b.lo[axis]) axis = k;
    return axis;
  }

  void bounds(Range& r) const {
    r.box = Box(), r.centre_box = Box(), r.triangles = 0;
    for (uint32_t i = r.begin; i < r.end; ++i) {
      r.box.extend(items_[i].box);
      r.centre_box.extend(items_[i].centroid);
      r.triangles += items_[i].count;
    }
  }

  // Halves the range at the median centroid along the longest axis (or, if all centroids
  // coincide, in input order). Always splits a range of two or more items.
  bool median_split(const Range& r, Range& left, Range& right) {
    const int axis = longest_axis(r.centre_box);
    const uint32_t middle = r.begin + (r.end - r.begin) / 2;
    std::nth_element(items_.begin() + r.begin, items_.begin() + middle, items_.begin() + r.end,
                     [&](const Item& s, const Item& t) {
                       return s.centroid[axis] < t.centroid[axis] ||
                              (s.centroid[axis] == t.centroid[axis] && s.first < t.first);
                     });
    left.begin = r.begin, left.end = middle;
    right.begin = middle, right.end = r.end;
    bounds(left), bounds(right);
    return true;
  }

  // Splits at the cheapest bin boundary along the longest centroid axis, unless a leaf is
  // allowed and cheaper (then returns false).
  bool split(const Range& r, bool may_be_leaf, Range& left, Range& right) {
    const int axis = longest_axis(r.centre_box);
    const float lo = r.centre_box.lo[axis], extent = r.centre_box.hi[axis] - lo;
    if (!(extent > 0)) return !may_be_leaf && median_split(r, left, right);
    const double scale = kBins / double(extent);  // double: a tiny extent must not overflow
    auto bin_of = [&](const Item& item) {
      return std::min(kBins - 1, static_cast<int>((double(item.centroid[axis]) - lo) * scale));
    };
    std::array<Box, kBins> bin_box, bin_centre;
    std::array<uint32_t, kBins> bin_items{}, bin_triangles{};
    for (uint32_t i = r.begin; i < r.end; ++i) {
      const int b = bin_of(items_[i]);
      bin_box[b].extend(items_[i].box);
      bin_centre[b].extend(items_[i].centroid);
      ++bin_items[b];
      bin_triangles[b] += items_[i].count;
    }
    // Sweep from the right, then from the left: the cost of splitting after bin b, weighing
    // each side's box area by the triangles it holds.
    std::array<double, kBins> right_cost{};
    Box sweep;
    uint32_t n = 0;
    for (int b = kBins - 1; b > 0; --b) {
      sweep.extend(bin_box[b]);
      n += bin_triangles[b];
      right_cost[b - 1] = sweep.half_area() * n;
    }
    sweep = Box();
    n = 0;
    uint32_t items = 0;
    double best_cost = std::numeric_limits<double>::infinity();
    int best_bin = -1;
    for (int b = 0; b < kBins - 1; ++b) {
      sweep.extend(bin_box[b]);
      n += bin_triangles[b];
      items += bin_items[b];
      if (items == 0 || items == r.end - r.begin) continue;
      const double cost = sweep.half_area() * n + right_cost[b];
      if (cost < best_cost) best_cost = cost, best_bin = b;
    }
    // extent > 0 puts the smallest and the largest centroid in bins 0 and kBins − 1.
    assert(best_bin >= 0);
    if (may_be_leaf &&
        kTraversalCost * r.box.half_area() + best_cost >= r.box.half_area() * r.triangles)
      return false;
    auto middle = std::partition(items_.begin() + r.begin, items_.begin() + r.end,
                                 [&](const Item& item) { return bin_of(item) <= best_bin; });
    left = Range{r.begin, static_cast<uint32_t>(middle - items_.begin()), 0, Box(), Box()};
    right = Range{left.end, r.end, 0, Box(), Box()};
    for (int b = 0; b < kBins; ++b) {
      Range& side = b <= best_bin ? left : right;
      side.box.extend(bin_box[b]);
      side.centre_box.extend(bin_centre[b]);
      side.triangles += bin_triangles[b];
    }
    return true;
  }

  std::vector<Item> items_;
  int spawn_depth_ = 0;
};

}  // namespace

Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b,
                                 const Point3& c) {
  const Point3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;  // vertex region of a

  const Point3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;  // vertex region of b

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));  // edge ab

  const Point3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;  // vertex region of c

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));  // edge ac

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)  // edge bc
    return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));

  // Face region: p projects inside; (va, vb, vc) are its barycentric weights times the area.
  const double sum = va + vb + vc;
  if (!(sum > 0)) return closest_point_on_sides(p, a, b, c);
  const double v = vb / sum, w = vc / sum;
  return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
}

std::vector<SurfaceTriangle> surface_triangles(const Topology& topology,
                                               std::span<const float> positions) {
  std::vector<SurfaceTriangle> triangles;
  triangles.reserve(topology.faces.size() + 3 * topology.quad_count());
  surface_triangles(topology, positions, triangles);
  return triangles;
}

void surface_triangles(const Topology& topology, std::span<const float> positions,
                       std::vector<SurfaceTriangle>& triangles) {
  assert(positions.size() == size_t{topology.vertex_count} * 3);
  triangles.clear();
  auto vertex = [&](uint32_t v) {
    assert(v < topology.vertex_count);
    return std::array<float, 3>{positions[3 * size_t{v}], positions[3 * size_t{v} + 1],
                                positions[3 * size_t{v} + 2]};
  };
  for (uint32_t f = 0; f < topology.faces.size(); ++f) {
    const Face& face = topology.faces[f];
    const int degree = face.degree();
    if (degree == 3) {
      triangles.push_back({vertex(face.v[0]), vertex(face.v[1]), vertex(face.v[2]), f});
    } else if (degree == 4) {
      std::array<std::array<float, 3>, 4> corner;
      for (int i = 0; i < 4; ++i) corner[i] = vertex(face.v[i]);
      std::array<float, 3> centroid;
      for (int k = 0; k < 3; ++k)
        centroid[k] = static_cast<float>(
            (double(corner[0][k]) + corner[1][k] + corner[2][k] + corner[3][k]) * 0.25);
      for (int i = 0; i < 4; ++i)
        triangles.push_back({corner[i], corner[(i + 1) % 4], centroid, f});
    }
  }
}

TriangleBvh::TriangleBvh(std::span<const SurfaceTriangle> triangles, unsigned threads) {
  assert(triangles.size() < kNoIndex);
  if (triangles.empty()) return;
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  BvhBuilder builder(triangles, threads);
  nodes_ = std::move(builder.nodes);
  original_ = std::move(builder.order);
  triangles_.resize(triangles.size());
  leaf_position_.resize(triangles.size());
  for (uint32_t i = 0; i < original_.size(); ++i) {
    triangles_[i] = triangles[original_[i]];
    leaf_position_[original_[i]] = i;
  }
  for (const Node& n : nodes_) box_area_ += half_area(n);
  parent_.assign(nodes_.size(), kNoIndex);
  depth_.assign(nodes_.size(), 0);
  leaf_of_.resize(triangles.size());
  for (uint32_t n = 0; n < nodes_.size(); ++n) {  // parents come before their children
    const Node& node = nodes_[n];
    if (node.count == 0) {
      parent_[n + 1] = parent_[node.first] = n;
      depth_[n + 1] = depth_[node.first] = static_cast<uint8_t>(depth_[n] + 1);
    } else {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) leaf_of_[i] = n;
    }
  }
}

bool TriangleBvh::refit(std::span<const SurfaceTriangle> triangles) {
  assert(triangles.size() == triangles_.size());
  for (uint32_t i = 0; i < original_.size(); ++i) {
    assert(triangles[original_[i]].face == triangles_[i].face);
    triangles_[i] = triangles[original_[i]];
  }
  // Children come after their parents: in reverse order, a node's children are done first.
  double area = 0;
  for (size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    Box box;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i)
        box.extend(triangles_[i].a), box.extend(triangles_[i].b), box.extend(triangles_[i].c);
    } else {
      for (const Node* child : {&nodes_[n + 1], &nodes_[node.first]})
        box.extend(Box{child->lo, child->hi});
    }
    node.lo = box.lo, node.hi = box.hi;
    area += half_area(node);
  }
  return area <= 1.5 * box_area_;
}

// The best triangle so far (leaf order) and its closest point.
struct TriangleBvh::Best {
  double d2;
  uint32_t triangle = kNoIndex;
  Point3 point{0, 0, 0};
};

// Depth-first search of the subtree at `node`, nearer child first; a pending entry keeps its
// box distance so that it can be dropped once something closer has been found. Stops at once
// when a triangle nearer than sqrt(enough) has been found.
void TriangleBvh::descend(const Point3& p, uint32_t node, Best& best, double enough,
                          uint32_t tested) const {
  struct Pending {
    uint32_t node;
    double d2;
  };
  std::array<Pending, kMaxDepth> stack;
  size_t top = 0;
  while (node != kNoIndex) {
    const Node& n = nodes_[node];
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        if (i == tested) continue;
        const SurfaceTriangle& t = triangles_[i];
        const Point3 q = closest_point_on_triangle(p, to_point(t.a), to_point(t.b), to_point(t.c));
        const double d2 = squared_distance(p, q);
        if (d2 < best.d2) best = {d2, i, q};
      }
      if (best.d2 < enough) return;
    } else {
      uint32_t near = node + 1, far = n.first;
      double near_d2 = squared_distance_to_box(p, nodes_[near]);
      double far_d2 = squared_distance_to_box(p, nodes_[far]);
      if (far_d2 < near_d2) std::swap(near, far), std::swap(near_d2, far_d2);
      if (near_d2 < best.d2) {
        if (far_d2 < best.d2) {
          assert(top < stack.size());
          stack[top++] = {far, far_d2};
        }
        node = near;
        continue;
      }
    }
    node = kNoIndex;  // the next pending box that may still hold something closer
    while (top > 0 && node == kNoIndex) {
      const Pending& pending = stack[--top];
      if (pending.d2 < best.d2) node = pending.node;
    }
  }
}

TriangleBvh::Hit TriangleBvh::hit(const Best& best, bool with_weights) const {
  Hit h;
  if (best.triangle == kNoIndex) return h;
  h.squared_distance = best.d2;
  h.point = best.point;
  h.triangle = original_[best.triangle];
  const SurfaceTriangle& t = triangles_[best.triangle];
  h.face = t.face;
  if (with_weights)
    h.weights = barycentric(best.point, to_point(t.a), to_point(t.b), to_point(t.c));
  return h;
}

TriangleBvh::Hit TriangleBvh::closest(const Point3& p, double max_squared_distance) const {
  Best best{max_squared_distance};
  if (!nodes_.empty() && squared_distance_to_box(p, nodes_[0]) < best.d2) descend(p, 0, best);
  return hit(best);
}

void TriangleBvh::within(const Point3& p, double max_squared_distance,
                         std::vector<Hit>& out) const {
  std::array<uint32_t, kMaxDepth> stack;
  size_t top = 0;
  if (!nodes_.empty() && squared_distance_to_box(p, nodes_[0]) < max_squared_distance)
    stack[top++] = 0;
  while (top > 0) {  // depth first: at most one pending sibling per level
    const uint32_t node = stack[--top];
    const Node& n = nodes_[node];
    if (n.count == 0) {
      for (uint32_t child : {node + 1, n.first})
        if (squared_distance_to_box(p, nodes_[child]) < max_squared_distance) {
          assert(top < stack.size());
          stack[top++] = child;
        }
      continue;
    }
    for (uint32_t i = n.first; i < n.first + n.count; ++i) {
      const SurfaceTriangle& t = triangles_[i];
      const Point3 q = closest_point_on_triangle(p, to_point(t.a), to_point(t.b), to_point(t.c));
      const double d2 = squared_distance(p, q);
      if (d2 < max_squared_distance) out.push_back(hit({d2, i, q}));
    }
  }
}

TriangleBvh::Hit TriangleBvh::closest(const Point3& p, Cursor& cursor, bool with_weights,
                                      double enough) const {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Best best{kInfinity};
  if (nodes_.empty()) return hit(best);
  Cursor& c = cursor;
  if (c.leaf == kNoIndex) {
    descend(p, 0, best);
    if (best.triangle == kNoIndex) return hit(best);  // only if every distance overflowed
    c.leaf = leaf_of_[best.triangle];
    c.triangle = best.triangle;
    c.last = p;
    c.clearance[0] = kInfinity;  // nothing is outside the root
    for (uint32_t d = 1; d <= depth_[c.leaf]; ++d) c.clearance[d] = -kInfinity;
    return hit(best, with_weights);
  }
  assert(c.leaf < nodes_.size() && nodes_[c.leaf].count > 0);
  c.travel += std::sqrt(squared_distance(p, c.last));
  c.last = p;
  const double travel = c.travel;
  // With `enough`, the previous answer first (not for an exact query: a tie would go elsewhere).
  uint32_t tested = kNoIndex;
  if (enough > 0 && c.triangle != kNoIndex) {
    const SurfaceTriangle& t = triangles_[c.triangle];
    const Point3 q = closest_point_on_triangle(p, to_point(t.a), to_point(t.b), to_point(t.c));
    best = {squared_distance(p, q), c.triangle, q};
    if (best.d2 < enough) return hit(best, with_weights);
    tested = c.triangle;
  }
  descend(p, c.leaf, best, enough, tested);
  if (best.d2 < enough) {
    c.triangle = best.triangle;
    return hit(best, with_weights);
  }
  const uint32_t leaf_depth = depth_[c.leaf];
  uint32_t node = c.leaf, depth = leaf_depth;
  uint32_t improved_at = 0;  // depth of the sibling subtree holding the answer; 0: the leaf
  for (; depth > 0; --depth) {
    // Nothing outside the ancestor at this depth can be closer? The margin covers rounding.
    const double stamped = c.clearance[depth];
    const double reach = (stamped - travel) - 1e-12 * (std::abs(stamped) + travel);
    if (reach > 0 && best.d2 <= reach * reach) break;
    const uint32_t parent = parent_[node];
    const uint32_t sibling = node == parent + 1 ? nodes_[parent].first : parent + 1;
    const double d2 = squared_distance_to_box(p, nodes_[sibling]);
    c.sibling[depth] = std::sqrt(d2) + travel;
    if (d2 < best.d2) {
      const uint32_t before = best.triangle;
      descend(p, sibling, best, enough);
      if (best.triangle != before) improved_at = depth;
      if (best.d2 < enough) break;  // the levels from here down are reset below
    }
    node = parent;
  }
  // Below the depth where the climb stopped, the clearances follow from the fresh siblings.
  for (uint32_t d = depth + 1; d <= leaf_depth; ++d)
    c.clearance[d] = std::min(c.clearance[d - 1], c.sibling[d]);
  if (improved_at > 0) {
    // A new leaf, under the same ancestors down to depth improved_at − 1 (their clearances
    // still hold); below that its surroundings are unknown.
    c.leaf = leaf_of_[best.triangle];
    for (uint32_t d = improved_at; d <= depth_[c.leaf]; ++d) c.clearance[d] = -kInfinity;
  }
  c.triangle = best.triangle;
  return hit(best, with_weights);
}

}  // namespace dynpm
