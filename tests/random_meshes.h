// Seeded random mixed meshes for the property tests (property_*_test.cpp): quad grids with some
// quads split into two triangles along either diagonal, holes, parts in blocks, ribs welded on in
// T-joints, an occasional loose sheet, a few smoothly deformed time steps, and the numbering of
// vertices, faces and corners shuffled; random targets, key steps and options; the shape counts
// the simplifier keeps. DYNPM_PROPERTY_ROUNDS=k runs k times as many seeds, for a longer soak.
//
// Random numbers come from std::mt19937 through the helpers below, never through the standard
// distributions, whose output differs between standard libraries: a seed makes the same mesh
// everywhere.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "dynpm/core.h"
#include "dynpm/pipeline.h"
#include "dynpm/simplify.h"

namespace dynpm::test {

using Rng = std::mt19937;

inline uint32_t pick(Rng& rng, uint32_t lo, uint32_t hi) {  // in [lo, hi]
  return lo + static_cast<uint32_t>(rng() % (uint64_t{hi} - lo + 1));
}
inline double uniform(Rng& rng, double lo, double hi) {
  return lo + (hi - lo) * (rng() / 4294967296.0);
}
inline bool chance(Rng& rng, double p) { return rng() < p * 4294967296.0; }
template <class T>
inline void shuffle(Rng& rng, std::vector<T>& v) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[pick(rng, 0, uint32_t(i - 1))]);
}

