// The view-dependent request (docs/selective.md "View-dependent"): per split a bounding sphere of
// its final descendants at the step, bottom-up over the vertex hierarchy as in Hoppe's VDPM
// (1997), and its screen-space error for a camera; a split is wanted when the error exceeds the
// tolerance and the sphere meets the frustum. viewer/src/dpm/view_target.js does the same
// arithmetic in the same order, so both decoders want the same splits.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dynpm/lod.h"
#include "step_position.h"

namespace dynpm {
namespace {

using Vec = std::array<double, 3>;

Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec normalized(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}
// a · s + b
Vec scaled_plus(const Vec& a, double s, const Vec& b) {
  return {a[0] * s + b[0], a[1] * s + b[1], a[2] * s + b[2]};
}
Vec negated(const Vec& a) { return {-a[0], -a[1], -a[2]}; }

// The smallest sphere around spheres a and b (x, y, z, r each), into out.
void enclose(const float* a, const float* b, float* out) {
  const double dx = double(b[0]) - a[0], dy = double(b[1]) - a[1], dz = double(b[2]) - a[2];
  const double d = std::sqrt(dx * dx + dy * dy + dz * dz), ra = a[3], rb = b[3];
  if (d + rb <= ra) return (void)std::copy_n(a, 4, out);
  if (d + ra <= rb) return (void)std::copy_n(b, 4, out);
  const double r = (d + ra + rb) / 2, s = (r - ra) / d;
  out[0] = static_cast<float>(a[0] + dx * s);
  out[1] = static_cast<float>(a[1] + dy * s);
  out[2] = static_cast<float>(a[2] + dz * s);
  out[3] = static_cast<float>(r);
}

}  // namespace

std::vector<float> split_spheres(const ProgressiveMesh& mesh, double t) {
  const uint32_t n = mesh.vertex_count(), b = mesh.base_vertex_count;
  // Per vertex, the sphere of itself and what the splits after the current one made of it.
  std::vector<float> vertex(size_t{n} * 4, 0.0f), out(size_t{mesh.split_count()} * 4);
  for (uint32_t v = 0; v < n; ++v) {
    const auto p = position_at(mesh, v, t);
    for (int c = 0; c < 3; ++c) vertex[size_t{v} * 4 + c] = static_cast<float>(p[c]);
  }
  // Split i turns its parent into the parent and v0: its descendants are the parent's after i
  // (splits of the parent later than i, already merged in) and v0's (all later than i).
  for (uint32_t i = mesh.split_count(); i-- > 0;) {
    float* parent = &vertex[size_t{mesh.parent[i]} * 4];
    enclose(parent, &vertex[size_t{b + i} * 4], &out[size_t{i} * 4]);
    std::copy_n(&out[size_t{i} * 4], 4, parent);
  }
  return out;
}

ViewFrustum::ViewFrustum(const ViewRequest& view) : eye_(view.eye) {
  const Vec f = normalized(minus(view.at, view.eye));
  const Vec right = normalized(cross(f, view.up)), up = cross(right, f);
  const double tv = std::tan(view.fov * std::numbers::pi / 360);
  const double width = view.width > 0 ? view.width : view.height;
  const double th = tv * width / view.height;
  // A point q (from the eye) is inside when q·f ≥ 0, |q·up| ≤ tv q·f and |q·right| ≤ th q·f.
  inward_ = {f, normalized(scaled_plus(f, tv, negated(up))), normalized(scaled_plus(f, tv, up)),
             normalized(scaled_plus(f, th, negated(right))), normalized(scaled_plus(f, th, right))};
  scale_ = view.height / (2 * tv);
}

double ViewFrustum::screen_error(const float* sphere, double error) const {
  const Vec q = {sphere[0] - eye_[0], sphere[1] - eye_[1], sphere[2] - eye_[2]};
  const double r = sphere[3];
  for (const Vec& n : inward_)
    if (dot(q, n) < -r) return -1;
  const double distance = std::sqrt(dot(q, q)) - r;
  if (distance <= 0) return error > 0 ? std::numeric_limits<double>::infinity() : 0;
  return error / distance * scale_;
}

std::vector<std::pair<double, uint32_t>> RefineTargets::view_candidates(const ViewRequest& view,
                                                                        double t) const {
  const ProgressiveMesh& m = *mesh_;
  if (spheres_step_ != t || spheres_.empty()) {
    spheres_ = split_spheres(m, t);
    spheres_step_ = t;
  }
  const ViewFrustum frustum(view);
  std::vector<std::pair<double, uint32_t>> out;
  // A split's error: the level's before it (errors never increase along the stream), what the
  // mesh keeps while it is not applied.
  for (uint32_t i = 0; i < m.split_count(); ++i) {
    const double e = frustum.screen_error(&spheres_[size_t{i} * 4], m.level_error(i));
    if (e > view.pixels) out.emplace_back(e, i);
  }
  return out;
}

std::vector<std::pair<double, uint32_t>> RefineTargets::view_splits(const ViewRequest& view,
                                                                    double t) const {
  auto out = view_candidates(view, t);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return before(a, b); });
  return out;
}

void RefineTargets::add_view(const ViewRequest& view, double t,
                             std::vector<uint8_t>& splits) const {
  auto wanted = view_candidates(view, t);
  if (!view.budget) {
    for (const auto& [error, i] : wanted) splits[i] = 1;
    close_under_dependencies(*deps_, splits);
    return;
  }
  uint64_t vertices = mesh_->base_vertex_count;
  for (uint8_t s : splits) vertices += s;
  // By decreasing screen error: a heap, popped only as far as the budget goes.
  auto lower = [](const auto& a, const auto& b) { return before(b, a); };
  std::make_heap(wanted.begin(), wanted.end(), lower);
  std::vector<uint32_t> stack;
  while (!wanted.empty() && vertices < view.budget) {
    std::pop_heap(wanted.begin(), wanted.end(), lower);
    vertices += add_with_dependencies(*deps_, splits, wanted.back().second, stack);
    wanted.pop_back();
  }
}

}  // namespace dynpm
