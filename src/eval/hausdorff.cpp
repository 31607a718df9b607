// The Hausdorff distance between two surfaces, measured as Metro does: P. Cignoni, C. Rocchini,
// R. Scopigno, "Metro: measuring error on simplified surfaces", Computer Graphics Forum 17(2),
// 1998. The paper's Tables 1–3 report this distance between an animation and its simplified
// version, per time step, in % of the bounding-box diagonal.
//
// The one-sided distance from surface S to surface T is the largest distance from a point of S
// to its closest point on T. Metro estimates it by sampling S densely and measuring every
// sample exactly:
//
//   1. Sample S. Metro samples three kinds of places, and so do we:
//        vertices  every vertex in a face, once (corners are where maxima like to sit);
//        edges     every edge once, at n = ⌊length / h + u⌋ stratified points, where h is the
//                  spacing of the area samples, sqrt(area / N), and u is uniform in [0, 1);
//        faces     every triangle (quads as four triangles through their centroid, §5 of the
//                  paper) gets ⌊N · area_i / area + u⌋ uniform points: in expectation exactly
//                  proportional to area, so their mean is an unbiased area-weighted mean. The
//                  points are stratified (one per cell of a regular subdivision, in the
//                  spirit of Metro's "similar triangles" sampling): each triangle is covered
//                  evenly.
//      N, the area sample count, is 10 × the face count of the larger mesh by default.
//   2. For each sample p, d(p) = |p − closest point of T| from a BVH over T's triangles
//      (bvh.cpp): an exact distance, not an approximation.
//   3. max over all samples; mean and RMS over the area samples only, so that they estimate
//      the surface integrals (1/|S|) ∫ d and sqrt((1/|S|) ∫ d²) without the vertex and edge
//      samples tilting them.
//
// Both directions are measured and the Hausdorff distance is the larger maximum.
//
// Determinism: the samples are cut into jobs by position in the vertex, edge and triangle lists
// (never by thread), each job draws from its own generator seeded from (seed, direction, kind,
// job), and job results are combined in job order. So the result depends on the seed only, not
// on the thread count or scheduling. The generator is SplitMix64 (Steele, Lea, Flood 2014),
// written here because std::uniform_real_distribution differs between standard libraries.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "core/face_geometry.h"
#include "core/parallel.h"
#include "dynpm/eval.h"
#include "field_distance.h"

namespace dynpm {
namespace {

// SplitMix64: a 64-bit counter passed through a strong mixing function.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed) {}
  uint64_t next() { return mix(state_ += 0x9e3779b97f4a7c15ull); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  uint64_t state_;
};

uint64_t job_seed(uint64_t seed, uint64_t direction, uint64_t kind, uint64_t job) {
  uint64_t h = Random::mix(seed + 0x632be59bd9b4e019ull);
  for (uint64_t part : {direction, kind, job}) h = Random::mix(h ^ (part + 0x9e3779b97f4a7c15ull));
  return h;
}

// ---------------------------------------------------------------------------------------------
// The inputs: checked once per topology, positions once per step.

Result<SurfaceTopology> prepare(const char* name, const Topology& topology) {
  SurfaceTopology prepared;
  prepared.topology = &topology;
  const uint32_t n = topology.vertex_count;
  if (topology.faces.empty()) return Status::error(std::string(name) + ": the mesh has no faces");
  std::vector<uint32_t> row_start(size_t{n} + 2, 0);
  for (size_t f = 0; f < topology.faces.size(); ++f) {
    const Face& face = topology.faces[f];
    const int degree = face.degree();
    if (degree < 3)
      return Status::error(std::string(name) + ": face " + std::to_string(f) + " has " +
                           std::to_string(degree) + " corners");
    for (int i = 0; i < degree; ++i) {
      if (face.v[i] >= n)
        return Status::error(std::string(name) + ": face " + std::to_string(f) + " names vertex " +
                             std::to_string(face.v[i]) + " of " + std::to_string(n));
      ++row_start[std::min(face.v[i], face.v[(i + 1) % degree]) + 2];
    }
  }
  // Edges in compressed rows by smaller vertex, then sorted and deduplicated per row.
  for (size_t v = 2; v < row_start.size(); ++v) row_start[v] += row_start[v - 1];
  std::vector<uint32_t> larger(row_start.back());
  std::vector<char> referenced(n, 0);
  for (const Face& face : topology.faces) {
    const int degree = face.degree();
    for (int i = 0; i < degree; ++i) {
      const uint32_t a = face.v[i], b = face.v[(i + 1) % degree];
      larger[row_start[std::min(a, b) + 1]++] = std::max(a, b);
      referenced[a] = 1;
    }
  }
  for (uint32_t v = 0; v < n; ++v) {
    if (referenced[v]) prepared.vertices.push_back(v);
    auto first = larger.begin() + row_start[v], last = larger.begin() + row_start[v + 1];
    std::sort(first, last);
    for (auto it = first; it != last; ++it)
      if (it == first || *it != *(it - 1)) prepared.edges.push_back({v, *it});
  }
  return prepared;
}

Status check_positions(const char* name, const Topology& topology,
                       std::span<const float> positions) {
  if (positions.size() != size_t{topology.vertex_count} * 3)
    return Status::error(std::string(name) + ": " + std::to_string(positions.size()) +
                         " coordinates for " + std::to_string(topology.vertex_count) + " vertices");
  for (size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i]))
      return Status::error(std::string(name) + ": vertex " + std::to_string(i / 3) +
                           " has a non-finite coordinate");
  return Status();
}