// Seeds first, first + 1, …: `count` of them, times DYNPM_PROPERTY_ROUNDS if set; then the
// seeds that once found a bug (they stay meaningful as long as random_case() draws the same).
inline std::vector<uint32_t> seeds(uint32_t first, uint32_t count,
                                   std::vector<uint32_t> found = {}) {
  if (const char* rounds = std::getenv("DYNPM_PROPERTY_ROUNDS"))
    count *= std::max(1, std::atoi(rounds));
  std::vector<uint32_t> out(count);
  for (uint32_t i = 0; i < count; ++i) out[i] = first + i;
  for (uint32_t seed : found)
    if (seed >= first + count) out.push_back(seed);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Random mixed meshes

struct RandomCase {
  Animation animation;
  size_t ribs = 0;
  std::string description;  // for failure messages
};

// A rib: a strip of quads standing on the panel's grid line y = row from x = first to x = last,
// `height` cells high, up (+z) or down (−z). Every panel edge under it gets a third face, a
// fourth where a rib on the other side stands on it too:
//
//   rib (up):   r ─── r ─── r          panel, seen from above:   ┼───┼───┼───┼
//               │     │     │                                    │   │ ╱ │   │
//               r ─── r ─── r                         row ────── ┿━━━┿━━━┿───┼   (━ joint)
//               │     │     │                                    │ ╲ │   │   │
//   row:   ──── p ━━━ p ━━━ p ────                               ┼───┼───┼───┼
struct Rib {
  uint32_t row = 0, first = 0, last = 0, height = 1;
  int direction = 1;
};

// The split of a grid cell (a, b, c, d), counter-clockwise: none, along a–c, along b–d.
enum class Split { kNone, kAC, kBD };

inline void add_cell(std::vector<std::pair<Face, int32_t>>& faces, uint32_t a, uint32_t b,
                     uint32_t c, uint32_t d, Split split, int32_t part) {
  auto face = [](uint32_t x, uint32_t y, uint32_t z, uint32_t w = kNoVertex) {
    Face f;
    f.v = {x, y, z, w};
    return f;
  };
  switch (split) {
    case Split::kNone: faces.push_back({face(a, b, c, d), part}); break;
    case Split::kAC:
      faces.push_back({face(a, b, c), part});
      faces.push_back({face(a, c, d), part});
      break;
    case Split::kBD:
      faces.push_back({face(a, b, d), part});
      faces.push_back({face(b, c, d), part});
      break;
  }
}

inline Split random_split(Rng& rng, double share) {
  if (!chance(rng, share)) return Split::kNone;
  return chance(rng, 0.5) ? Split::kAC : Split::kBD;
}

inline Topology to_topology(uint32_t vertex_count,
                            const std::vector<std::pair<Face, int32_t>>& faces) {
  Topology t = Topology::with_vertices(vertex_count);
  for (const auto& [f, part] : faces) t.add_face(f, part);
  return t;
}

// A mesh of max_vertices / 5 … max_vertices / 2 panel cells, about as many vertices.
inline RandomCase random_case(Rng& rng, uint32_t max_vertices) {
  // The panel: nx × ny cells, vertex (i, j) = j·(nx + 1) + i, a gentle wave in z.
  const uint32_t cells = pick(rng, max_vertices / 5, max_vertices / 2);
  const uint32_t nx = pick(rng, 4, std::max(4u, uint32_t(1.5 * std::sqrt(double(cells)))));
  const uint32_t ny = std::max(3u, cells / nx);
  std::vector<double> xyz;
  auto add_vertex = [&xyz](double x, double y, double z) {
    xyz.insert(xyz.end(), {x, y, z});
    return uint32_t(xyz.size() / 3 - 1);
  };
  const double wave = uniform(rng, 0, 0.4), wx = uniform(rng, 0.2, 1), wy = uniform(rng, 0.2, 1);
  auto panel_z = [&](uint32_t i, uint32_t j) { return wave * std::sin(wx * i) * std::cos(wy * j); };
  for (uint32_t j = 0; j <= ny; ++j)
    for (uint32_t i = 0; i <= nx; ++i) add_vertex(i, j, panel_z(i, j));
  auto panel = [nx](uint32_t i, uint32_t j) { return j * (nx + 1) + i; };

  // Parts in blocks; neighbouring blocks may share an id. Ids are any int32.
  const int32_t kParts[] = {1, 2, 3, 7, 12, 100000, -4, 0};
  auto random_part = [&] { return kParts[pick(rng, 0, std::size(kParts) - 1)]; };
  const uint32_t bx = pick(rng, 2, nx), by = pick(rng, 2, ny);
  const uint32_t blocks_x = (nx + bx - 1) / bx, blocks_y = (ny + by - 1) / by;
  std::vector<int32_t> block_part(size_t{blocks_x} * blocks_y);
  for (int32_t& p : block_part) p = random_part();

  const double r = uniform(rng, 0, 1);
  const double split_share = r < 0.15 ? 0.0 : r > 0.9 ? 1.0 : uniform(rng, 0.05, 0.6);
  std::vector<Split> split(size_t{nx} * ny);
  for (Split& s : split) s = random_split(rng, split_share);
  auto cell = [nx](uint32_t i, uint32_t j) { return size_t{j} * nx + i; };

  // Ribs on interior grid lines; two on one line stand on opposite sides.
  std::vector<Rib> ribs;
  const uint32_t rib_count = chance(rng, 0.15) ? 0 : chance(rng, 0.6) ? 1 : 2;
  for (uint32_t k = 0; k < rib_count; ++k) {
    Rib rib;
    rib.row = pick(rng, 1, ny - 1);
    rib.first = pick(rng, 0, nx - 1);
    rib.last = pick(rng, rib.first + 1, std::min(nx, rib.first + pick(rng, 1, nx)));
    rib.height = pick(rng, 1, 4);
    rib.direction = chance(rng, 0.7) ? 1 : -1;
    for (const Rib& other : ribs)
      if (other.row == rib.row && other.direction == rib.direction) rib.direction = -rib.direction;
    ribs.push_back(rib);
  }
  // Cells beside a joint stay, so that every joint edge keeps its two panel faces.
  std::vector<char> keep(split.size(), 0), removed(split.size(), 0);
  for (const Rib& rib : ribs)
    for (uint32_t j = rib.row - 1; j <= rib.row; ++j)
      for (uint32_t i = rib.first > 0 ? rib.first - 1 : 0; i <= std::min(rib.last, nx - 1); ++i)
        keep[cell(i, j)] = 1;

  auto panel_faces = [&] {
    std::vector<std::pair<Face, int32_t>> faces;
    for (uint32_t j = 0; j < ny; ++j)
      for (uint32_t i = 0; i < nx; ++i)
        if (!removed[cell(i, j)])
          add_cell(faces, panel(i, j), panel(i + 1, j), panel(i + 1, j + 1), panel(i, j + 1),
                   split[cell(i, j)], block_part[(j / by) * blocks_x + i / bx]);
    return faces;
  };

  // Holes: rectangles of cells, each kept only if the panel stays valid with no pinched vertex
  // (a hole touching another in a corner only, or cutting a vertex's fan in two).
  uint32_t holes = 0;
  const uint32_t hole_tries = pick(rng, 0, 5);
  for (uint32_t h = 0; h < hole_tries; ++h) {
    const uint32_t w = pick(rng, 1, 3), ht = pick(rng, 1, 3);
    const uint32_t i0 = pick(rng, 0, nx - std::min(w, nx)),
                   j0 = pick(rng, 0, ny - std::min(ht, ny));
    std::vector<size_t> rect;
    bool free = true;
    for (uint32_t j = j0; j < std::min(ny, j0 + ht); ++j)
      for (uint32_t i = i0; i < std::min(nx, i0 + w); ++i) {
        free &= !keep[cell(i, j)] && !removed[cell(i, j)];
        rect.push_back(cell(i, j));
      }
    if (!free) continue;
    for (size_t c : rect) removed[c] = 1;
    const Topology t = to_topology(uint32_t(xyz.size() / 3), panel_faces());
    const ValidationReport report = validate(t);
    if (report.ok() && report.count(ProblemKind::kNonManifoldVertex) == 0 && !t.faces.empty()) {
      ++holes;
    } else {
      for (size_t c : rect) removed[c] = 0;
    }
  }
  std::vector<std::pair<Face, int32_t>> faces = panel_faces();

  for (const Rib& rib : ribs) {
    const double dz = uniform(rng, 0.6, 1.2);
    const int32_t part = random_part();
    const uint32_t width = rib.last - rib.first + 1;
    std::vector<uint32_t> ids;  // (i, k) → ids[k·width + i − first]
    for (uint32_t k = 0; k <= rib.height; ++k)
      for (uint32_t i = rib.first; i <= rib.last; ++i)
        ids.push_back(k == 0
                          ? panel(i, rib.row)
                          : add_vertex(i, rib.row, panel_z(i, rib.row) + rib.direction * dz * k));
    auto at = [&](uint32_t i, uint32_t k) { return ids[k * width + i - rib.first]; };
    for (uint32_t k = 0; k < rib.height; ++k)
      for (uint32_t i = rib.first; i < rib.last; ++i) {
        const Split s = random_split(rng, split_share);
        if (rib.direction > 0)
          add_cell(faces, at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1), s, part);
        else
          add_cell(faces, at(i, k + 1), at(i + 1, k + 1), at(i + 1, k), at(i, k), s, part);
      }
  }

  // Sometimes a loose sheet below the panel: another component.
  const bool sheet = chance(rng, 0.3);
  if (sheet) {
    const uint32_t mx = pick(rng, 1, 4), my = pick(rng, 1, 4);
    const int32_t part = random_part();
    const double x0 = uniform(rng, -2, nx), y0 = uniform(rng, -2, ny);
    const uint32_t first = uint32_t(xyz.size() / 3);
    for (uint32_t j = 0; j <= my; ++j)
      for (uint32_t i = 0; i <= mx; ++i) add_vertex(x0 + i, y0 + j, -2.5);
    for (uint32_t j = 0; j < my; ++j)
      for (uint32_t i = 0; i < mx; ++i) {
        auto id = [&](uint32_t a, uint32_t b) { return first + b * (mx + 1) + a; };
        add_cell(faces, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1),
                 random_split(rng, split_share), part);
      }
  }

  // Drop vertices that holes left without faces; shuffle vertex numbers, face order and each
  // face's first corner (the orientation stays).
  const uint32_t all = uint32_t(xyz.size() / 3);
  std::vector<char> used(all, 0);
  for (const auto& [f, part] : faces)
    for (uint32_t c : f.v)
      if (c != kNoVertex) used[c] = 1;
  std::vector<uint32_t> order;
  for (uint32_t v = 0; v < all; ++v)
    if (used[v]) order.push_back(v);
  shuffle(rng, order);
  std::vector<uint32_t> new_id(all, kNoVertex);
  for (uint32_t v = 0; v < order.size(); ++v) new_id[order[v]] = v;
  shuffle(rng, faces);

  RandomCase out;
  Topology& t = out.animation.topology;
  t = Topology::with_vertices(uint32_t(order.size()));
  int64_t node = int64_t(pick(rng, 0, 2000000)) - 1000, element = int64_t(rng()) << 8;
  for (int64_t& id : t.node_ids) id = node += pick(rng, 1, 1000);
  for (auto [f, part] : faces) {
    const int d = f.degree(), turn = int(pick(rng, 0, uint32_t(d - 1)));
    Face g;
    for (int c = 0; c < d; ++c) g.v[c] = new_id[f.v[(c + turn) % d]];
    t.add_face(g, part, element += pick(rng, 1, 50));
  }

  // Time steps: p_t = p + s_t · (Σ modes a · sin(k · p + φ) + a shift) + offset. The modes'
  // gradients stay below one, so no face degenerates in any step.
  const uint32_t steps = pick(rng, 1, 4);
  struct Mode {
    double a[3], k[3], phase;
  };
  std::vector<Mode> modes(2);
  for (Mode& m : modes) {
    for (int c = 0; c < 3; ++c) m.a[c] = uniform(rng, -1.2, 1.2), m.k[c] = uniform(rng, -0.2, 0.2);
    m.phase = uniform(rng, 0, 6.28);
  }
  double offset[3] = {0, 0, 0};
  if (chance(rng, 0.3))
    for (double& o : offset) o = uniform(rng, -1000, 1000);
  Frames& frames = out.animation.frames;
  frames.set_vertex_count(t.vertex_count);
  double time = uniform(rng, -1, 1), s = chance(rng, 0.7) ? 0 : uniform(rng, 0, 0.3);
  for (uint32_t step = 0; step < steps; ++step) {
    const double shift[3] = {uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)};
    std::vector<float> p(size_t{t.vertex_count} * 3);
    for (uint32_t v = 0; v < all; ++v) {
      if (new_id[v] == kNoVertex) continue;
      const double* q = &xyz[size_t{v} * 3];
      for (int c = 0; c < 3; ++c) {
        double d = shift[c];
        for (const Mode& m : modes)
          d += m.a[c] * std::sin(m.k[0] * q[0] + m.k[1] * q[1] + m.k[2] * q[2] + m.phase);
        p[size_t{new_id[v]} * 3 + c] = float(q[c] + s * d + offset[c]);
      }
    }
    frames.add_step(std::move(p), time);
    time += uniform(rng, 0.001, 2);
    s += uniform(rng, 0, 0.4);
  }

  out.ribs = ribs.size();
  const ValidationReport report = validate(out.animation);
  out.description = std::to_string(nx) + "×" + std::to_string(ny) + " cells, " +
                    std::to_string(t.vertex_count) + " vertices, " +
                    std::to_string(t.triangle_count()) + " triangles, " +
                    std::to_string(t.quad_count()) + " quads, " + std::to_string(t.parts().size()) +
                    " part ids, " + std::to_string(ribs.size()) + " ribs (" +
                    std::to_string(report.count(ProblemKind::kNonManifoldEdge)) +
                    " joint edges), " + std::to_string(holes) + " holes, " +
                    (sheet ? "a loose sheet, " : "") + std::to_string(steps) + " steps";
  return out;
}

