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
//      (bvh.cpp): an exact distance, not an approximation. The samples are measured in space
//      order where that pays (sample_jobs.cpp), which changes no number.
//   3. max over all samples; mean and RMS over the area samples only, so that they estimate
//      the surface integrals (1/|S|) ∫ d and sqrt((1/|S|) ∫ d²) without the vertex and edge
//      samples tilting them.
//
// Both directions are measured and the Hausdorff distance is the larger maximum. The samples
// are drawn and measured in jobs (sample_jobs.cpp); here the jobs are made and run in passes,
// and their tallies combined.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "core/parallel.h"
#include "dynpm/eval.h"
#include "field_distance.h"
#include "sample_jobs.h"

namespace dynpm {
namespace {

using sampling::AreaPart, sampling::Direction, sampling::Job, sampling::Tally, sampling::add_jobs,
    sampling::run_job, sampling::run_jobs_in_space_order, sampling::triangle_area;
using sampling::kBatchSamples, sampling::kEdgeSamples, sampling::kFaceSamples,
    sampling::kVertexSamples;

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
  // Space order pays where the closest points are searched in a tree larger than the caches
  // (a BVH of 64 Ki triangles takes some 4 MB), and only without fields
  // (run_jobs_in_space_order).
  std::array<bool, 2> in_space_order;
  for (int k = 0; k < 2; ++k)
    in_space_order[k] =
        fields.empty() && directions[k].to->triangles.size() >= options.space_order_triangles;
  auto run = [&](bool area, AreaPart part, std::vector<Tally>& out) {
    // Batches of consecutive jobs of one direction and kind: about kBatchSamples samples in
    // all, measured together in space order when that pays (see in_space_order), else one job.
    // One part per batch, taken by whichever thread is free (batches differ in cost).
    struct Batch {
      size_t begin, end;  // jobs
      double samples;
    };
    std::vector<Batch> pass;
    for (size_t i = 0; i < jobs.size(); ++i) {
      if ((jobs[i].kind == kFaceSamples) != area) continue;
      if (pass.empty() || pass.back().end != i || !in_space_order[jobs[i].direction] ||
          pass.back().samples + jobs[i].samples > double(kBatchSamples) ||
          jobs[i].direction != jobs[i - 1].direction || jobs[i].kind != jobs[i - 1].kind)
        pass.push_back({i, i, 0});
      ++pass.back().end;
      pass.back().samples += jobs[i].samples;
    }
    parallel_for(
        pass.size(), pass.size(), std::min(threads, 1024u), [&](size_t first, size_t last, size_t) {
          for (size_t n = first; n < last; ++n) {
            const Batch batch = pass[n];
            const Job& job = jobs[batch.begin];
            const Direction& d = directions[job.direction];
            if (!in_space_order[job.direction]) {
              out[batch.begin] =
                  run_job(job, d, options.seed, batch.begin, known_max[job.direction], part);
              continue;
            }
            std::vector<Tally> measured = run_jobs_in_space_order(
                std::span(jobs).subspan(batch.begin, batch.end - batch.begin), d, options.seed,
                batch.begin, known_max[job.direction], part);
            std::move(measured.begin(), measured.end(), out.begin() + batch.begin);
          }
        });
    if (!area || !fields.empty()) return;
    std::array<Tally, 2> measured;
    for (const Batch& batch : pass)
      for (size_t i = batch.begin; i < batch.end; ++i) {
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