// ---------------------------------------------------------------------------------------------
// Sampling one surface and measuring against the other.

struct Tally {
  double max = -1;  // -1: no sample yet
  Point3 max_at{0, 0, 0};
  FieldTally fields;
  double area_sum = 0, area_sum2 = 0;  // over the area samples in the mean
  uint64_t mean_samples = 0;
  double all_sum = 0, all_sum2 = 0;  // over every sample (for a surface without area)
  uint64_t vertex_samples = 0, edge_samples = 0, face_samples = 0;

  void merge(const Tally& t) {  // in job order, so ties keep the earlier sample
    if (t.max > max) max = t.max, max_at = t.max_at;
    fields.merge(t.fields);
    area_sum += t.area_sum, area_sum2 += t.area_sum2;
    mean_samples += t.mean_samples;
    all_sum += t.all_sum, all_sum2 += t.all_sum2;
    vertex_samples += t.vertex_samples, edge_samples += t.edge_samples;
    face_samples += t.face_samples;
  }

  OneSidedDistance result() const {
    OneSidedDistance d;
    d.max = std::max(max, 0.0);
    d.max_at = max_at;
    d.vertex_samples = vertex_samples, d.edge_samples = edge_samples;
    d.face_samples = face_samples;
    const uint64_t all = vertex_samples + edge_samples + face_samples;
    if (mean_samples > 0) {
      d.mean = area_sum / double(mean_samples);
      d.rms = std::sqrt(area_sum2 / double(mean_samples));
    } else if (all > 0) {
      d.mean = all_sum / double(all);
      d.rms = std::sqrt(all_sum2 / double(all));
    }
    return d;
  }
};

enum SampleKind : uint32_t { kVertexSamples, kEdgeSamples, kFaceSamples };

// One direction: samples on `from`, distances to `to`.
struct Direction {
  const Surface* from = nullptr;
  const Surface* to = nullptr;
  double face_density = 0;   // area samples per unit area
  uint64_t mean_stride = 1;  // the mean and RMS take every mean_stride-th area sample of a job
  double edge_density = 0;   // edge samples per unit length
  std::vector<FieldSides> fields;
  double field_tolerance = 0, facing_reach = 0;  // HausdorffOptions::field_…
  std::vector<Point3> vertex_normals;            // of `from`, with a facing reach
};

struct Job {
  uint32_t direction;
  SampleKind kind;
  size_t begin, end;  // a range of vertices, edges or triangles of `from`
};

double triangle_area(const SurfaceTriangle& t) {
  const Vec3 p[3] = {load(t.a.data()), load(t.b.data()), load(t.c.data())};
  return 0.5 * length(doubled_vector_area(p, 3));
}

// ⌊expected + u⌋: an integer whose mean is `expected`.
uint64_t random_round(double expected, Random& random) {
  const double whole = std::floor(expected);
  return static_cast<uint64_t>(whole) + (random.uniform() < expected - whole ? 1 : 0);
}

