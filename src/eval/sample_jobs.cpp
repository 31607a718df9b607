// Drawing and measuring the samples of one direction (sample_jobs.h; the distance as a whole is
// hausdorff.cpp's).
//
// Determinism: the samples are cut into jobs by position in the vertex, edge and triangle lists
// (never by thread), each job draws from its own generator seeded from (seed, direction, kind,
// job), and job results are combined in job order. So the result depends on the seed only, not
// on the thread count or scheduling. The generator is SplitMix64 (Steele, Lea, Flood 2014),
// written here because std::uniform_real_distribution differs between standard libraries.
#include "sample_jobs.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "core/face_geometry.h"

namespace dynpm::sampling {
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

// Draws a job's samples in order from its own generator and hands each to
// measure(item, p, normal, area_sample, in_mean, own): item is the vertex, edge or triangle's
// position in the job, `own(k)` field k's value at p on `from` (NaN: none there, an element
// field off a face), `normal` the way p faces (zero: not needed). The draws never depend on
// what is measured, so every way of measuring sees the same samples.
template <class Measure>
void draw_samples(const Job& job, const Direction& d, uint64_t seed, size_t job_index,
                  AreaPart part, const Measure& measure) {
  Random random(job_seed(seed, job.direction, job.kind, job_index));
  uint64_t area_index = 0;  // the job's area samples so far
  auto area_sample = [&](size_t item, const Point3& p, const Point3& normal, const auto& own) {
    const bool in_mean = area_index++ % d.mean_stride == 0;
    if (part != AreaPart::kAll && in_mean != (part == AreaPart::kMean)) return;
    measure(item, p, normal, true, in_mean, own);
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
        measure(i - job.begin, vertex(v), vertex_normal(v), false, false,
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
          measure(i - job.begin, {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]}, normal,
                  false, false,
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
          area_sample(i - job.begin,
                      {a[0] + u * ab[0] + v * ac[0], a[1] + u * ab[1] + v * ac[1],
                       a[2] + u * ab[2] + v * ac[2]},
                      normal, [&](size_t k) {
                        return interpolate((*d.fields[k].from_corners)[i], {1 - u - v, u, v});
                      });
        });
      }
      break;
  }
}

uint64_t& sample_counter(Tally& tally, SampleKind kind) {
  return kind == kVertexSamples ? tally.vertex_samples
         : kind == kEdgeSamples ? tally.edge_samples
                                : tally.face_samples;
}

// Adds a sample measured at `distance` to the tally (in drawing order: ties keep the earlier).
void count_distance(Tally& tally, const Point3& p, double distance, bool in_mean) {
  if (distance > tally.max) tally.max = distance, tally.max_at = p;
  tally.all_sum += distance, tally.all_sum2 += distance * distance;
  if (in_mean) {
    tally.area_sum += distance, tally.area_sum2 += distance * distance;
    ++tally.mean_samples;
  }
}

// `known_max` ≥ 0: a distance that some sample of this direction reaches (the mean's area
// samples' maximum, then every area sample's), set only when a sample outside the mean — a
// vertex or edge sample, or an area sample the mean skips — can matter through the maximum
// alone (no fields). Such a sample needs no closest point if it is nearer than that — or than
// the largest distance measured so far in its jobs — to some triangle (closest() with `enough`
// tests the previous answer's triangle first, then searches until it meets one): it cannot be
// the (first) sample at the maximum. The margin keeps a distance that would round to the
// maximum itself measured. Returns the sample's distance, or NaN when it cannot matter.
double sample_distance(const Direction& d, const Point3& p, bool in_mean, double known_max,
                       double max_so_far, TriangleBvh::Cursor& cursor, bool with_weights,
                       TriangleBvh::Hit& hit) {
  double enough = 0;  // a hit nearer than sqrt(enough) cannot raise the maximum
  if (known_max >= 0 && !in_mean) {
    const double below = std::max(known_max, max_so_far);
    enough = below * below * (1 - 1e-12);
  }
  hit = d.to->bvh.closest(p, cursor, with_weights, enough);
  if (hit.squared_distance < enough) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(hit.squared_distance);
}

