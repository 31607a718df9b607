// The result fields' values of a SPLT's vertices and faces: docs/FORMAT.md "Fields: FDEF and
// FLDS" is the specification, field_coding.h sums it up.
#include "field_coding.h"

#include <algorithm>

#include "core/parallel.h"
#include "dpm_format.h"

namespace dynpm::progressive {
namespace {

bool per_face(const ProgressiveField& f) { return f.info.location == FieldLocation::kElement; }

// The chunk's items: its split vertices, or the faces its splits create.
std::pair<uint32_t, uint32_t> items_of(const ProgressiveMesh& mesh, const ProgressiveField& f,
                                       const FieldChunk& c) {
  if (per_face(f)) return {c.face_begin, c.face_end};
  return {mesh.base_vertex_count + c.first, mesh.base_vertex_count + c.last};
}

// The item a split item's value is predicted from: a vertex's parent, a face's heir.
uint32_t parent_of(const ProgressiveMesh& mesh, const ProgressiveField& f, uint32_t item) {
  return per_face(f) ? mesh.face_heir[item] : mesh.parent[item - mesh.base_vertex_count];
}

// Whether a section may use the ring: a node field on a grid (a median of float bit patterns
// means nothing).
bool ring_allowed(const ProgressiveField& f) { return !per_face(f) && !f.lossless; }

// The guess of item's q-value at step t (FORMAT.md "Fields: FDEF and FLDS"); q(u, s) gives item
// u's q-value at step s, `s` is the stencil of the split that made the item when it is a vertex.
template <class Q>
int64_t guess_of(const ProgressiveMesh& mesh, const ProgressiveField& f, const FieldGrid& g,
                 FieldPredictor predictor, const ChunkStencils& cs, const SplitStencil* s,
                 uint32_t item, size_t t, Q q) {
  if (t == 0 || predictor == FieldPredictor::kParent) {
    const uint32_t p = parent_of(mesh, f, item);
    if (t == 0) return q(p, 0);
    return g.add(q(item, t - 1), g.residual(q(p, t), q(p, t - 1)));
  }
  // The median change over the ring's first kMaxMedianRing vertices in ascending order (a real
  // ring has fewer), the lower one of an even count.
  std::array<int64_t, kMaxMedianRing> change;
  const uint32_t n = std::min<uint32_t>(s->ring_end - s->ring_begin, kMaxMedianRing);
  for (uint32_t k = 0; k < n; ++k)
    change[k] = q(cs.ring[s->ring_begin + k], t) - q(cs.ring[s->ring_begin + k], t - 1);
  std::nth_element(change.begin(), change.begin() + (n - 1) / 2, change.begin() + n);
  return q(item, t - 1) + change[(n - 1) / 2];
}

}  // namespace

std::vector<std::vector<std::vector<FieldSection>>> encode_split_fields(
    const ProgressiveMesh& mesh, const ChunkStencils& all, std::span<const FieldChunk> chunks,
    unsigned threads) {
  const size_t steps = mesh.step_count(), tasks = mesh.fields.size() * steps;
  std::vector<std::vector<std::vector<FieldSection>>> sections(
      mesh.fields.size(), std::vector<std::vector<FieldSection>>(steps));
  // Runs body(field, t, residual) for each field and step, a task each, where residual(item, s,
  // predictor) is item's residual at step s ∈ {t − 1, t}: each task turns the steps it reads
  // into q-values once (t − 2 … t), and works out t − 1's residuals (its contexts) again rather
  // than wait for the task before, so that every step codes on a thread of its own.
  const auto for_each_step = [&](auto&& body) {
    parallel_for(tasks, tasks, thread_count(threads), [&](size_t begin, size_t end, size_t) {
      for (size_t task = begin; task < end; ++task) {
        const size_t index = task / steps, t = task % steps;
        const ProgressiveField& f = mesh.fields[index];
        const FieldGrid g(f);
        // Steps t − 2, t − 1, t (those that exist), 32 bits a value: grid integers, or float bits.
        std::array<std::vector<uint32_t>, 3> q;
        for (size_t k = 0; k < 3 && k <= t; ++k) {
          const std::vector<float>& values = f.values[t - k];
          q[2 - k].resize(values.size());
          for (size_t u = 0; u < values.size(); ++u)
            q[2 - k][u] = static_cast<uint32_t>(g.q(values[u]));
        }
        const auto value = [&](uint32_t u, size_t r) {
          const uint32_t stored = q[2 - (t - r)][u];
          return g.lossless ? int64_t{stored} : int64_t{static_cast<int32_t>(stored)};
        };
        body(index, t, [&](uint32_t item, size_t s, FieldPredictor predictor) {
          const SplitStencil* stencil =
              per_face(f) ? nullptr : &all.splits[item - mesh.base_vertex_count];
          return g.residual(value(item, s),
                            guess_of(mesh, f, g, predictor, all, stencil, item, s, value));
        });
      }
    });
  };
  // First each section's predictor, by an estimate of its bits (a residual r costs about
  // bit_width(|r|) + 1): a field that spreads over regions (stress, strain) follows its ring,
  // one that is constant over parts or changes by whole regions at once its parent.
  for_each_step([&](size_t index, size_t t, auto residual) {
    const ProgressiveField& f = mesh.fields[index];
    for (const FieldChunk& c : chunks) {
      FieldPredictor best = FieldPredictor::kParent;
      if (t > 0 && ring_allowed(f)) {
        const auto [first, last] = items_of(mesh, f, c);
        std::array<uint64_t, 2> bits{};
        for (uint32_t item = first; item < last; ++item)
          for (FieldPredictor p : {FieldPredictor::kParent, FieldPredictor::kRingMedian}) {
            const int64_t r = residual(item, t, p);
            bits[size_t(p)] += std::bit_width(static_cast<uint64_t>(r < 0 ? -r : r)) + 1;
          }
        if (bits[1] < bits[0]) best = FieldPredictor::kRingMedian;
      }
      sections[index][t].push_back({best, {}});
    }
  });
  // Then the sections: a step's models run through every chunk in order; a residual's context
  // is the same item's residual at t − 1, with that section's predictor.
  for_each_step([&](size_t index, size_t t, auto residual) {
    const ProgressiveField& f = mesh.fields[index];
    SplitFieldModels::StepModels models;
    for (size_t c = 0; c < chunks.size(); ++c) {
      const auto [first, last] = items_of(mesh, f, chunks[c]);
      FieldSection& section = sections[index][t][c];
      const FieldPredictor before = t > 0 ? sections[index][t - 1][c].predictor : section.predictor;
      RangeEncoder coder;
      for (uint32_t item = first; item < last; ++item) {
        const int bucket = t > 0 ? residual_bucket(residual(item, t - 1, before)) : 0;
        models[bucket].encode(coder, residual(item, t, section.predictor));
      }
      section.bytes = coder.finish();
    }
  });
  return sections;
}

std::string decode_split_field(const ProgressiveMesh& mesh, ProgressiveField& f,
                               const FieldChunk& chunk, const ChunkStencils& stencils,
                               std::span<SplitFieldModels::StepModels> models,
                               std::span<const FieldSectionView> sections) {
  const FieldGrid g(f);
  const auto [first, last] = items_of(mesh, f, chunk);
  // A quantized value lies in [min, max], give or take two grid steps.
  const double top = g.lossless ? 0 : (f.max - f.min) / g.step + 2;
  const auto q = [&](uint32_t u, size_t s) { return g.q(f.values[s][u]); };
  std::vector<int64_t> before(last - first, 0);  // the residuals at t − 1
  for (size_t t = 0; t < sections.size(); ++t) f.values[t].resize(last);
  for (size_t t = 0; t < sections.size(); ++t) {
    const std::string at = "step " + std::to_string(t) + ": ";
    const FieldPredictor predictor = sections[t].predictor;
    if (predictor != FieldPredictor::kParent &&
        !(predictor == FieldPredictor::kRingMedian && t > 0 && ring_allowed(f)))
      return at + "predictor " + std::to_string(int(predictor)) + " is not valid here";
    RangeDecoder d(sections[t].bytes);
    for (uint32_t item = first; item < last; ++item) {
      const SplitStencil* s =
          per_face(f) ? nullptr : &stencils.splits[item - mesh.base_vertex_count - chunk.first];
      int64_t& r = before[item - first];
      r = models[t][t > 0 ? residual_bucket(r) : 0].decode(d);
      if (!d.ok()) return at + "the values are cut short";
      if (!residual_fits(r, g.lossless))
        return at + "item " + std::to_string(item) + ": " + kLosslessResidual;
      const int64_t value = g.add(guess_of(mesh, f, g, predictor, stencils, s, item, t, q), r);
      const float x = g.value(value);
      if (g.lossless ? !(x >= f.min && x <= f.max) : (value < -2 || double(value) > top))
        return at + "item " + std::to_string(item) + "'s value is far outside the field's range";
      f.values[t][item] = x;
    }
    if (!d.exhausted()) return at + "the values leave bytes unread";
  }
  return {};
}

}  // namespace dynpm::progressive