// n points uniformly distributed on a triangle, stratified: the triangle is cut into k² similar
// triangles (k = ⌈√n⌉, k rows of "up" and "down" cells), n of the cells are chosen uniformly
// at random (Knuth's selection sampling), and each gets one uniform point. Every point of the
// triangle is equally likely, as with plain uniform sampling, but the points cover it evenly,
// and the cells are visited row by row in alternating directions, so each point is close to
// the previous one and the previous answer is a good hint for the next query.
// emit(u, v) receives coordinates along the edges ab and ac (u, v ≥ 0, u + v ≤ 1).
template <class Emit>
void sample_triangle(uint64_t n, Random& random, const Emit& emit) {
  if (n == 0) return;
  const uint64_t k = static_cast<uint64_t>(std::ceil(std::sqrt(double(n))));
  const double scale = 1.0 / double(k);
  uint64_t cells_left = k * k, wanted = n;
  for (uint64_t row = 0; row < k; ++row) {
    const uint64_t cells = 2 * (k - row) - 1;  // up, down, up, …, up
    for (uint64_t c = 0; c < cells; ++c, --cells_left) {
      if (random.uniform() * double(cells_left) >= double(wanted)) continue;
      --wanted;
      const uint64_t cell = row % 2 == 0 ? c : cells - 1 - c;
      const double u0 = double(cell / 2), v0 = double(row);
      double r = random.uniform(), s = random.uniform();
      if (r + s > 1) r = 1 - r, s = 1 - s;
      if (cell % 2 == 0)  // up: (u0, v0), (u0 + 1, v0), (u0, v0 + 1)
        emit((u0 + r) * scale, (v0 + s) * scale);
      else  // down: (u0 + 1, v0 + 1), (u0, v0 + 1), (u0 + 1, v0)
        emit((u0 + 1 - r) * scale, (v0 + 1 - s) * scale);
    }
  }
  assert(wanted == 0);
}

// Which of a job's area samples a run measures: all, or (when the mean takes every
// mean_stride-th) those of the mean in a first pass and the others in a second. Both passes
// draw the same samples; each counts its own.
enum class AreaPart { kAll, kMean, kRest };

