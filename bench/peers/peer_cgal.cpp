// Peer driver: CGAL (Debian libcgal-dev) Surface_mesh_simplification::edge_collapse.
//
// Built twice (CMakeLists.txt):
//   peer_cgal     Garland-Heckbert: GarlandHeckbert_plane_policies (classic plane quadrics,
//                 default discontinuity multiplier 100) as cost and placement;
//   peer_cgal_lt  (PEER_CGAL_LT) the default Lindstrom-Turk cost and placement.
// Both: CGAL::Surface_mesh over Simple_cartesian<double>, no filter, stop when the mesh has at
// most the target number of vertices (a custom stop predicate reading number_of_vertices();
// every collapse removes one vertex), then collect_garbage().
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/version.h>
#ifndef PEER_CGAL_LT
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#endif

#include "cgal_mesh.h"
#include "driver_common.h"
#include "obj_io.h"

using namespace peers;
namespace SMS = CGAL::Surface_mesh_simplification;

namespace {
#ifdef PEER_CGAL_LT
const char* kPeer = "cgal-lt";
#else
const char* kPeer = "cgal";
#endif

// Stops as soon as the mesh has at most `target` vertices.
struct VertexCountStop {
  const SurfaceMesh* mesh;
  std::size_t target;
  template <typename F, typename Profile>
  bool operator()(const F& /*cost*/, const Profile& /*profile*/, std::size_t /*initial_edges*/,
                  std::size_t /*current_edges*/) const {
    return mesh->number_of_vertices() <= target;
  }
};
}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv, kPeer);
  TriSoup in;
  if (auto err = read_obj(args.input, in); !err.empty()) die(kPeer, err);

  Timer setup_timer;
  SurfaceMesh mesh;
  const SoupInfo info = soup_to_surface_mesh(in, mesh);
  const double setup_seconds = setup_timer.seconds();
  const std::size_t vertices_mesh = mesh.number_of_vertices();

  Timer tm;
  const VertexCountStop stop{&mesh, args.vertices};
#ifdef PEER_CGAL_LT
  const int removed = SMS::edge_collapse(mesh, stop);
#else
  using GH = SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel>;
  GH gh(mesh);
  const int removed = SMS::edge_collapse(
      mesh, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
#endif
  mesh.collect_garbage();
  const double secs = tm.seconds();

  std::vector<Vec3> outV;
  std::vector<Tri> outF;
  surface_mesh_to_arrays(mesh, outV, outF);
  if (auto err = write_obj(args.output, outV, outF); !err.empty()) die(kPeer, err);

  Json j =
      result_json(kPeer, args, in, args.vertices, outV.size(), outF.size(), secs, setup_seconds);
  j.add("soup_was_mesh", info.was_polygon_mesh)
      .add("vertices_duplicated", info.duplicated)
      .add("vertices_mesh", vertices_mesh)
      .add("edges_removed", removed)
      .add("version", std::string("CGAL ") + CGAL_VERSION_STR);
  j.print();
  return 0;
}
