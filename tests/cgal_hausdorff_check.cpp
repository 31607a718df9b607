// dynpm's Hausdorff distance against CGAL's, on fixed pairs of real meshes: the Stanford bunny
// against a jittered copy and against a copy decimated by vertex clustering, and the CalculiX
// crash box's first step against its last.
//
// CGAL::Polygon_mesh_processing::approximate_Hausdorff_distance(tm1, tm2) is one-sided: the
// largest distance from samples of tm1 (its own random sampling of vertices, edges and faces)
// to tm2. Both sides are sampled densely (≈ 1 M points). CGAL's bounded_error_Hausdorff_distance
// (a certified estimate within a given error bound) is the reference: each direction of dynpm's
// result is within 2% of it, and dynpm's sampled maximum can only be below the true value.
// CGAL's sampled estimate is a third opinion, met from below: dynpm is not more than 2% short.
//
// Quads are given to CGAL as their star triangulation (four triangles through the centroid),
// which is the surface dynpm measures.
//
// CGAL (Debian libcgal-dev, header-only, with GMP and MPFR) is a test-only dependency. Without
// it this file builds a single test that skips, or fails where DYNPM_REQUIRE_THIRD_PARTY=1.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "dynpm/eval.h"
#include "dynpm/io.h"
#include "third_party.h"

#if DYNPM_HAVE_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace dynpm {
namespace {

#if !DYNPM_HAVE_CGAL

TEST(EvalCgal, HausdorffAgreesWithCgal) {
  if (test::third_party_required()) FAIL() << "CGAL (libcgal-dev) was not found at configure time";
  GTEST_SKIP() << "CGAL (libcgal-dev) was not found at configure time";
}

#else

namespace pmp = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;

struct Mesh {
  Topology topology;
  std::vector<float> positions;
};

Mesh read(const std::string& path) {
  auto a = read_mesh(path);
  EXPECT_TRUE(a.ok()) << a.message();
  if (!a.ok()) return {};
  return {a->topology, std::vector<float>(a->frames.step(0).begin(), a->frames.step(0).end())};
}

// The surface dynpm measures, as a CGAL mesh: triangles as they are, quads as four triangles
// through their centroid. orient_polygon_soup() may duplicate a non-manifold vertex so that
// Surface_mesh can hold the faces; the geometry is the same.
CgalMesh to_cgal(const Mesh& m) {
  std::vector<Kernel::Point_3> points;
  std::map<std::array<float, 3>, size_t> index_of;  // corners at one place become one point
  std::vector<std::array<size_t, 3> > triangles;
  for (const SurfaceTriangle& t : surface_triangles(m.topology, m.positions)) {
    std::array<size_t, 3> corners;
    for (int i = 0; i < 3; ++i) {
      const std::array<float, 3>& p = i == 0 ? t.a : i == 1 ? t.b : t.c;
      auto [it, added] = index_of.emplace(p, points.size());
      if (added) points.emplace_back(p[0], p[1], p[2]);
      corners[i] = it->second;
    }
    triangles.push_back(corners);
  }
  pmp::orient_polygon_soup(points, triangles);
  CgalMesh mesh;
  pmp::polygon_soup_to_polygon_mesh(points, triangles, mesh);
  return mesh;
}

// A copy moved by up to `amount` per coordinate, with a fixed pseudo-random pattern.
Mesh jittered(const Mesh& m, float amount) {
  Mesh j = m;
  uint64_t state = 12345;
  for (float& x : j.positions) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    x += amount * (float((state >> 40) & 0xffff) / 32767.5f - 1.0f);
  }
  return j;
}

// Decimation by vertex clustering (Rossignac and Borrel 1993): vertices in one grid cell of
// size `cell` merge into their mean; faces that lose a corner to a merge disappear.
Mesh clustered(const Mesh& m, float cell) {
  std::map<std::array<int64_t, 3>, uint32_t> cluster_of_cell;
  std::vector<uint32_t> cluster(m.topology.vertex_count);
  std::vector<std::array<double, 4> > sum;  // x, y, z, count
  for (uint32_t v = 0; v < m.topology.vertex_count; ++v) {
    std::array<int64_t, 3> key;
    for (int k = 0; k < 3; ++k) key[k] = int64_t(std::floor(m.positions[3 * v + k] / cell));
    auto [it, added] = cluster_of_cell.emplace(key, uint32_t(sum.size()));
    if (added) sum.push_back({0, 0, 0, 0});
    cluster[v] = it->second;
    for (int k = 0; k < 3; ++k) sum[it->second][k] += m.positions[3 * v + k];
    sum[it->second][3] += 1;
  }
  Mesh c;
  c.topology = Topology::with_vertices(uint32_t(sum.size()));
  for (const auto& s : sum)
    for (int k = 0; k < 3; ++k) c.positions.push_back(float(s[k] / s[3]));
  for (const Face& f : m.topology.faces) {
    const uint32_t a = cluster[f.v[0]], b = cluster[f.v[1]], d = cluster[f.v[2]];
    if (a != b && b != d && d != a) c.topology.add_triangle(a, b, d);
  }
  return c;
}