// `known_max` ≥ 0: a distance that some sample of this direction reaches (the mean's area
// samples' maximum, then every area sample's), set only when a sample outside the mean — a
// vertex or edge sample, or an area sample the mean skips — can matter through the maximum
// alone (no fields). Such a sample needs no closest point if it is nearer than that — or than
// this job's maximum so far — to a triangle of the previous answer's leaf: it cannot be the
// (first) sample at the maximum. The margin keeps a distance that would round to the maximum
// itself measured.
Tally run_job(const Job& job, const Direction& d, uint64_t seed, size_t job_index, double known_max,
              AreaPart part) {
  Random random(job_seed(seed, job.direction, job.kind, job_index));
  Tally tally;
  tally.fields = FieldTally(d.fields.size());
  TriangleBvh::Cursor cursor;  // consecutive samples are close: start where the last one ended
  const bool with_weights = !d.fields.empty();
  FieldSampler sampler(*d.to, d.fields, d.field_tolerance, d.facing_reach);
  std::vector<double> values(d.fields.size());
  // `own(k)`: field k's value at p on `from` (NaN: none there, an element field off a face);
  // `normal`: the way p faces (zero: not needed).
  uint64_t area_index = 0;  // the job's area samples so far
  auto measure = [&](const Point3& p, const Point3& normal, uint64_t& counter, bool area_sample,
                     const auto& own) {
    const bool in_mean = area_sample && area_index++ % d.mean_stride == 0;
    if (area_sample && part != AreaPart::kAll && in_mean != (part == AreaPart::kMean)) return;
    double enough = 0;  // a hit nearer than sqrt(enough) cannot raise the maximum
    if (known_max >= 0 && !in_mean) {
      const double below = std::max(known_max, tally.max);
      enough = below * below * (1 - 1e-12);
      if (below > 0 && d.to->bvh.previous_closer_than(p, enough, cursor)) {
        ++counter;
        return;
      }
    }
    const TriangleBvh::Hit hit = d.to->bvh.closest(p, cursor, with_weights, enough);
    if (hit.squared_distance < enough) {
      ++counter;
      return;
    }
    const double distance = std::sqrt(hit.squared_distance);
    if (distance > tally.max) tally.max = distance, tally.max_at = p;
    tally.all_sum += distance, tally.all_sum2 += distance * distance;
    if (in_mean) {
      tally.area_sum += distance, tally.area_sum2 += distance * distance;
      ++tally.mean_samples;
    }
    ++counter;
    if (d.fields.empty()) return;
    for (size_t k = 0; k < d.fields.size(); ++k) values[k] = own(k);
    sampler.measure(p, normal, hit, values, area_sample, tally.fields);
  };
  const std::vector<float>& positions = d.from->positions;
  auto vertex = [&](uint32_t v) {
    const float* x = &positions[3 * size_t{v}];
    return Point3{x[0], x[1], x[2]};
  };
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  auto node_value = [&](size_t k, uint32_t v) {
    const SurfaceField& f = d.fields[k].from;
    return f.location == FieldLocation::kNode ? double(f.values[v]) : kNone;
  };
  auto vertex_normal = [&](uint32_t v) {
    return d.vertex_normals.empty() ? Point3{0, 0, 0} : d.vertex_normals[v];
  };
  switch (job.kind) {
    case kVertexSamples:
      for (size_t i = job.begin; i < job.end; ++i) {
        const uint32_t v = d.from->topology->vertices[i];
        measure(vertex(v), vertex_normal(v), tally.vertex_samples, false,
                [&](size_t k) { return node_value(k, v); });
      }
      break;
    case kEdgeSamples:
      for (size_t i = job.begin; i < job.end; ++i) {
        const Edge& e = d.from->topology->edges[i];
        const Point3 a = vertex(e.a), b = vertex(e.b);
        const Point3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double length = std::sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
        const uint64_t n = random_round(length * d.edge_density, random);
        const Point3 na = vertex_normal(e.a), nb = vertex_normal(e.b);
        const Point3 normal{na[0] + nb[0], na[1] + nb[1], na[2] + nb[2]};
        for (uint64_t j = 0; j < n; ++j) {  // one point in each of n equal pieces
          const double t = (double(j) + random.uniform()) / double(n);
          measure({a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]}, normal,
                  tally.edge_samples, false,
                  [&](size_t k) { return (1 - t) * node_value(k, e.a) + t * node_value(k, e.b); });
        }
      }
      break;
    case kFaceSamples:
      for (size_t i = job.begin; i < job.end; ++i) {
        const SurfaceTriangle& t = d.from->triangles[i];
        const uint64_t n = random_round(triangle_area(t) * d.face_density, random);
        const Point3 a{t.a[0], t.a[1], t.a[2]};
        const Point3 ab{double(t.b[0]) - a[0], double(t.b[1]) - a[1], double(t.b[2]) - a[2]};
        const Point3 ac{double(t.c[0]) - a[0], double(t.c[1]) - a[1], double(t.c[2]) - a[2]};
        const Point3 normal = d.facing_reach > 0 ? triangle_normal(t) : Point3{0, 0, 0};
        sample_triangle(n, random, [&](double u, double v) {
          measure({a[0] + u * ab[0] + v * ac[0], a[1] + u * ab[1] + v * ac[1],
                   a[2] + u * ab[2] + v * ac[2]},
                  normal, tally.face_samples, true, [&](size_t k) {
                    return interpolate((*d.fields[k].from_corners)[i], {1 - u - v, u, v});
                  });
        });
      }
      break;
  }
  return tally;
}

// Jobs of about kSamplesPerJob samples each, cut by list position only.
constexpr double kSamplesPerJob = 8192;

void add_jobs(std::vector<Job>& jobs, uint32_t direction, SampleKind kind, size_t count,
              double samples_per_item) {
  const size_t per_job = static_cast<size_t>(
      std::clamp(kSamplesPerJob / std::max(samples_per_item, 1e-9), 16.0, 65536.0));
  for (size_t begin = 0; begin < count; begin += per_job)
    jobs.push_back({direction, kind, begin, std::min(count, begin + per_job)});
}

// The surface at `positions`, in the memory of `s` (which holds its topology's last step, or
// nothing): the BVH is refitted when it has one for these triangles, else built.
Status fill_step(const char* name, Surface& s, std::span<const float> positions, unsigned threads) {
  const SurfaceTopology& topology = *s.topology;
  DYNPM_RETURN_IF_ERROR(check_positions(name, *topology.topology, positions));
  s.positions.assign(positions.begin(), positions.end());
  surface_triangles(*topology.topology, positions, s.triangles);
  if (s.bvh.triangle_count() != s.triangles.size() || !s.bvh.refit(s.triangles))
    s.bvh = TriangleBvh(s.triangles, thread_count(threads));
  s.area = 0, s.edge_length = 0;
  for (const SurfaceTriangle& t : s.triangles) s.area += triangle_area(t);
  for (const Edge& e : topology.edges) {
    double l2 = 0;
    for (int c = 0; c < 3; ++c) {
      const double x = double(positions[3 * size_t{e.a} + c]) - positions[3 * size_t{e.b} + c];
      l2 += x * x;
    }
    s.edge_length += std::sqrt(l2);
  }
  return {};
}

