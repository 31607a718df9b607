#include "field_term.h"

#include <algorithm>
#include <string>

#include "core/parallel.h"

namespace dynpm::simplification {

void FieldTerm::choose(std::span<const CostField> fields, std::span<const FieldInfo> infos,
                       FieldForm form, size_t key_count, uint32_t vertex_count) {
  fields_.clear();
  for (const CostField& c : fields) fields_.push_back({c.field, infos[c.field], c.weight});
  form_ = form;
  key_count_ = key_count;
  if (form_ == FieldForm::kSpread)
    intervals_.assign(size_t{vertex_count} * key_count * fields_.size() * 2, 0.0f);
  else
    read_.assign(key_count * fields_.size(), {});
}

Status FieldTerm::load_step(const FrameSource& frames, const Topology& input, size_t k, size_t t) {
  const uint32_t n = input.vertex_count;
  for (size_t f = 0; f < fields_.size(); ++f) {
    Chosen& c = fields_[f];
    const bool element = c.info.location == FieldLocation::kElement;
    values_.resize(element ? input.faces.size() : n);
    DYNPM_RETURN_IF_ERROR(frames.read_field(c.field, t, values_));
    for (float x : values_)
      if (!std::isfinite(x))
        return Status::error("field " + c.info.name + " at step " + std::to_string(t) +
                             " holds a value that is not a finite number");
    if (!values_.empty()) {
      const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
      c.lo = std::min(c.lo, double{*lo}), c.hi = std::max(c.hi, double{*hi});
    }
    if (form_ != FieldForm::kSpread) {
      read_[k * fields_.size() + f] = values_;  // the quadrics need the ranges first
      continue;
    }
    if (!element) {
      for (uint32_t v = 0; v < n; ++v)
        interval(v, k)[2 * f] = interval(v, k)[2 * f + 1] = values_[v];
      continue;
    }
    // An element field at a vertex: the smallest and largest value of its faces, since a
    // collapse merges the faces around v0 into those around v1 (a vertex without faces: 0).
    for (uint32_t v = 0; v < n; ++v)
      interval(v, k)[2 * f] = HUGE_VALF, interval(v, k)[2 * f + 1] = -HUGE_VALF;
    for (size_t face = 0; face < input.faces.size(); ++face)
      for (int corner = 0; corner < input.faces[face].degree(); ++corner) {
        float* i = interval(input.faces[face].v[corner], k) + 2 * f;
        i[0] = std::min(i[0], values_[face]), i[1] = std::max(i[1], values_[face]);
      }
    for (uint32_t v = 0; v < n; ++v)
      if (interval(v, k)[2 * f] > interval(v, k)[2 * f + 1])
        interval(v, k)[2 * f] = interval(v, k)[2 * f + 1] = 0;
  }
  return {};
}

void FieldTerm::finish(double diagonal) {
  scale_.clear();
  for (const Chosen& c : fields_) {
    const double range = c.hi - c.lo;
    scale_.push_back(range > 0 ? c.weight * diagonal / range : 0.0);
  }
  std::vector<float>().swap(values_);
}

void FieldTerm::build(const Topology& input, const CollapseMesh& mesh,
                      std::span<const float> positions, unsigned threads) {
  if (form_ == FieldForm::kSpread || fields_.empty()) return;
  // Node values scaled to [0, 1] by their range, vertex-major like the quadrics.
  const uint32_t n = input.vertex_count;
  const size_t m = fields_.size();
  node_values_.assign(size_t{n} * key_count_ * m, 0.0f);
  for (size_t k = 0; k < key_count_; ++k)
    for (size_t f = 0; f < m; ++f) {
      std::vector<float>& raw = read_[k * m + f];
      const double range = fields_[f].hi - fields_[f].lo;
      for (float& x : raw) x = range > 0 ? static_cast<float>((x - fields_[f].lo) / range) : 0.0f;
      if (fields_[f].info.location == FieldLocation::kNode)
        for (uint32_t v = 0; v < n; ++v)
          node_values_[(size_t{v} * key_count_ + k) * m + f] = raw[v];
    }
  quadrics_.assign(size_t{n} * key_count_ * quadric_floats(), 0.0f);
  parallel_for_chunks(size_t{n} * key_count_, threads, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i)
      build_quadric(input, mesh, positions, static_cast<uint32_t>(i / key_count_), i % key_count_);
  });
  std::vector<std::vector<float>>().swap(read_);
  if (form_ == FieldForm::kQuadric) std::vector<float>().swap(node_values_);
}

