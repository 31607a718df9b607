// The sampling half of the Metro-style distance (hausdorff.cpp): the samples of one direction,
// cut into jobs by position in the vertex, edge and triangle lists, drawn and measured against
// the other surface, and tallied per job. Internal to the eval module.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "dynpm/eval.h"
#include "field_distance.h"

namespace dynpm::sampling {

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

// Jobs of about kSamplesPerJob samples each, cut by list position only. Without fields,
// consecutive ones of about kBatchSamples samples in all are one part of the work, measured in
// space order (run_jobs_in_space_order).
constexpr double kSamplesPerJob = 8192;
constexpr size_t kBatchSamples = size_t{1} << 19;

struct Job {
  uint32_t direction;
  SampleKind kind;
  size_t begin, end;  // a range of vertices, edges or triangles of `from`
  double samples;     // about how many it draws: its items times the average per item
};

// Which of a job's area samples a run measures: all, or (when the mean takes every
// mean_stride-th) those of the mean in a first pass and the others in a second. Both passes
// draw the same samples; each counts its own.
enum class AreaPart { kAll, kMean, kRest };

// The area of a triangle of a surface.
double triangle_area(const SurfaceTriangle& t);

// Appends jobs of about kSamplesPerJob samples over `count` items (vertices, edges or
// triangles of `from`) that draw `samples_per_item` samples each on average.
void add_jobs(std::vector<Job>& jobs, uint32_t direction, SampleKind kind, size_t count,
              double samples_per_item);

// `known_max` ≥ 0: a distance that some sample of this direction reaches (the mean's area
// samples' maximum, then every area sample's), set only when a sample outside the mean — a
// vertex or edge sample, or an area sample the mean skips — can matter through the maximum
// alone (no fields); such samples then need no exact distance (sample_jobs.cpp).
//
// One job, measured in drawing order (with fields, always).
Tally run_job(const Job& job, const Direction& d, uint64_t seed, size_t job_index, double known_max,
              AreaPart part);
// Consecutive jobs of one direction and kind without fields, measured in space order, with the
// same results as run_job() on each; jobs[i] has job index first_job_index + i.
std::vector<Tally> run_jobs_in_space_order(std::span<const Job> jobs, const Direction& d,
                                           uint64_t seed, size_t first_job_index, double known_max,
                                           AreaPart part);

}  // namespace dynpm::sampling
