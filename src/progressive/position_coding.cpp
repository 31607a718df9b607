// The positions of a SPLT's new vertices: docs/FORMAT.md "Positions" (the SPLT part) is the
// specification, position_coding.h sums it up.
#include "position_coding.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/parallel.h"

namespace dynpm::progressive {
namespace {

// How many splits ahead the motion guess asks for its ring's values (code_batch()).
constexpr size_t kRingsAhead = 8;

// The ring fit's pull toward the identity: λ = (trace(B) + 1) / 1024 (ring_motion_guess()).
// Measured on the crash data: 2⁻⁸ … 2⁻¹⁴ of the trace give files within 1.5 % of each other,
// no pull 5–27 % larger ones (a shell's ring is flat: B is singular across it).
constexpr double kRingFitPull = 1.0 / 1024;
// A fitted guess this far out (grid steps) is refused: it stays an exact integer in int64 and JS.
constexpr double kRingFitLimit = 0x1p40;

// Step t > 0 (FORMAT.md "Positions", in SPLT): the linear map that takes the ring's offsets from
// its centre at t − 1 to those at t (least squares, pulled toward the identity by λ), applied
// to v0's offset at t − 1 and added to the centre at t. A shell turns and stretches as it crushes:
// the ring's mean motion alone misses the turn by the angle times v0's offset (the files are
// 8–24 % smaller with the fit on the crash data: docs/BENCHMARKS.md). Binary64, each operation in
// the order written: the JS decoder repeats it step by step (the module is compiled with
// -ffp-contract=off, so no fused multiply-add changes a rounding). False (the mean motion is used)
// with fewer than 3 ring vertices or when the system or the result is not sound.
template <class Now, class Before>
bool ring_motion_guess(const ChunkStencils& cs, const SplitStencil& s, uint32_t v0, Now now,
                       Before before, std::array<int64_t, 3>& guess) {
  const uint32_t count = s.ring_end - s.ring_begin;
  if (count < 3) return false;
  std::array<int64_t, 3> sum0{}, sum1{};
  for (uint32_t k = s.ring_begin; k < s.ring_end; ++k)
    for (int c = 0; c < 3; ++c) sum0[c] += before(cs.ring[k], c), sum1[c] += now(cs.ring[k], c);
  const double n = count;
  std::array<double, 3> c0, c1;
  for (int c = 0; c < 3; ++c) c0[c] = double(sum0[c]) / n, c1[c] = double(sum1[c]) / n;
  // B = Σ e0 e0ᵀ (symmetric: 00 11 22 01 02 12), A = Σ e1 e0ᵀ, in ring order (ascending).
  double b00 = 0, b11 = 0, b22 = 0, b01 = 0, b02 = 0, b12 = 0;
  std::array<std::array<double, 3>, 3> a{};
  for (uint32_t k = s.ring_begin; k < s.ring_end; ++k) {
    std::array<double, 3> e0, e1;
    for (int c = 0; c < 3; ++c)
      e0[c] = double(before(cs.ring[k], c)) - c0[c], e1[c] = double(now(cs.ring[k], c)) - c1[c];
    b00 += e0[0] * e0[0], b11 += e0[1] * e0[1], b22 += e0[2] * e0[2];
    b01 += e0[0] * e0[1], b02 += e0[0] * e0[2], b12 += e0[1] * e0[2];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] += e1[r] * e0[c];
  }
  const double lambda = (b00 + b11 + b22) * kRingFitPull + kRingFitPull;
  const double k00 = b00 + lambda, k11 = b11 + lambda, k22 = b22 + lambda;
  // y = (B + λI)⁻¹ d by the adjugate, d = v0's offset at t − 1.
  const double m00 = k11 * k22 - b12 * b12, m01 = b02 * b12 - b01 * k22,
               m02 = b01 * b12 - b02 * k11, m11 = k00 * k22 - b02 * b02,
               m12 = b01 * b02 - k00 * b12, m22 = k00 * k11 - b01 * b01;
  const double det = k00 * m00 + b01 * m01 + b02 * m02;
  if (!(det > 0)) return false;
  std::array<double, 3> d;
  for (int c = 0; c < 3; ++c) d[c] = double(before(v0, c)) - c0[c];
  const std::array<double, 3> y{(m00 * d[0] + m01 * d[1] + m02 * d[2]) / det,
                                (m01 * d[0] + m11 * d[1] + m12 * d[2]) / det,
                                (m02 * d[0] + m12 * d[1] + m22 * d[2]) / det};
  std::array<double, 3> x;
  for (int r = 0; r < 3; ++r) {
    x[r] = std::floor(c1[r] + ((a[r][0] * y[0] + a[r][1] * y[1] + a[r][2] * y[2]) + lambda * y[r]) +
                      0.5);
    if (!(std::abs(x[r]) < kRingFitLimit)) return false;  // NaN too
  }
  for (int c = 0; c < 3; ++c) guess[c] = static_cast<int64_t>(x[c]);
  return true;
}

// The guesses of q_t(v0) on the three coordinates before the correction by v0's own last misses
// (FORMAT.md "Positions", in SPLT); now(u, c) and before(u, c) give vertex u's q-value on
// coordinate c at steps t and t − 1. The three at once: the ring's values of a vertex lie
// together, and split order is not spatial, so each ring vertex is one miss instead of three.
template <class Now, class Before>
std::array<int64_t, 3> uncorrected_guesses(const ChunkStencils& cs, const SplitStencil& s,
                                           const Grid& g, uint32_t v0, size_t t, Now now,
                                           Before before) {
  std::array<int64_t, 3> guess{};
  if (g.lossless) {
    for (int c = 0; c < 3; ++c)
      guess[c] = t == 0 ? now(s.parent, c)
                        : g.add(before(v0, c), g.residual(now(s.parent, c), before(s.parent, c)));
    return guess;
  }
  if (t == 0) {
    for (int c = 0; c < 3; ++c) {
      if (s.quads == 0) {
        guess[c] = now(s.parent, c);
        continue;
      }
      int64_t sum = 0;
      for (int k = 0; k < s.quads; ++k) sum += now(s.w[k], c) + now(s.parent, c) - now(s.x[k], c);
      guess[c] = rounded_mean(sum, s.quads);
    }
    return guess;
  }
  if (ring_motion_guess(cs, s, v0, now, before, guess)) return guess;
  std::array<int64_t, 3> motion{};
  for (uint32_t k = s.ring_begin; k < s.ring_end; ++k)
    for (int c = 0; c < 3; ++c) motion[c] += now(cs.ring[k], c) - before(cs.ring[k], c);
  for (int c = 0; c < 3; ++c)
    guess[c] = before(v0, c) + rounded_mean(motion[c], s.ring_end - s.ring_begin);
  return guess;
}

// 3/8 of the last step's miss `before`, rounded half up; only from t = 2 on (at t = 1 that miss
// is step 0's, not a motion's) and not when lossless.
int64_t correction(const Grid& g, size_t t, int64_t before) {
  return !g.lossless && t >= 2 ? floor_div(3 * before + 4, 8) : 0;
}

// Walks the chunk's positions in the file's order; value(t, v, c, guess, model, got) codes or
// decodes q_t(v) into got. False when value() is.
template <class Value>
bool walk(const ProgressiveMesh& mesh, uint32_t first, const ChunkStencils& stencils,
          SplitPositionModels& models, size_t steps, const GridValues& qv, Value&& value) {
  const Grid g = grid_of(mesh);
  const size_t n = stencils.splits.size();
  std::vector<int64_t> before(n * 3, 0);  // the residuals at t − 1
  for (size_t t = 0; t < steps; ++t) {
    auto& m = models.step(t);
    for (size_t k = 0; k < n; ++k) {
      if (const size_t ahead = k + kRingsAhead; t > 0 && ahead < n)  // as in code_batch()
        for (uint32_t i = stencils.splits[ahead].ring_begin; i < stencils.splits[ahead].ring_end;
             ++i) {
          qv.prefetch(stencils.ring[i], t);
          qv.prefetch(stencils.ring[i], t - 1);
        }
      const uint32_t v = mesh.base_vertex_count + first + static_cast<uint32_t>(k);
      const std::array<int64_t, 3> guesses = uncorrected_guesses(
          stencils, stencils.splits[k], g, v, t, [&](uint32_t u, int c) { return qv.at(u, t, c); },
          [&](uint32_t u, int c) { return qv.at(u, t - 1, c); });
      for (int c = 0; c < 3; ++c) {
        int64_t& r = before[k * 3 + c];
        const int64_t expected = guesses[c] + correction(g, t, r);
        int64_t got;
        if (!value(t, v, c, expected, m[c][t > 0 ? residual_bucket(r) : 0], got)) return false;
        r = g.residual(got, expected);
      }
    }
  }
  return true;
}

}  // namespace