// Per face of v, in v's face order, per triangle (a quad as the triangles 012 and 023): the
// linear fit of each field, g·p + d with p around v, weighted by the triangle's area.
void FieldTerm::build_quadric(const Topology& input, const CollapseMesh& mesh,
                              std::span<const float> positions, uint32_t v, size_t k) {
  const size_t m = fields_.size();
  auto at = [&](uint32_t w) { return load(&positions[(size_t{w} * key_count_ + k) * 3]); };
  const Vec3 origin = at(v);
  std::vector<double> q(quadric_floats(), 0.0);  // xx xy xz yy yz zz bx by bz c α (G D)…
  for (uint32_t face_id : mesh.faces_of(v)) {
    const Face& face = input.faces[face_id];
    const int d = face.degree();
    for (int tri = 0; tri + 2 < d; ++tri) {
      const uint32_t c[3] = {face.v[0], face.v[tri + 1], face.v[tri + 2]};
      const Vec3 p0 = at(c[0]) - origin, e1 = at(c[1]) - at(c[0]), e2 = at(c[2]) - at(c[0]);
      const Vec3 normal = cross(e1, e2);
      const double doubled = dot(normal, normal);
      if (!(doubled > 0)) continue;
      const double area = 0.5 * std::sqrt(doubled);
      q[10] += area;
      for (size_t f = 0; f < m; ++f) {
        const double weight = scale_[f] * (fields_[f].hi - fields_[f].lo);  // weight · diagonal
        const double c2 = weight * weight;
        const std::vector<float>& u = read_[k * m + f];
        Vec3 g{};
        double offset;
        if (fields_[f].info.location == FieldLocation::kElement) {
          offset = u[face_id];
        } else {
          // The gradient in the triangle's plane: g·e1 = u1 − u0, g·e2 = u2 − u0, g·n = 0.
          const double du1 = double{u[c[1]]} - u[c[0]], du2 = double{u[c[2]]} - u[c[0]];
          g = (cross(e2, normal) * du1 + cross(normal, e1) * du2) * (1.0 / doubled);
          offset = u[c[0]] - dot(g, p0);
        }
        const double a = area * c2;
        q[0] += a * g.x * g.x, q[1] += a * g.x * g.y, q[2] += a * g.x * g.z;
        q[3] += a * g.y * g.y, q[4] += a * g.y * g.z, q[5] += a * g.z * g.z;
        q[6] += a * g.x * offset, q[7] += a * g.y * offset, q[8] += a * g.z * offset;
        q[9] += a * offset * offset;
        double* per_field = &q[11 + 4 * f];
        per_field[0] += area * g.x, per_field[1] += area * g.y, per_field[2] += area * g.z;
        per_field[3] += area * offset;
      }
    }
  }
  std::copy(q.begin(), q.end(), quadric(v, k));
}

namespace {

// v0's attribute quadric seen from v1 (offset: v1's position around v0): its shared c and
// each field's Σ area · d there.
double shared_at(const float* q, Vec3 y) {
  const double v = y.x * (q[0] * y.x + q[1] * y.y + q[2] * y.z) +
                   y.y * (q[1] * y.x + q[3] * y.y + q[4] * y.z) +
                   y.z * (q[2] * y.x + q[4] * y.y + q[5] * y.z) +
                   2 * (q[6] * y.x + q[7] * y.y + q[8] * y.z) + q[9];
  return v;
}
double field_offset_at(const float* per_field, Vec3 y) {
  return per_field[3] + per_field[0] * y.x + per_field[1] * y.y + per_field[2] * y.z;
}

}  // namespace

double FieldTerm::quadric_squared(uint32_t v0, uint32_t v1, size_t k, Vec3 offset) const {
  const float* q0 = quadric(v0, k);
  const float* q1 = quadric(v1, k);
  const double area = double{q0[10]} + q1[10];
  if (!(area > 0)) return 0;
  double e = shared_at(q0, offset) + q1[9];
  for (size_t f = 0; f < fields_.size(); ++f) {
    const double weight = scale_[f] * (fields_[f].hi - fields_[f].lo);
    const double sum_d = field_offset_at(q0 + 11 + 4 * f, offset) + q1[11 + 4 * f + 3];
    // The optimal value (kQuadric, and an element field, which has no value at v1) or v1's own.
    const bool own =
        form_ == FieldForm::kAttributes && fields_[f].info.location == FieldLocation::kNode;
    const double s = own ? double{value(v1, k, f)} : sum_d / area;
    e += weight * weight * (s * s * area - 2 * s * sum_d);
  }
  return e > 0 ? e / area : 0;
}

