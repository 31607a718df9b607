// Selective refinement's costs (docs/selective.md): deriving the split dependencies from the
// records at load, and moving the active front — set_active() between two dependency-closed sets
// — by about 100 k splits and collapses. Median of repeated runs in wall time and in this
// thread's CPU time (_cpu), with the load average before and after (the machine is shared).
//   selective_bench MODEL.dpm [repeats] [view tolerance in pixels, default 0.005]
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "dynpm/lod.h"
#include "timing.h"

namespace {

using dynpm::bench::cpu_now;
using dynpm::bench::median;

double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double load_average() {
  double load[1] = {0};
  return getloadavg(load, 1) == 1 ? load[0] : -1;
}

struct Timing {
  std::vector<double> wall, cpu;
  template <class F>
  void run(F&& f) {
    const double w = wall_now(), c = cpu_now();
    f();
    wall.push_back(wall_now() - w);
    cpu.push_back(cpu_now() - c);
  }
  void print(const char* what, double scale, const char* unit) const {
    std::printf("%-44s %9.3f %s  (cpu %9.3f %s)\n", what, median(wall) * scale, unit,
                median(cpu) * scale, unit);
  }
};

// A view re-targeted (docs/selective.md "View-dependent"): the spheres once per step, then per
// camera the request (screen errors, their order, the closure) and set_active(), for a camera
// low over one corner looking at the model's centre and the same camera moved by a twentieth of
// the model, without and with a budget of 200 k vertices. `pixels`: the tolerance (the plate is
// gently bent, its split errors small: 0.005 px refines about half of it from there).
void view_retarget(const dynpm::ProgressiveMesh& m, const dynpm::RefineTargets& targets,
                   dynpm::SelectiveNavigator& nav, int repeats, double pixels) {
  using namespace dynpm;
  Timing spheres;
  for (int r = 0; r < repeats; ++r) spheres.run([&] { (void)split_spheres(m, 0); });
  std::array<double, 3> c, size;
  for (int k = 0; k < 3; ++k) {
    c[k] = (m.bbox_min[k] + m.bbox_max[k]) / 2;
    size[k] = m.bbox_max[k] - m.bbox_min[k];
  }
  const double across = std::max(size[0], size[1]);
  auto camera = [&](double shift, uint64_t budget) {
    RefineTarget v;
    v.kind = RefineTarget::Kind::kView;
    v.view.eye = {m.bbox_min[0] + (0.1 + shift) * across, m.bbox_min[1] + 0.1 * across,
                  c[2] + 0.06 * across};
    v.view.at = {c[0] + shift * across, c[1], c[2]};
    v.view.fov = 45;
    v.view.width = 1920;
    v.view.height = 1080;
    v.view.pixels = pixels;
    v.view.budget = budget;
    return v;
  };
  ElsewhereLevel one;
  one.ratio = 0.01;
  std::printf("view re-targeted (1920×1080, 45°, %g px, 1 %% elsewhere), camera moved by 1/20:\n",
              pixels);
  spheres.print("  spheres (once per step)", 1e3, "ms");
  for (uint64_t budget : {uint64_t{0}, uint64_t{200000}}) {
    const RefineTarget a = camera(0, budget), b = camera(0.05, budget);
    std::vector<uint8_t> first = targets.request(one, std::span(&a, 1), 0).value(), second;
    nav.set_active(first);
    const uint32_t at_first = nav.vertex_count();
    Timing request, there, back;
    uint32_t changed = 0;
    for (int r = 0; r < repeats; ++r) {
      request.run([&] { second = targets.request(one, std::span(&b, 1), 0).value(); });
      there.run([&] { nav.set_active(second); });
      changed = nav.last_applied() + nav.last_undone();
      back.run([&] { nav.set_active(first); });
    }
    nav.set_active(second);
    std::printf("  budget %s: %u → %u vertices, %u splits + collapses\n", budget ? "200 k" : "none",
                at_first, nav.vertex_count(), changed);
    request.print("    request (errors, order, closure)", 1e3, "ms");
    there.print("    set_active", 1e3, "ms");
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynpm;
  if (argc < 2) {
    std::fprintf(stderr, "usage: selective_bench MODEL.dpm [repeats] [view_pixels]\n");
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
  const double load_before = load_average();
  auto mesh = read_dpm(argv[1]);
  if (!mesh) {
    std::fprintf(stderr, "%s\n", mesh.message().c_str());
    return 1;
  }
  const ProgressiveMesh& m = *mesh;
  const uint32_t n = m.split_count();
  std::printf("%s: %u vertices, %u splits, %zu steps\n", argv[1], m.vertex_count(), n,
              m.step_count());

  Timing derive;
  SplitDependencies deps;
  for (int r = 0; r < repeats; ++r) derive.run([&] { deps = derive_split_dependencies(m); });
  std::printf("dependencies: mean %.2f, max %zu per split (%zu in all, %.1f B/vertex in memory)\n",
              deps.mean_count(), deps.max_count(), deps.deps.size(),
              4.0 * double(deps.deps.size() + deps.dep_start.size()) / m.vertex_count());
  derive.print("derivation, per 1 M splits", 1e3 * 1e6 / n, "ms");

  // The front moved in stream order: prefix(k) ↔ prefix(k + 100 k).
  const uint32_t step = std::min<uint32_t>(100000, n / 2), k = n / 4;
  std::vector<uint8_t> a(n, 0), b(n, 0);
  std::fill_n(a.begin(), k, uint8_t{1});
  std::fill_n(b.begin(), k + step, uint8_t{1});
  SelectiveNavigator nav(m, deps);
  nav.set_active(a);
  Timing up, down;
  for (int r = 0; r < repeats; ++r) {
    up.run([&] { nav.set_active(b); });
    down.run([&] { nav.set_active(a); });
  }
  std::printf("prefix %u ↔ %u: %u splits / collapses each way\n", k, k + step, step);
  up.print("  refine (splits)", 1e3, "ms");
  down.print("  coarsen (collapses)", 1e3, "ms");

  // A region moved: a slab a tenth of the model wide, at 5 % elsewhere, shifted by its width.
  const RefineTargets targets(m, deps);
  ElsewhereLevel five;
  five.ratio = 0.05;
  int axis = 0;
  for (int c = 1; c < 3; ++c)
    if (m.bbox_max[c] - m.bbox_min[c] > m.bbox_max[axis] - m.bbox_min[axis]) axis = c;
  const double lo = m.bbox_min[axis], len = m.bbox_max[axis] - lo;
  auto slab = [&](double from) {
    RefineTarget box;
    for (int c = 0; c < 3; ++c) {
      box.box[c] = m.bbox_min[c] - 1;
      box.box[c + 3] = m.bbox_max[c] + 1;
    }
    box.box[axis] = lo + from * len;
    box.box[axis + 3] = lo + (from + 0.1) * len;
    return box;
  };
  Timing request;
  std::vector<uint8_t> first, second;
  const RefineTarget one = slab(0.3), two = slab(0.4);
  for (int r = 0; r < repeats; ++r)
    request.run([&] { first = targets.request(five, std::span(&one, 1), 0).value(); });
  second = targets.request(five, std::span(&two, 1), 0).value();
  Timing there, back;
  nav.set_active(first);
  const uint32_t at_first = nav.vertex_count();
  uint32_t changed = 0;
  for (int r = 0; r < repeats; ++r) {
    there.run([&] { nav.set_active(second); });
    changed = nav.last_applied() + nav.last_undone();
    back.run([&] { nav.set_active(first); });
  }
  std::printf(
      "slab moved by its width: %u → %u vertices, %u splits + collapses\n", at_first,
      [&] {
        nav.set_active(second);
        return nav.vertex_count();
      }(),
      changed);
  request.print("  request (select + closure)", 1e3, "ms");
  there.print("  set_active there", 1e3, "ms");
  back.print("  set_active back", 1e3, "ms");
  view_retarget(m, targets, nav, repeats, argc > 3 ? std::atof(argv[3]) : 0.005);
  std::printf("load average %.2f before, %.2f after; %d runs, medians\n", load_before,
              load_average(), repeats);
  return 0;
}