void GridValues::take(const ProgressiveMesh& mesh, size_t steps, uint32_t begin, uint32_t end) {
  const Grid g = grid_of(mesh);
  resize(steps, std::max<uint32_t>(end, static_cast<uint32_t>(q_.empty() ? 0 : q_[0].size() / 3)));
  for (size_t t = 0; t < steps; ++t)
    for (size_t k = size_t{begin} * 3; k < size_t{end} * 3; ++k)
      q_[t][k] = static_cast<uint32_t>(g.q(mesh.positions[t][k], static_cast<int>(k % 3)));
}

void GridValues::move_to_positions(ProgressiveMesh& mesh, size_t t, uint32_t begin) {
  const Grid g = grid_of(mesh);
  std::vector<float>& xyz = mesh.positions[t];
  xyz.resize(q_[t].size());
  for (size_t k = size_t{begin} * 3; k < xyz.size(); ++k)
    xyz[k] =
        g.p(at(static_cast<uint32_t>(k / 3), t, static_cast<int>(k % 3)), static_cast<int>(k % 3));
  std::vector<uint32_t>().swap(q_[t]);  // freed (assigning {} would keep the capacity)
}

void ChunkStencils::add(const ProgressiveMesh& mesh, uint32_t i, std::span<const Face> faces) {
  SplitStencil s;
  s.parent = mesh.parent[i];
  s.ring_begin = static_cast<uint32_t>(ring.size());
  ring.push_back(s.parent);
  for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
    const SplitWing& w = mesh.wings[k];
    ring.push_back(w.vertex);
    if (w.was_triangle()) continue;
    s.w[s.quads] = w.vertex;
    s.x[s.quads] = faces[w.face].v[(w.v0_slot() + 2) % 4];
    ++s.quads;
  }
  const uint32_t v0 = mesh.base_vertex_count + i;
  for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m) {
    const Face& f = faces[mesh.moved_faces[m]];
    const int d = f.degree();
    for (int c = 0; c < d; ++c)
      if (f.v[c] == v0) {
        ring.push_back(f.v[(c + 1) % d]);
        ring.push_back(f.v[(c + d - 1) % d]);
      }
  }
  // A set: each neighbour once (a mean does not depend on the order).
  std::sort(ring.begin() + s.ring_begin, ring.end());
  ring.erase(std::unique(ring.begin() + s.ring_begin, ring.end()), ring.end());
  s.ring_end = static_cast<uint32_t>(ring.size());
  splits.push_back(s);
}

