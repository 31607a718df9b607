// Peer driver: OpenMesh (Debian libopenmesh-dev) Decimater::DecimaterT.
//
// Settings: ModQuadricT with no error limit (unset_max_err: the quadric error is the priority
// only) + ModNormalFlippingT (binary; its default maximum normal deviation, 90 degrees),
// decimate_to(target vertices), then garbage_collection(). OpenMesh collapses halfedges: the
// surviving vertex keeps its position (no optimal placement). Points are double (Vec3d).
// Faces OpenMesh refuses (non-manifold: complex edge/vertex) are dropped and counted in
// "faces_rejected".
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <iostream>
#include <sstream>

#include "driver_common.h"
#include "obj_io.h"
#include "openmesh_obj.h"

using namespace peers;

namespace {
const char* kPeer = "openmesh";

struct Traits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv, kPeer);
  TriSoup in;
  if (auto err = read_obj(args.input, in); !err.empty()) die(kPeer, err);

  // OpenMesh prints "complex edge" warnings for every rejected face: silence them.
  std::ostringstream om_log;
  omerr().disconnect(std::cerr);
  omerr().connect(om_log);

  Timer setup_timer;
  Mesh mesh;
  const std::size_t rejected = add_soup(mesh, in);
  // Isolated vertices (unreferenced in the file) would never be collapsed: drop them.
  // Status flags are reference counted: keep our own request so that the decimater's
  // release in its destructor does not drop the deleted flags before garbage_collection().
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  std::size_t isolated = 0;
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) {
      mesh.delete_vertex(v, false);
      ++isolated;
    }
  mesh.garbage_collection();
  const double setup_seconds = setup_timer.seconds();

  Timer tm;
  std::size_t collapses = 0;
  {
    OpenMesh::Decimater::DecimaterT<Mesh> dec(mesh);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle hq;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle hn;
    dec.add(hq);
    dec.add(hn);
    dec.module(hq).unset_max_err();
    if (!dec.initialize()) die(kPeer, "decimater initialization failed");
    collapses = dec.decimate_to(args.vertices);
  }
  mesh.garbage_collection();
  const double secs = tm.seconds();

  std::vector<Vec3> outV;
  std::vector<Tri> outF;
  openmesh_arrays(mesh, outV, outF);
  compact(outV, outF);
  if (auto err = write_obj(args.output, outV, outF); !err.empty()) die(kPeer, err);

  Json j =
      result_json(kPeer, args, in, args.vertices, outV.size(), outF.size(), secs, setup_seconds);
  j.add("faces_rejected", rejected)
      .add("isolated_vertices_dropped", isolated)
      .add("collapses", collapses)
      .add("version", std::string("OpenMesh ") + std::to_string(OM_GET_VER) + "." +
                          std::to_string(OM_GET_MAJ));
  j.print();
  return 0;
}
