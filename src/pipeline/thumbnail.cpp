// The thumbnail of a model (dynpm/pipeline.h, render_thumbnail()): a small software rasterizer —
// an orthographic camera, a z-buffer, one colour per facet — drawn at twice the size and averaged
// down, then written as PNG (png.h). The view matches the viewer's first one: its up axis rule
// (viewer/src/orientation.js upAxisOf), its Iso direction, its part colours (part_view.js).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <type_traits>
#include <vector>

#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "png.h"
#include "thumbnail_level.h"

namespace dynpm {
namespace {

using V3 = std::array<double, 3>;
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 normalized(const V3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? V3{a[0] / n, a[1] / n, a[2] / n} : V3{0, 0, 0};
}

constexpr std::array<uint8_t, 3> kBackground = {0xee, 0xf0, 0xf3};  // the viewer's
constexpr int kSupersample = 2;
// The headlight's brightness in this many steps: facets of nearly one orientation get one
// colour, so the PNG has fewer edges to tell (16: 18–33 % fewer bytes on the crash boxes and the
// hat rail, 8 lets flat panels fall into streaks; docs/BENCHMARKS.md "Thumbnails in 16 shades").
constexpr double kShadeLevels = 16;

// The viewer's rule: the axis (y or z) the base mesh moves along most from the first step to the
// last, if twice as much as along the other; else the one the box is thinner along.
bool z_is_up(const ProgressiveMesh& mesh) {
  const size_t n = size_t{mesh.base_vertex_count} * 3;
  if (mesh.steps_read > 1 && n > 0) {
    const std::vector<float>& first = mesh.positions.front();
    const std::vector<float>& last = mesh.positions[mesh.steps_read - 1];
    double moved[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i) moved[i % 3] += std::abs(last[i] - first[i]);
    if (moved[2] >= 2 * moved[1] && moved[2] > 0) return true;
    if (moved[1] >= 2 * moved[2] && moved[1] > 0) return false;
  }
  return mesh.bbox_max[2] - mesh.bbox_min[2] < mesh.bbox_max[1] - mesh.bbox_min[1];
}

// The viewer's part colour of the k-th part (ascending id): hues by the golden angle.
std::array<double, 3> part_colour(size_t k) {
  const double h = std::fmod(0.58 + static_cast<double>(k) * 0.618033988749895, 1.0);
  const double s = 0.9, l = 0.5;
  const double q = l < 0.5 ? l * (1 + s) : l + s - l * s, p = 2 * l - q;
  auto channel = [&](double t) {
    t = t < 0 ? t + 1 : t > 1 ? t - 1 : t;
    if (t < 1.0 / 6) return p + (q - p) * 6 * t;
    if (t < 0.5) return q;
    if (t < 2.0 / 3) return p + (q - p) * (2.0 / 3 - t) * 6;
    return p;
  };
  return {channel(h + 1.0 / 3), channel(h), channel(h - 1.0 / 3)};
}

// A z-buffered image of flat-coloured triangles in screen coordinates (x right, y down).
class Raster {
 public:
  Raster(uint32_t width, uint32_t height)
      : w_(width),
        h_(height),
        depth_(size_t{width} * height, std::numeric_limits<double>::max()),
        rgb_(size_t{width} * height * 3) {
    for (size_t i = 0; i < rgb_.size(); ++i) rgb_[i] = kBackground[i % 3];
  }
  void triangle(const V3& a, const V3& b, const V3& c, const std::array<uint8_t, 3>& colour) {
    const double area = edge(a, b, c[0], c[1]);
    if (area == 0 || !std::isfinite(area)) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
    const int x1 = std::min<int>(static_cast<int>(w_) - 1,
                                 static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
    const int y1 = std::min<int>(static_cast<int>(h_) - 1,
                                 static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double wa = edge(b, c, px, py) / area, wb = edge(c, a, px, py) / area,
                     wc = edge(a, b, px, py) / area;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double z = wa * a[2] + wb * b[2] + wc * c[2];
        const size_t i = size_t(y) * w_ + size_t(x);
        if (z >= depth_[i]) continue;
        depth_[i] = z;
        for (int k = 0; k < 3; ++k) rgb_[3 * i + k] = colour[k];
      }
  }
  // Each block of f × f pixels averaged into one.
  std::vector<uint8_t> reduced(int f) const {
    const uint32_t w = w_ / f, h = h_ / f;
    std::vector<uint8_t> out(size_t{w} * h * 3);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        for (int k = 0; k < 3; ++k) {
          unsigned sum = 0;
          for (int dy = 0; dy < f; ++dy)
            for (int dx = 0; dx < f; ++dx)
              sum += rgb_[3 * ((size_t(y) * f + dy) * w_ + size_t(x) * f + dx) + k];
          out[3 * (size_t(y) * w + x) + k] = static_cast<uint8_t>(sum / unsigned(f * f));
        }
    return out;
  }

 private:
  static double edge(const V3& a, const V3& b, double x, double y) {
    return (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
  }
  uint32_t w_, h_;
  std::vector<double> depth_;
  std::vector<uint8_t> rgb_;
};

}  // namespace

DpmReadLimits thumbnail_read_limits(const ThumbnailOptions& options) {
  DpmReadLimits limits;
  limits.fields = false;
  limits.ratio = options.ratio;
  return limits;
}

std::string render_thumbnail(const ProgressiveMesh& mesh, const ThumbnailOptions& options) {
  const uint32_t W = options.width * kSupersample, H = options.height * kSupersample;
  Raster raster(W, H);
  if (mesh.steps_read == 0)
    return pipeline::encode_png(raster.reduced(kSupersample), options.width, options.height);
  Navigator nav(mesh);
  nav.set_level(mesh.split_count());
  std::vector<float> xyz(size_t{nav.vertex_count()} * 3);
  nav.positions(static_cast<double>(mesh.steps_read - 1), xyz);

  // The camera: looking from +x, −y, +z on a z-up model (+x, +y, +z on a y-up one).
  const bool z_up = z_is_up(mesh);
  const V3 up = z_up ? V3{0, 0, 1} : V3{0, 1, 0};
  const V3 forward = normalized(z_up ? V3{-1, 1, -1} : V3{-1, -1, -1});
  const V3 right = normalized(cross(forward, up)), screen_up = cross(right, forward);
  // The viewer's headlight, in camera space (0.3, 0.5, 1): above and right of the eye.
  const V3 light = normalized({0.3 * right[0] + 0.5 * screen_up[0] - forward[0],
                               0.3 * right[1] + 0.5 * screen_up[1] - forward[1],
                               0.3 * right[2] + 0.5 * screen_up[2] - forward[2]});
  auto point = [&](uint32_t v) { return V3{xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; };

  // The drawn vertices' extent on the screen, fitted with a margin.
  double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  double hi[2] = {-lo[0], -lo[1]};
  for (const Face& f : nav.faces())
    for (int c = 0; c < f.degree(); ++c) {
      const V3 p = point(f.v[c]);
      const double s[2] = {dot(p, right), dot(p, screen_up)};
      for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], s[k]), hi[k] = std::max(hi[k], s[k]);
    }
  if (!(hi[0] >= lo[0]) || !std::isfinite(hi[0] - lo[0]) || !std::isfinite(hi[1] - lo[1]))
    return pipeline::encode_png(raster.reduced(kSupersample), options.width, options.height);
  const double margin = 0.06;
  const double scale = std::min((1 - 2 * margin) * W / std::max(hi[0] - lo[0], 1e-30),
                                (1 - 2 * margin) * H / std::max(hi[1] - lo[1], 1e-30));
  const double cx = (lo[0] + hi[0]) / 2, cy = (lo[1] + hi[1]) / 2;
  auto screen = [&](const V3& p) {
    return V3{W / 2.0 + (dot(p, right) - cx) * scale, H / 2.0 - (dot(p, screen_up) - cy) * scale,
              dot(p, forward)};
  };