StepPositionEncoder::StepPositionEncoder(const ProgressiveMesh& mesh, const ChunkStencils& all,
                                         std::span<const std::pair<uint32_t, uint32_t>> chunks,
                                         unsigned threads)
    : mesh_(mesh),
      all_(all),
      chunks_(chunks),
      threads_(thread_count(threads)),
      batch_steps_(std::min(threads_, kMaxBatchSteps)) {
  sections_.reserve(mesh.step_count());
}

std::vector<uint32_t> StepPositionEncoder::spare_step() {
  std::vector<uint32_t> q;
  if (!spare_q_.empty()) {
    q = std::move(spare_q_.back());
    spare_q_.pop_back();
  }
  q.resize(size_t{mesh_.vertex_count()} * 3);
  return q;
}

void StepPositionEncoder::add_step(std::vector<uint32_t> q) {
  batch_.push_back(std::move(q));
  if (batch_.size() == batch_steps_) code_batch();
}

std::vector<std::vector<std::string>> StepPositionEncoder::finish() {
  if (!batch_.empty()) code_batch();
  // Their memory back for the rest of the file's writing and the thumbnail.
  spare_q_ = {}, residuals_ = {};         // their vectors freed with them
  std::vector<uint32_t>().swap(last_q_);  // freed: `= {}` keeps the capacity
  std::vector<int32_t>().swap(last_r_);
  return std::move(sections_);
}