// The quadric q seen from y (y around q's origin), added to `into` (zero: just moved).
void FieldTerm::add_translated(const float* q, Vec3 y, double* into) const {
  // b' = A y + b and c' = Q(y); A, α and each Σ area · g unchanged, each Σ area · d at y.
  for (int i = 0; i < 6; ++i) into[i] += q[i];
  into[6] += q[0] * y.x + q[1] * y.y + q[2] * y.z + q[6];
  into[7] += q[1] * y.x + q[3] * y.y + q[4] * y.z + q[7];
  into[8] += q[2] * y.x + q[4] * y.y + q[5] * y.z + q[8];
  into[9] += shared_at(q, y);
  into[10] += q[10];
  for (size_t f = 0; f < fields_.size(); ++f) {
    const float* per_field = q + 11 + 4 * f;
    for (int i = 0; i < 3; ++i) into[11 + 4 * f + i] += per_field[i];
    into[11 + 4 * f + 3] += field_offset_at(per_field, y);
  }
}

void FieldTerm::merge(uint32_t v0, uint32_t v1, std::span<const Vec3> offsets,
                      std::span<const Vec3> moves) {
  if (form_ == FieldForm::kSpread) {
    for (size_t k = 0; k < key_count_; ++k) {
      const float* a = interval(v0, k);
      float* b = interval(v1, k);
      for (size_t f = 0; f < fields_.size(); ++f)
        b[2 * f] = std::min(b[2 * f], a[2 * f]),
              b[2 * f + 1] = std::max(b[2 * f + 1], a[2 * f + 1]);
    }
    return;
  }
  if (fields_.empty()) return;
  std::vector<double> sum(quadric_floats()), moved(quadric_floats());
  for (size_t k = 0; k < key_count_; ++k) {
    std::fill(sum.begin(), sum.end(), 0.0);
    add_translated(quadric(v1, k), Vec3{}, sum.data());
    add_translated(quadric(v0, k), offsets[k], sum.data());
    float* b = quadric(v1, k);
    std::copy(sum.begin(), sum.end(), b);
    if (moves.empty()) continue;
    std::fill(moved.begin(), moved.end(), 0.0);
    add_translated(b, moves[k], moved.data());  // around v1's new position
    std::copy(moved.begin(), moved.end(), b);
  }
}

size_t FieldTerm::floats_per_vertex_step() const {
  const size_t m = fields_.size();
  if (m == 0) return 0;
  if (form_ == FieldForm::kSpread) return 2 * m;
  return quadric_floats() + (form_ == FieldForm::kAttributes ? m : 0);
}

}  // namespace dynpm::simplification

namespace dynpm {

Result<std::vector<CostField>> cost_fields(const SimplifyOptions& options,
                                           const FrameSource& frames) {
  const bool valid_weight = std::isfinite(options.field_weight) && options.field_weight >= 0;
  if (!valid_weight) return Status::error("the field weight must be a number ≥ 0");
  std::vector<CostField> chosen;
  const std::vector<std::string> names = options.field_weights.empty() && options.field_weight == 0
                                             ? std::vector<std::string>{}
                                             : frames.field_names();
  if (options.field_weights.empty()) {
    for (size_t f = 0; f < names.size(); ++f) chosen.push_back({f, options.field_weight});
  }
  for (const SimplifyOptions::FieldWeight& fw : options.field_weights) {
    const auto it = std::find(names.begin(), names.end(), fw.name);
    if (it == names.end()) {
      std::string available;
      for (const std::string& name : names) {
        if (!available.empty()) available += ", ";
        available += name;
      }
      return Status::error(
          "unknown field '" + fw.name + "' (" +
          (names.empty() ? std::string("the input has no fields") : "the input has " + available) +
          ")");
    }
    const double weight = fw.weight.value_or(options.field_weight);
    if (!std::isfinite(weight) || weight < 0)
      return Status::error("field " + fw.name + ": the weight must be a number ≥ 0");
    chosen.push_back({size_t(it - names.begin()), weight});
  }
  std::erase_if(chosen, [](const CostField& c) { return c.weight == 0; });
  return chosen;
}

}  // namespace dynpm