Result<Surface> prepare_step(const char* name, const SurfaceTopology& topology,
                             std::span<const float> positions, unsigned threads) {
  Surface s;
  s.topology = &topology;
  DYNPM_RETURN_IF_ERROR(fill_step(name, s, positions, threads));
  return s;
}

Result<HausdorffResult> evaluate(const Surface& a, const Surface& b,
                                 const HausdorffOptions& options,
                                 std::span<const FieldPair> fields) {
  assert(options.samples_per_face >= 0 && std::isfinite(options.samples_per_face));
  const Topology& a_topology = *a.topology->topology;
  const Topology& b_topology = *b.topology->topology;
  const size_t larger = std::max(a_topology.faces.size(), b_topology.faces.size());
  const double area_samples = options.face_samples > 0
                                  ? double(options.face_samples)
                                  : std::round(options.samples_per_face * double(larger));
  const unsigned threads = thread_count(options.threads);

  // Each field's values on both surfaces' triangles, for both directions.
  std::vector<CornerValues> a_corners, b_corners;
  for (const FieldPair& f : fields) {
    DYNPM_RETURN_IF_ERROR(check_field("A", a_topology, f.a));
    DYNPM_RETURN_IF_ERROR(check_field("B", b_topology, f.b));
    a_corners.push_back(corner_values(a_topology, f.a));
    b_corners.push_back(corner_values(b_topology, f.b));
  }
  std::array<Direction, 2> directions;
  directions[0].from = &a, directions[0].to = &b;
  directions[1].from = &b, directions[1].to = &a;
  for (size_t k = 0; k < fields.size(); ++k) {
    directions[0].fields.push_back({fields[k].a, &a_corners[k], &b_corners[k]});
    directions[1].fields.push_back({fields[k].b, &b_corners[k], &a_corners[k]});
  }

  std::vector<Job> jobs;
  for (uint32_t k = 0; k < 2; ++k) {
    Direction& d = directions[k];
    d.field_tolerance = options.field_tolerance;
    if (!fields.empty() && options.field_facing_reach > 0) {
      d.facing_reach = options.field_facing_reach;
      d.vertex_normals = vertex_normals(*d.from->topology->topology, d.from->positions);
    }
    const SurfaceTopology& from = *d.from->topology;
    if (d.from->area > 0 && area_samples > 0) {
      d.face_density = area_samples / d.from->area;
      if (fields.empty() && options.mean_samples > 0 && area_samples > double(options.mean_samples))
        d.mean_stride =
            static_cast<uint64_t>(std::ceil(area_samples / double(options.mean_samples)));
      if (options.sample_edges) d.edge_density = std::sqrt(d.face_density);
    }
    if (options.sample_vertices) add_jobs(jobs, k, kVertexSamples, from.vertices.size(), 1);
    if (d.edge_density > 0)
      add_jobs(jobs, k, kEdgeSamples, from.edges.size(),
               d.from->edge_length * d.edge_density / double(from.edges.size()));
    if (d.face_density > 0)
      add_jobs(jobs, k, kFaceSamples, d.from->triangles.size(),
               area_samples / double(d.from->triangles.size()));
  }

  // The area samples first: their maximum then spares most vertex and edge samples a closest
  // point when nothing but the maximum needs them (run_job). Either way the result is the same.
  // When the mean takes a part of the area samples, those first: their maximum then spares
  // most other area samples a closest point. Then the rest of the area samples, and last the
  // vertex and edge samples, spared by the maximum of all area samples. Either way the result
  // is the same.
  const bool strided = directions[0].mean_stride > 1 || directions[1].mean_stride > 1;
  std::vector<Tally> mean_tallies(strided ? jobs.size() : 0), tallies(jobs.size());
  std::array<double, 2> known_max{-1, -1};
  auto run = [&](bool area, AreaPart part, std::vector<Tally>& out) {
    std::vector<size_t> pass;
    for (size_t i = 0; i < jobs.size(); ++i)
      if ((jobs[i].kind == kFaceSamples) == area) pass.push_back(i);
    // One part per job, taken by whichever thread is free (jobs differ in cost).
    parallel_for(pass.size(), pass.size(), std::min(threads, 1024u),
                 [&](size_t begin, size_t end, size_t) {
                   for (size_t j = begin; j < end; ++j) {
                     const Job& job = jobs[pass[j]];
                     out[pass[j]] = run_job(job, directions[job.direction], options.seed, pass[j],
                                            known_max[job.direction], part);
                   }
                 });
    if (!area || !fields.empty()) return;
    std::array<Tally, 2> measured;
    for (size_t i : pass) {
      if (strided) measured[jobs[i].direction].merge(mean_tallies[i]);
      measured[jobs[i].direction].merge(tallies[i]);
    }
    for (int k = 0; k < 2; ++k)
      if (measured[k].face_samples > 0) known_max[k] = std::max(measured[k].max, 0.0);
  };
  if (strided) run(true, AreaPart::kMean, mean_tallies);
  run(true, strided ? AreaPart::kRest : AreaPart::kAll, tallies);
  run(false, AreaPart::kAll, tallies);
  std::array<Tally, 2> total;
  for (size_t i = 0; i < jobs.size(); ++i) {
    if (strided) total[jobs[i].direction].merge(mean_tallies[i]);
    total[jobs[i].direction].merge(tallies[i]);
  }

  HausdorffResult r;
  r.a_to_b = total[0].result();
  r.b_to_a = total[1].result();
  r.hausdorff = std::max(r.a_to_b.max, r.b_to_a.max);
  r.mean = 0.5 * (r.a_to_b.mean + r.b_to_a.mean);
  r.rms = std::sqrt(0.5 * (r.a_to_b.rms * r.a_to_b.rms + r.b_to_a.rms * r.b_to_a.rms));
  for (Tally& t : total) t.fields.merge(FieldTally(fields.size()));  // sized even without samples
  for (size_t k = 0; k < fields.size(); ++k) {
    FieldDistance f;
    const FieldTally& ab = total[0].fields;
    const FieldTally& ba = total[1].fields;
    f.nearest_a_to_b = std::max(ab.nearest[k], 0.0);
    f.nearest_b_to_a = std::max(ba.nearest[k], 0.0);
    f.nearest = std::max(f.nearest_a_to_b, f.nearest_b_to_a);
    const bool facing = options.field_facing_reach > 0;  // else the closest point's
    f.a_to_b = facing ? std::max(ab.facing[k], 0.0) : f.nearest_a_to_b;
    f.b_to_a = facing ? std::max(ba.facing[k], 0.0) : f.nearest_b_to_a;
    f.max = std::max(f.a_to_b, f.b_to_a);
    auto mean = [&](const FieldTally& t) {
      return t.area_samples > 0 ? t.area_sum[k] / double(t.area_samples) : 0.0;
    };
    f.mean = 0.5 * (mean(ab) + mean(ba));
    const bool from_b = f.b_to_a > f.a_to_b;
    f.max_at = facing ? (from_b ? ba.facing_at[k] : ab.facing_at[k])
                      : (from_b ? ba.nearest_at[k] : ab.nearest_at[k]);
    r.fields.push_back(f);
  }
  if (options.reference_diagonal > 0) {
    r.diagonal = options.reference_diagonal;
  } else {
    BoundingBox box;
    box.extend(a.positions);
    r.diagonal = box.diagonal();
  }
  return r;
}

}  // namespace