// 30 bits of Morton order: x, y and z (each below 2¹⁰) interleaved.
uint32_t morton_code(uint32_t x, uint32_t y, uint32_t z) {
  auto spread = [](uint32_t v) {  // bit i to bit 3i
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    return (v | (v << 2)) & 0x09249249u;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

// The order in which a batch of drawn samples is measured, as indices into `runs` (the samples
// of one vertex, edge or triangle, consecutive when drawn): by the Morton code of each run's
// first sample in the box of those samples, unless the drawing order already jumps less between
// runs (a surface numbered by a mesher, or a structured grid, is in space order already, and
// Morton order jumps at its block borders).
template <class Drawn, class Run>
void space_order(std::span<const Drawn> samples, std::span<const Run> runs,
                 std::vector<uint64_t>& order) {
  order.resize(runs.size());
  if (runs.empty()) return;
  auto first = [&](size_t r) -> const Point3& { return samples[runs[r].begin].p; };
  Point3 lo = first(0), hi = first(0);
  for (size_t r = 1; r < runs.size(); ++r)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], first(r)[k]), hi[k] = std::max(hi[k], first(r)[k]);
  for (size_t r = 0; r < runs.size(); ++r) {
    std::array<uint32_t, 3> cell{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      if (hi[k] > lo[k])
        cell[k] = static_cast<uint32_t>((first(r)[k] - lo[k]) / (hi[k] - lo[k]) * 1023.0);
    order[r] = uint64_t{morton_code(cell[0], cell[1], cell[2])} << 32 | r;
  }
  std::sort(order.begin(), order.end());
  auto jump = [&](size_t from, size_t to) {
    const Point3 &a = samples[runs[from].end - 1].p, &b = samples[runs[to].begin].p;
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
  };
  double in_drawing_order = 0, in_space_order = 0;
  for (size_t r = 1; r < runs.size(); ++r) {
    in_drawing_order += jump(r - 1, r);
    in_space_order += jump(uint32_t(order[r - 1]), uint32_t(order[r]));
  }
  for (size_t r = 0; r < runs.size(); ++r)
    order[r] = in_drawing_order <= in_space_order ? r : uint32_t(order[r]);
}

// How many samples a job draws, in expectation (every pass draws them all).
double expected_samples(const Job& job, const Direction& d) {
  double expected = 0;
  if (job.kind == kVertexSamples) return double(job.end - job.begin);
  for (size_t i = job.begin; i < job.end; ++i) {
    if (job.kind == kFaceSamples) {
      expected += triangle_area(d.from->triangles[i]) * d.face_density;
    } else {
      const Edge& e = d.from->topology->edges[i];
      const float *a = &d.from->positions[3 * size_t{e.a}],
                  *b = &d.from->positions[3 * size_t{e.b}];
      const double x = double(b[0]) - a[0], y = double(b[1]) - a[1], z = double(b[2]) - a[2];
      expected += std::sqrt(x * x + y * y + z * z) * d.edge_density;
    }
  }
  return expected;
}

}  // namespace

double triangle_area(const SurfaceTriangle& t) {
  const Vec3 p[3] = {load(t.a.data()), load(t.b.data()), load(t.c.data())};
  return 0.5 * length(doubled_vector_area(p, 3));
}

// In drawing order: with fields always, since which of two equally near triangles a closest
// point lands on depends on the search's path, and a field can differ between them.
Tally run_job(const Job& job, const Direction& d, uint64_t seed, size_t job_index, double known_max,
              AreaPart part) {
  Tally tally;
  tally.fields = FieldTally(d.fields.size());
  TriangleBvh::Cursor cursor;  // consecutive samples are close: start where the last one ended
  FieldSampler sampler(*d.to, d.fields, d.field_tolerance, d.facing_reach);
  std::vector<double> values(d.fields.size());
  uint64_t& counter = sample_counter(tally, job.kind);
  draw_samples(job, d, seed, job_index, part,
               [&](size_t, const Point3& p, const Point3& normal, bool area_sample, bool in_mean,
                   const auto& own) {
                 ++counter;
                 TriangleBvh::Hit hit;
                 const double distance = sample_distance(d, p, in_mean, known_max, tally.max,
                                                         cursor, !d.fields.empty(), hit);
                 if (std::isnan(distance)) return;
                 count_distance(tally, p, distance, in_mean);
                 if (d.fields.empty()) return;
                 for (size_t k = 0; k < d.fields.size(); ++k) values[k] = own(k);
                 sampler.measure(p, normal, hit, values, area_sample, tally.fields);
               });
  return tally;
}