// Each step's misses (the residual before the correction) on every thread, then the corrections
// in step order (a residual's own recurrence), then each step's sections on a thread of its own
// (a step's models run through every chunk in order).
void StepPositionEncoder::code_batch() {
  const Grid g = grid_of(mesh_);
  const uint32_t b = mesh_.base_vertex_count;
  const size_t splits = all_.splits.size(), parts = std::max<size_t>(1, splits / 4096);
  const size_t first = steps_done_, count = batch_.size();
  const auto step_q = [&](size_t s) -> const std::vector<uint32_t>& {
    return s >= first ? batch_[s - first] : last_q_;
  };
  const auto value = [&](const std::vector<uint32_t>& q, uint32_t u, int c) {
    const uint32_t stored = q[size_t{u} * 3 + c];
    return g.lossless ? int64_t{stored} : int64_t{static_cast<int32_t>(stored)};
  };
  std::vector<std::vector<int32_t>>& r = residuals_;  // every element is written below
  r.resize(count);
  for (auto& step : r) step.resize(splits * 3);
  for (size_t j = 0; j < count; ++j) {
    const size_t t = first + j;
    const std::vector<uint32_t>& now = step_q(t);
    const std::vector<uint32_t>& last = step_q(t > 0 ? t - 1 : t);
    parallel_for(splits, parts, threads_, [&](size_t begin, size_t end, size_t) {
      for (size_t k = begin; k < end; ++k) {
        // The neighbours' values, scattered (split order is not spatial): asked for a few
        // splits ahead, their misses overlap instead of stalling the sums one by one.
        if (const size_t ahead = k + kRingsAhead; t > 0 && ahead < end)
          for (uint32_t i = all_.splits[ahead].ring_begin; i < all_.splits[ahead].ring_end; ++i) {
            prefetch(&now[size_t{all_.ring[i]} * 3]);
            prefetch(&last[size_t{all_.ring[i]} * 3]);
          }
        const uint32_t v = b + static_cast<uint32_t>(k);
        const std::array<int64_t, 3> guesses = uncorrected_guesses(
            all_, all_.splits[k], g, v, t, [&](uint32_t u, int c) { return value(now, u, c); },
            [&](uint32_t u, int c) { return value(last, u, c); });
        for (int c = 0; c < 3; ++c) {
          const int64_t miss = g.residual(value(now, v, c), guesses[c]);
          r[j][k * 3 + c] = static_cast<int32_t>(miss);  // |miss| < 2^31: q < 2^23
        }
      }
    });
  }
  const auto before = [&](size_t j) -> const std::vector<int32_t>& {
    return j > 0 ? r[j - 1] : last_r_;
  };
  if (!g.lossless)
    parallel_for(splits, parts, threads_, [&](size_t begin, size_t end, size_t) {
      for (size_t j = 0; j < count; ++j)
        if (const size_t t = first + j; t >= 2)
          for (size_t i = begin * 3; i < end * 3; ++i)
            r[j][i] = static_cast<int32_t>(r[j][i] - correction(g, t, before(j)[i]));
    });
  sections_.resize(first + count);
  parallel_for(count, count, threads_, [&](size_t begin, size_t end, size_t) {
    for (size_t j = begin; j < end; ++j) {
      const size_t t = first + j;
      std::array<std::array<SignedModel, kResidualBuckets>, 3> m;  // step t's, chunk to chunk
      // Held here: the coder's writes could otherwise be taken to move the vectors' arrays.
      const int32_t* now = r[j].data();
      const int32_t* last = before(j).data();
      for (const auto& [from, to] : chunks_) {
        RangeEncoder coder;
        for (size_t i = size_t{from} * 3; i < size_t{to} * 3; i += 3)
          for (int c = 0; c < 3; ++c)
            m[c][t > 0 ? residual_bucket(last[i + c]) : 0].encode(coder, now[i + c]);
        sections_[t].push_back(coder.finish());
      }
    }
  });
  steps_done_ += count;
  spare_q_.push_back(std::move(last_q_));
  last_q_ = std::move(batch_.back());
  batch_.pop_back();
  for (auto& q : batch_) spare_q_.push_back(std::move(q));
  std::swap(last_r_, r.back());
  batch_.clear();
}

std::string decode_split_positions(const ProgressiveMesh& mesh, uint32_t first,
                                   const ChunkStencils& stencils, SplitPositionModels& models,
                                   std::span<const std::string_view> sections, GridValues& q) {
  const Grid g = grid_of(mesh);
  // A quantized position lies in the bounding box, give or take two grid steps.
  std::array<double, 3> top{};
  for (int c = 0; c < 3; ++c) top[c] = (mesh.bbox_max[c] - mesh.bbox_min[c]) / g.step + 2;
  std::vector<RangeDecoder> decoders;
  for (std::string_view s : sections) decoders.emplace_back(s);
  std::string problem;
  walk(mesh, first, stencils, models, sections.size(), q,
       [&](size_t t, uint32_t v, int c, int64_t guess, SignedModel& m, int64_t& got) {
         RangeDecoder& d = decoders[t];
         const int64_t residual = m.decode(d);
         got = g.add(guess, residual);
         if (!d.ok()) {
           problem = "the positions of step " + std::to_string(t) + " are cut short";
           return false;
         }
         if (!residual_fits(residual, g.lossless)) {
           problem = "step " + std::to_string(t) + ": vertex " + std::to_string(v) + ": " +
                     kLosslessResidual;
           return false;
         }
         if (!g.lossless && (got < -2 || double(got) > top[c])) {
           problem = "step " + std::to_string(t) + ": vertex " + std::to_string(v) +
                     "'s position is far outside the bounding box";
           return false;
         }
         q.set(v, t, c, got);
         return true;
       });
  if (!problem.empty()) return problem;
  for (size_t t = 0; t < decoders.size(); ++t)
    if (!decoders[t].exhausted())
      return "the positions of step " + std::to_string(t) + " leave bytes unread";
  return {};
}

}  // namespace dynpm::progressive