// What the simplifier keeps through every collapse (its check_every_collapse mode checks the
// same after each one).
struct Shape {
  int64_t euler = 0;
  size_t boundary_loops = 0, components = 0;
  bool operator==(const Shape&) const = default;
};
inline Shape shape_of(const Topology& t) {
  const TopologyStats s = topology_stats(t, Adjacency::build(t));
  return {s.euler_characteristic, s.boundary_loops, s.components};
}
inline std::ostream& operator<<(std::ostream& os, const Shape& s) {
  return os << "χ " << s.euler << ", " << s.boundary_loops << " boundary loops, " << s.components
            << " components";
}

// A valid mesh with no vertex outside the faces and no face twice.
inline void expect_clean(const Topology& t, const std::string& what) {
  const ValidationReport report = validate(t);
  for (const Problem& p : report.problems)
    if (p.severity == Severity::kError) ADD_FAILURE() << what << ": " << p.message;
  EXPECT_EQ(report.count(ProblemKind::kUnreferencedVertex), 0u) << what;
  EXPECT_EQ(report.count(ProblemKind::kDuplicateFace), 0u) << what;
}

// Every step, the paper's three, auto:K, or a list with repeats in any order.
inline std::vector<size_t> random_key_steps(Rng& rng, const FrameSource& frames) {
  const uint32_t steps = uint32_t(frames.step_count());
  KeyStepRule rule;
  switch (pick(rng, 0, 3)) {
    case 0: return {};
    case 1: rule.kind = KeyStepRule::Kind::kPaper; break;
    case 2:
      rule.kind = KeyStepRule::Kind::kAuto;
      rule.count = pick(rng, 1, steps);
      break;
    default: {
      std::vector<size_t> list(pick(rng, 1, 3));
      for (size_t& k : list) k = pick(rng, 0, steps - 1);
      return list;
    }
  }
  auto choice = choose_key_steps(frames, rule);
  EXPECT_TRUE(choice.ok()) << choice.message();
  return choice.ok() ? choice->steps : std::vector<size_t>{};
}