// Consecutive jobs of one direction and kind without fields (the distance alone), measured
// together in space order, about kBatchSamples samples at a time: the samples are drawn job by
// job as run_job() draws them, measured in space_order(), and counted in drawing order. A
// vertex list or a level's faces in progressive order scatter consecutive samples over the
// whole surface, and each closest-point query would start from a cold, distant leaf; in space
// order the next query starts next door. The distances, and so every reported number, are those
// of drawing order: a closest distance is the same whichever equally near triangle holds it.
// A job expected to draw more than kBatchSamples alone (a few huge triangles) is measured by
// run_job(), in drawing order, which is space order within a triangle.
std::vector<Tally> run_jobs_in_space_order(std::span<const Job> jobs, const Direction& d,
                                           uint64_t seed, size_t first_job_index, double known_max,
                                           AreaPart part) {
  struct Drawn {
    Point3 p;
    bool in_mean;
  };
  struct Run {
    size_t begin, end;
  };
  // The thread's memory from its last batch (below 2 · kBatchSamples samples, and their runs):
  // megabytes that would otherwise be mapped, faulted in and unmapped again for every batch.
  thread_local std::vector<Drawn> samples;
  thread_local std::vector<Run> runs;
  thread_local std::vector<uint64_t> order;
  thread_local std::vector<double> distance;
  std::vector<Tally> tallies(jobs.size());
  double max_so_far = -1;  // of every sample measured in these jobs
  TriangleBvh::Cursor cursor;
  for (size_t next = 0; next < jobs.size();) {
    const size_t first_job = next;
    samples.clear(), runs.clear();
    std::vector<size_t> job_end;  // of the jobs drawn, in `samples`
    while (next < jobs.size() && samples.size() < kBatchSamples) {
      if (expected_samples(jobs[next], d) > double(kBatchSamples)) {
        if (!samples.empty()) break;  // the jobs before it first, then it alone
        tallies[next] = run_job(jobs[next], d, seed, first_job_index + next, known_max, part);
        max_so_far = std::max(max_so_far, tallies[next].max);
        ++next;
        break;  // the jobs after it in a batch of their own (job_end counts from first_job)
      }
      size_t item = std::numeric_limits<size_t>::max();
      draw_samples(jobs[next], d, seed, first_job_index + next, part,
                   [&](size_t i, const Point3& p, const Point3&, bool, bool in_mean, const auto&) {
                     if (i != item || runs.empty())
                       runs.push_back({samples.size(), samples.size()}), item = i;
                     samples.push_back({p, in_mean});
                     ++runs.back().end;
                   });
      job_end.push_back(samples.size());
      ++next;
    }
    space_order(std::span<const Drawn>(samples), std::span<const Run>(runs), order);
    distance.resize(samples.size());
    TriangleBvh::Hit hit;
    for (uint64_t r : order)
      for (size_t i = runs[r].begin; i < runs[r].end; ++i) {
        distance[i] = sample_distance(d, samples[i].p, samples[i].in_mean, known_max, max_so_far,
                                      cursor, false, hit);
        if (distance[i] > max_so_far) max_so_far = distance[i];
      }
    for (size_t j = 0, i = 0; j < job_end.size(); ++j) {
      Tally& tally = tallies[first_job + j];
      uint64_t& counter = sample_counter(tally, jobs[first_job + j].kind);
      for (; i < job_end[j]; ++i) {
        ++counter;
        if (!std::isnan(distance[i]))
          count_distance(tally, samples[i].p, distance[i], samples[i].in_mean);
      }
    }
  }
  return tallies;
}

void add_jobs(std::vector<Job>& jobs, uint32_t direction, SampleKind kind, size_t count,
              double samples_per_item) {
  const size_t per_job = static_cast<size_t>(
      std::clamp(kSamplesPerJob / std::max(samples_per_item, 1e-9), 16.0, 65536.0));
  for (size_t begin = 0; begin < count; begin += per_job)
    jobs.push_back({direction, kind, begin, std::min(count, begin + per_job),
                    double(std::min(count, begin + per_job) - begin) * samples_per_item});
}

}  // namespace dynpm::sampling
