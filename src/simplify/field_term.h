// The field term of the collapse cost (issue 18, docs/simplify.md "Fields in the cost"): per
// vertex, key step and cost field, what the vertex stands for, in one of three measured forms
// (FieldForm):
//
//   kSpread      the interval [lo, hi] of the values the vertex stands for — a node field's own
//                value, or the smallest and largest value of its faces for an element field. A
//                collapse unites v0's and v1's intervals; the shown value of v1 (max |value| or
//                mean of what it stands for) differs from each original value by at most
//                hi − lo, so the spread is what the collapse costs the field. 2 floats.
//   kAttributes  an attribute quadric in Hoppe's 1999 memory-efficient form, evaluated at v1's
//                own value (meshoptimizer's simplifyWithAttributes): per face a linear fit of the
//                field (a node field's gradient over each triangle; an element field is constant
//                on its face), Σ area · (g·p + d − s)². The 3×3 block Σ area · g gᵀ (with its b
//                and c) is shared by the fields, kept beside the geometric quadric so that the
//                geometric error stays separate; per field only Σ area · g and Σ area · d.
//   kQuadric     the same quadric at its optimal value s (Garland–Heckbert 1998): the
//                area-weighted residual of the fits, whatever value the level shows.
//
// Values are scaled to [0, 1] by each field's range over the key steps before they enter the
// quadric (floats keep the differences exact even for a field far from 0, a temperature).
// squared() returns Σ over the fields of (weight · diagonal · error)², a squared length next to
// the geometric mean squared distance; how the two combine is FieldCombine (quadrics.h).
#pragma once

#include <cmath>
#include <span>
#include <vector>

#include "collapse_mesh.h"
#include "core/face_geometry.h"
#include "dynpm/simplify.h"

namespace dynpm::simplification {

class FieldTerm {
 public:
  // Which fields, before the key steps are read.
  void choose(std::span<const CostField> fields, std::span<const FieldInfo> infos, FieldForm form,
              size_t key_count, uint32_t vertex_count);
  // Reads the cost fields at key step k (step t of the source).
  Status load_step(const FrameSource& frames, const Topology& input, size_t k, size_t t);
  // After the last key step: each field's scale from its range and the diagonal.
  void finish(double diagonal);
  // The quadric forms: the attribute quadrics of the input mesh from the key steps' positions
  // (xyz per key step, vertex-major as KeyStepQuadrics keeps them). Nothing for kSpread.
  void build(const Topology& input, const CollapseMesh& mesh, std::span<const float> positions,
             unsigned threads);

  bool empty() const { return fields_.empty(); }
  // The field error of v0 → v1 in key step k, squared, as a length: Σ over the cost fields of
  // (weight · diagonal · error / range)². `offset` is v1's position minus v0's in that step.
  double squared(uint32_t v0, uint32_t v1, size_t k, Vec3 offset) const {
    if (fields_.empty()) return 0;
    return form_ == FieldForm::kSpread ? spread_squared(v0, v1, k)
                                       : quadric_squared(v0, v1, k, offset);
  }
  // After the collapse v0 → v1 (each key step's offset as for squared()): v1 stands for v0's
  // values too. With optimal placement `moves` holds v1's move in each key step (else empty).
  void merge(uint32_t v0, uint32_t v1, std::span<const Vec3> offsets, std::span<const Vec3> moves);

  // Floats kept per vertex and key step (docs/simplify.md states the memory).
  size_t floats_per_vertex_step() const;

 private:
  double spread_squared(uint32_t v0, uint32_t v1, size_t k) const {
    double sum = 0;
    const float* a = interval(v0, k);
    const float* b = interval(v1, k);
    for (size_t f = 0; f < fields_.size(); ++f, a += 2, b += 2) {
      const double spread = double{std::max(a[1], b[1])} - std::min(a[0], b[0]);
      sum += scale_[f] * scale_[f] * spread * spread;
    }
    return sum;
  }
  double quadric_squared(uint32_t v0, uint32_t v1, size_t k, Vec3 offset) const;

  // data() + offset, not &intervals_[offset]: without cost fields the vector is empty.
  const float* interval(uint32_t v, size_t k) const {
    return intervals_.data() + ((size_t{v} * key_count_ + k) * fields_.size()) * 2;
  }
  float* interval(uint32_t v, size_t k) {
    return intervals_.data() + ((size_t{v} * key_count_ + k) * fields_.size()) * 2;
  }
  // The attribute quadric of v in key step k: shared block (xx xy xz yy yz zz bx by bz c), the
  // area α, then per field (Σ area·g: 3, Σ area·d: 1); around v's own position.
  size_t quadric_floats() const { return 11 + 4 * fields_.size(); }
  const float* quadric(uint32_t v, size_t k) const {
    return quadrics_.data() + (size_t{v} * key_count_ + k) * quadric_floats();
  }
  float* quadric(uint32_t v, size_t k) {
    return quadrics_.data() + (size_t{v} * key_count_ + k) * quadric_floats();
  }
  // A node field's value at v in key step k, scaled to [0, 1].
  float value(uint32_t v, size_t k, size_t f) const {
    return node_values_[(size_t{v} * key_count_ + k) * fields_.size() + f];
  }
  void add_translated(const float* q, Vec3 y, double* into) const;
  void build_quadric(const Topology& input, const CollapseMesh& mesh,
                     std::span<const float> positions, uint32_t v, size_t k);

  struct Chosen {
    size_t field;
    FieldInfo info;
    double weight;
    double lo = HUGE_VAL, hi = -HUGE_VAL;  // over the key steps
  };
  FieldForm form_ = FieldForm::kSpread;
  std::vector<Chosen> fields_;
  std::vector<double> scale_;     // per field: weight · diagonal / range
  std::vector<float> intervals_;  // kSpread: #V × #key steps × #fields × (lo, hi)
  // The quadric forms: raw values as read until finish() (node fields per vertex, element
  // fields per face; #key steps × #fields arrays), then node values scaled to [0, 1]
  // (#V × #key steps × #fields) and the quadrics (#V × #key steps × quadric_floats()).
  std::vector<std::vector<float>> read_;
  std::vector<float> node_values_;
  std::vector<float> quadrics_;
  std::vector<float> values_;  // one step of one field, as read
  size_t key_count_ = 0;
};

}  // namespace dynpm::simplification