  const std::set<int32_t> ids(mesh.part_ids.begin(), mesh.part_ids.end());
  const std::vector<int32_t> ranked(ids.begin(), ids.end());
  const std::span<const Face> faces = nav.faces();
  for (size_t f = 0; f < faces.size(); ++f) {
    const Face& face = faces[f];
    const int n = face.degree();
    V3 corner[4];
    for (int c = 0; c < n; ++c) corner[c] = point(face.v[c]);
    // A quad's normal from its diagonals: its mean plane's.
    const V3 normal =
        normalized(n == 4 ? cross(sub(corner[2], corner[0]), sub(corner[3], corner[1]))
                          : cross(sub(corner[1], corner[0]), sub(corner[2], corner[0])));
    const double lit = std::round(std::abs(dot(normal, light)) * kShadeLevels) / kShadeLevels;
    const double shade = 0.3 + 0.7 * lit;  // both sides lit
    const size_t rank =
        f < mesh.part_ids.size()
            ? static_cast<size_t>(std::lower_bound(ranked.begin(), ranked.end(), mesh.part_ids[f]) -
                                  ranked.begin())
            : 0;
    const std::array<double, 3> base = part_colour(rank);
    std::array<uint8_t, 3> colour;
    for (int k = 0; k < 3; ++k)
      colour[k] = static_cast<uint8_t>(std::clamp(base[k] * shade * 255 + 0.5, 0.0, 255.0));
    V3 s[4];
    for (int c = 0; c < n; ++c) s[c] = screen(corner[c]);
    raster.triangle(s[0], s[1], s[2], colour);
    if (n == 4) raster.triangle(s[0], s[2], s[3], colour);
  }
  return pipeline::encode_png(raster.reduced(kSupersample), options.width, options.height);
}

ProgressiveMesh thumbnail_level(const ProgressiveMesh& mesh, const ThumbnailOptions& options) {
  // The level a reader of the file stops at.
  const uint32_t splits =
      std::min(splits_for_limits(mesh, thumbnail_read_limits(options)), mesh.split_count());
  ProgressiveMesh level;
  level.full_vertex_count = mesh.full_vertex_count;
  level.full_face_count = mesh.full_face_count;
  level.full_split_count = mesh.full_split_count;
  level.base_vertex_count = mesh.base_vertex_count;
  level.base_face_count = mesh.base_face_count;
  level.bbox_min = mesh.bbox_min, level.bbox_max = mesh.bbox_max;
  level.base_faces = mesh.base_faces;
  auto prefix = [](const auto& values, size_t count) {
    return std::remove_cvref_t<decltype(values)>(values.begin(), values.begin() + count);
  };
  level.parent = prefix(mesh.parent, splits);
  level.error = prefix(mesh.error, splits);
  level.wing_start = prefix(mesh.wing_start, size_t{splits} + 1);
  level.wings = prefix(mesh.wings, level.wing_start.back());
  level.moved_start = prefix(mesh.moved_start, size_t{splits} + 1);
  level.moved_faces = prefix(mesh.moved_faces, level.moved_start.back());
  level.part_ids = prefix(mesh.part_ids, level.face_count_after(splits));
  level.complete = false, level.limited = true;
  return level;
}

void keep_thumbnail_step(ProgressiveMesh& level, size_t t, size_t steps,
                         std::span<const float> xyz) {
  if (!thumbnail_keeps_step(t, steps)) return;
  level.positions.emplace_back(xyz.begin(), xyz.begin() + size_t{level.vertex_count()} * 3);
  level.times.push_back(static_cast<double>(t));
  level.steps_read = level.times.size();
}

Result<std::string> add_thumbnail(std::string_view dpm_bytes, const std::string& name,
                                  const ThumbnailOptions& options) {
  auto mesh = decode_dpm(dpm_bytes, name, thumbnail_read_limits(options));
  if (!mesh) return mesh.status();
  return with_thumbnail(dpm_bytes, render_thumbnail(*mesh, options), name);
}

}  // namespace dynpm