// Options besides the targets, as a user might set them.
inline SimplifyOptions random_options(Rng& rng, const Animation& a) {
  SimplifyOptions o;
  o.key_steps = random_key_steps(rng, a.frames);
  o.keep_part_boundaries = chance(rng, 0.6);
  const double rotations[] = {30, 90, 170}, weights[] = {0.1, 1, 10};
  o.max_normal_rotation_degrees = rotations[pick(rng, 0, 2)];
  o.boundary_weight = weights[pick(rng, 0, 2)];
  for (uint32_t k = pick(rng, 0, 3); k > 0; --k)
    o.locked_vertices.push_back(pick(rng, 0, a.topology.vertex_count - 1));
  for (uint32_t k = pick(rng, 0, 3); k > 0; --k) {
    const Face& f = a.topology.faces[pick(rng, 0, uint32_t(a.topology.faces.size() - 1))];
    const int c = int(pick(rng, 0, uint32_t(f.degree() - 1)));
    o.feature_edges.push_back({f.v[c], f.v[(c + 1) % f.degree()]});
  }
  return o;
}

inline std::string describe(const SimplifyOptions& o) {
  std::string s = "key steps {";
  for (size_t k : o.key_steps) s += std::to_string(k) + " ";
  s += "}, part boundaries " + std::string(o.keep_part_boundaries ? "kept" : "free") +
       ", rotation ≤ " + std::to_string(o.max_normal_rotation_degrees) + "°, boundary weight " +
       std::to_string(o.boundary_weight) + ", " + std::to_string(o.locked_vertices.size()) +
       " locked, " + std::to_string(o.feature_edges.size()) + " feature edges";
  if (o.target_vertices) s += ", target " + std::to_string(*o.target_vertices) + " vertices";
  if (o.target_ratio) s += ", target ratio " + std::to_string(*o.target_ratio);
  if (o.target_faces) s += ", target " + std::to_string(*o.target_faces) + " faces";
  if (o.max_error) s += ", max error " + std::to_string(*o.max_error);
  return s;
}

inline BuildOptions random_build_options(Rng& rng, const Animation& a) {
  BuildOptions o;
  o.simplify = random_options(rng, a);
  o.lossless = chance(rng, 0.4);
  const double bounds[] = {1.0 / (1 << 10), 1.0 / (1 << 18), 1.0 / (1 << 24)};
  o.max_position_error = bounds[pick(rng, 0, 2)];
  return o;
}

}  // namespace dynpm::test
