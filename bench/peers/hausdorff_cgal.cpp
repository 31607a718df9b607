// Two-sided Hausdorff distance between two OBJ meshes, CGAL-based stand-in for
// `dynpm hausdorff A B --json` (same JSON key: hausdorff_pct).
//
//   hausdorff_cgal A.obj B.obj [--json] [--samples N] [--seed S]
//
// d(A,B) = CGAL::Polygon_mesh_processing::approximate_Hausdorff_distance (sequential) from a
// sampling of A to the surface of B, and the same from B to A; the result is the max of both,
// also given in percent of the bounding-box diagonal of A (A = the reference/input mesh).
// Fixed, dense sampling on each side: all vertices + N random points on the faces (uniform by
// area) + N/4 random points on the edges (uniform by length), with a fixed seed (also given to
// CGAL's default generator), so repeated runs agree exactly. N = 500,000 by default.
// Quads are split along their shorter diagonal (obj_io.h).
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Random.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "cgal_mesh.h"
#include "driver_common.h"
#include "obj_io.h"

using namespace peers;
namespace PMP = CGAL::Polygon_mesh_processing;

int main(int argc, char** argv) {
  const char* kTool = "hausdorff_cgal";
  std::string a_path, b_path;
  std::size_t samples = 500000;
  unsigned seed = 1;
  for (int i = 1; i < argc; ++i) {
    std::string s = argv[i];
    if (s == "--json") continue;  // JSON is the only output format
    if (s == "--samples" && i + 1 < argc)
      samples = std::strtoull(argv[++i], nullptr, 10);
    else if (s == "--seed" && i + 1 < argc)
      seed = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    else if (!s.empty() && s[0] != '-' && a_path.empty())
      a_path = s;
    else if (!s.empty() && s[0] != '-' && b_path.empty())
      b_path = s;
    else {
      std::fprintf(stderr, "usage: %s A.obj B.obj [--json] [--samples N] [--seed S]\n", kTool);
      return 2;
    }
  }
  if (a_path.empty() || b_path.empty() || samples == 0) {
    std::fprintf(stderr, "usage: %s A.obj B.obj [--json] [--samples N] [--seed S]\n", kTool);
    return 2;
  }

  TriSoup sa, sb;
  if (auto err = read_obj(a_path, sa); !err.empty()) die(kTool, err);
  if (auto err = read_obj(b_path, sb); !err.empty()) die(kTool, err);
  SurfaceMesh a, b;
  soup_to_surface_mesh(sa, a);
  soup_to_surface_mesh(sb, b);

  Timer tm;
  auto np = [&](const SurfaceMesh&) {
    return CGAL::parameters::number_of_points_on_faces(samples)
        .number_of_points_on_edges(samples / 4 + 1)
        .do_sample_vertices(true)
        .do_sample_edges(true)
        .random_seed(seed);
  };
  // random_seed seeds the face sampling only; the edge sampling (and spatial_sort) draw from
  // CGAL's default generator, which is seeded from the clock: reseed it before each side.
  CGAL::get_default_random() = CGAL::Random(seed);
  const double ab = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(a, b, np(a));
  CGAL::get_default_random() = CGAL::Random(seed);
  const double ba = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(b, a, np(b));
  const double secs = tm.seconds();

  const CGAL::Bbox_3 bb = PMP::bbox(a);
  const double diag = std::sqrt((bb.xmax() - bb.xmin()) * (bb.xmax() - bb.xmin()) +
                                (bb.ymax() - bb.ymin()) * (bb.ymax() - bb.ymin()) +
                                (bb.zmax() - bb.zmin()) * (bb.zmax() - bb.zmin()));
  const double h = std::max(ab, ba);

  Json j;
  j.add("a", a_path)
      .add("b", b_path)
      .add("hausdorff", h)
      .add("hausdorff_pct", diag > 0 ? 100.0 * h / diag : 0.0)
      .add("a_to_b", ab)
      .add("b_to_a", ba)
      .add("bbox_diag", diag)
      .add("samples_per_side", samples)
      .add("seed", static_cast<std::size_t>(seed))
      .add("seconds", secs)
      .add("tool", "hausdorff_cgal (CGAL " CGAL_VERSION_STR ")");
  j.print();
  return 0;
}