Result<HausdorffResult> hausdorff(const Topology& a_topology, std::span<const float> a_positions,
                                  const Topology& b_topology, std::span<const float> b_positions,
                                  const HausdorffOptions& options) {
  auto a = prepare("A", a_topology);
  if (!a) return a.status();
  auto b = prepare("B", b_topology);
  if (!b) return b.status();
  auto a_step = prepare_step("A", *a, a_positions, options.threads);
  if (!a_step) return a_step.status();
  auto b_step = prepare_step("B", *b, b_positions, options.threads);
  if (!b_step) return b_step.status();
  return evaluate(*a_step, *b_step, options, {});
}

Result<SurfaceTopology> prepare_topology(const char* name, const Topology& topology) {
  return prepare(name, topology);
}

Result<Surface> prepare_surface(const char* name, const SurfaceTopology& topology,
                                std::span<const float> positions, unsigned threads) {
  return prepare_step(name, topology, positions, threads);
}

Status update_surface(const char* name, Surface& surface, std::span<const float> positions,
                      unsigned threads) {
  assert(surface.topology != nullptr);
  return fill_step(name, surface, positions, threads);
}

Result<HausdorffResult> hausdorff(const Surface& a, const Surface& b,
                                  const HausdorffOptions& options,
                                  std::span<const FieldPair> fields) {
  return evaluate(a, b, options, fields);
}

}  // namespace dynpm
