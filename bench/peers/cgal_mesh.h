// Triangle soup -> CGAL::Surface_mesh, shared by peer_cgal and hausdorff_cgal.
//
// Unreferenced vertices are dropped. If the soup is not a valid polygon mesh (non-manifold
// edges or vertices, inconsistent orientation), it is first made one with
// Polygon_mesh_processing::orient_polygon_soup, which duplicates the offending vertices
// (geometry unchanged); "duplicated" reports how many points that added.
#pragma once

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

#include "obj_io.h"

namespace peers {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;

struct SoupInfo {
  bool was_polygon_mesh = true;
  std::size_t duplicated = 0;  // points added by orient_polygon_soup
};

inline SoupInfo soup_to_surface_mesh(TriSoup soup, SurfaceMesh& mesh) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  compact(soup.V, soup.F);
  std::vector<Point3> pts;
  pts.reserve(soup.V.size());
  for (const Vec3& v : soup.V) pts.emplace_back(v[0], v[1], v[2]);
  std::vector<std::vector<std::size_t>> polys;
  polys.reserve(soup.F.size());
  for (const Tri& t : soup.F) polys.push_back({t[0], t[1], t[2]});
  SoupInfo info;
  if (!PMP::is_polygon_soup_a_polygon_mesh(polys)) {
    info.was_polygon_mesh = false;
    const std::size_t before = pts.size();
    PMP::orient_polygon_soup(pts, polys);
    info.duplicated = pts.size() - before;
  }
  mesh.clear();
  PMP::polygon_soup_to_polygon_mesh(pts, polys, mesh);
  return info;
}

inline void surface_mesh_to_arrays(const SurfaceMesh& mesh, std::vector<Vec3>& V,
                                   std::vector<Tri>& F) {
  V.clear();
  F.clear();
  std::vector<std::uint32_t> id(mesh.num_vertices(), UINT32_MAX);  // indexed by vertex index
  for (auto v : mesh.vertices()) {
    id[v.idx()] = static_cast<std::uint32_t>(V.size());
    const Point3& p = mesh.point(v);
    V.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : mesh.faces()) {
    Tri t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) t[k] = id[v.idx()];
      ++k;
    }
    F.push_back(t);
  }
  compact(V, F);
}

}  // namespace peers