double diagonal(const Mesh& m) {
  BoundingBox box;
  box.extend(m.positions);
  return box.diagonal();
}

constexpr uint64_t kSamples = 1'000'000;

void expect_agreement(const std::string& name, const Mesh& a, const Mesh& b) {
  ASSERT_FALSE(a.topology.faces.empty());
  ASSERT_FALSE(b.topology.faces.empty());
  HausdorffOptions options;
  options.face_samples = kSamples;
  options.seed = 2024;
  auto ours = hausdorff(a.topology, a.positions, b.topology, b.positions, options);
  ASSERT_TRUE(ours.ok()) << ours.message();

  const CgalMesh ca = to_cgal(a), cb = to_cgal(b);
  auto cgal_one_sided = [&](const CgalMesh& from, const CgalMesh& to) {
    return pmp::approximate_Hausdorff_distance<CGAL::Sequential_tag>(
        from, to,
        CGAL::parameters::number_of_points_on_faces(kSamples)
            .number_of_points_on_edges(kSamples / 4)
            .random_seed(7));
  };
  const double error_bound = 1e-4 * diagonal(a);
  auto cgal_bounded = [&](const CgalMesh& from, const CgalMesh& to) {
    return pmp::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(from, to, error_bound);
  };
  const double cgal_ab = cgal_one_sided(ca, cb), cgal_ba = cgal_one_sided(cb, ca);
  const double bounded_ab = cgal_bounded(ca, cb), bounded_ba = cgal_bounded(cb, ca);
  const double d = ours->diagonal;
  std::printf("%-28s dynpm A→B %.6g (%.4f %%)  CGAL approx %.6g  CGAL bounded %.6g\n", name.c_str(),
              ours->a_to_b.max, 100 * ours->a_to_b.max / d, cgal_ab, bounded_ab);
  std::printf("%-28s dynpm B→A %.6g (%.4f %%)  CGAL approx %.6g  CGAL bounded %.6g\n", name.c_str(),
              ours->b_to_a.max, 100 * ours->b_to_a.max / d, cgal_ba, bounded_ba);
  for (auto [label, mine, approx, bounded] :
       {std::tuple{"A→B", ours->a_to_b.max, cgal_ab, bounded_ab},
        std::tuple{"B→A", ours->b_to_a.max, cgal_ba, bounded_ba}}) {
    ASSERT_GT(approx, 0) << name << " " << label;
    // CGAL's random sampling is a lower bound whose draw depends on its memory layout (the
    // sanitizer build got 0.3997 where the plain one got 0.4083 for the certified 0.4089), so
    // against it dynpm must only not fall more than 2% short; the certified value is two-sided.
    EXPECT_GE(mine, 0.98 * approx) << name << " " << label << " vs approximate";
    EXPECT_NEAR(mine, bounded, 0.02 * bounded) << name << " " << label << " vs bounded-error";
    // A sampled maximum is a lower bound of the true one-sided distance.
    EXPECT_LE(mine, bounded + error_bound + 1e-9 * d) << name << " " << label;
  }
}

bool have_data() { return std::filesystem::exists(DYNPM_SHARED_DATA "/meshes/bunny.obj"); }

TEST(EvalCgal, BunnyAgainstAJitteredCopy) {
  if (!have_data()) GTEST_SKIP() << "no ../shared/data";
  const Mesh bunny = read(DYNPM_SHARED_DATA "/meshes/bunny.obj");
  expect_agreement("bunny / jittered", bunny, jittered(bunny, float(0.004 * diagonal(bunny))));
}

TEST(EvalCgal, BunnyAgainstADecimatedCopy) {
  if (!have_data()) GTEST_SKIP() << "no ../shared/data";
  const Mesh bunny = read(DYNPM_SHARED_DATA "/meshes/bunny.obj");
  const Mesh coarse = clustered(bunny, float(diagonal(bunny) / 20));
  std::printf("bunny: %zu triangles, clustered copy: %zu\n", bunny.topology.faces.size(),
              coarse.topology.faces.size());
  EXPECT_LT(coarse.topology.faces.size(), bunny.topology.faces.size() / 3);
  expect_agreement("bunny / clustered", bunny, coarse);
}

TEST(EvalCgal, CrashBoxFirstAgainstLastStep) {
  const std::string dir = DYNPM_SHARED_DATA "/crashbox-s/obj/";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no ../shared/data";
  expect_agreement("crash box step 0 / 25", read(dir + "frame_000.obj"),
                   read(dir + "frame_025.obj"));
}

#endif

}  // namespace
}  // namespace dynpm
