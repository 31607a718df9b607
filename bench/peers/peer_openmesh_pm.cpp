// Peer driver: OpenMesh's progressive mesh file (.pm), for bench/peers/format_bench.py.
//
//   peer_openmesh_pm build FRAME.obj -o OUT.pm
//     Decimater::DecimaterT with ModQuadricT (no error limit) + ModNormalFlippingT, as
//     peer_openmesh, plus ModProgMeshT recording every collapse; decimate(0) goes as far as the
//     modules allow, then ModProgMeshT::write() writes the .pm: base vertices and faces, then
//     per detail vertex its position (3 floats) and three vertex indices (v1, vl, vr).
//   peer_openmesh_pm replay IN.pm -o FULL.obj [--repeats N]
//     Reads the .pm as OpenMesh's ProgViewer does (base mesh, every detail vertex added up
//     front) and times replaying every vertex_split(v0, v1, vl, vr) on a TriMesh, median of N
//     runs (default 9); writes the fully refined mesh.
// Both print one JSON line; "seconds" is the decimation (build) or the replay (replay) only.
#include <OpenMesh/Core/IO/BinaryHelper.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModProgMeshT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "driver_common.h"
#include "obj_io.h"
#include "openmesh_obj.h"

using namespace peers;

namespace {
const char* kPeer = "openmesh-pm";

struct Traits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

struct Options {
  std::string mode, input, output;
  int repeats = 9;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if ((s == "-o" || s == "--output") && i + 1 < argc)
      o.output = argv[++i];
    else if (s == "--repeats" && i + 1 < argc)
      o.repeats = std::max(1, std::atoi(argv[++i]));
    else if (o.mode.empty() && (s == "build" || s == "replay"))
      o.mode = s;
    else if (!s.empty() && s[0] != '-' && o.input.empty())
      o.input = s;
    else
      die(kPeer, "unknown argument '" + s + "'");
  }
  if (o.mode.empty() || o.input.empty() || o.output.empty()) {
    std::fprintf(stderr,
                 "usage: peer_openmesh_pm build FRAME.obj -o OUT.pm\n"
                 "       peer_openmesh_pm replay IN.pm -o FULL.obj [--repeats N]\n");
    std::exit(2);
  }
  return o;
}

int build(const Options& o) {
  TriSoup in;
  if (auto err = read_obj(o.input, in); !err.empty()) die(kPeer, err);
  std::ostringstream om_log;  // OpenMesh's "complex edge" warnings for rejected faces
  omerr().disconnect(std::cerr);
  omerr().connect(om_log);

  Mesh mesh;
  const std::size_t rejected = add_soup(mesh, in);

  Timer tm;
  std::size_t collapses = 0;
  OpenMesh::Decimater::DecimaterT<Mesh> dec(mesh);
  OpenMesh::Decimater::ModQuadricT<Mesh>::Handle hq;
  OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle hn;
  OpenMesh::Decimater::ModProgMeshT<Mesh>::Handle hp;
  dec.add(hq);
  dec.add(hn);
  dec.add(hp);
  dec.module(hq).unset_max_err();
  if (!dec.initialize()) die(kPeer, "decimater initialization failed");
  collapses = dec.decimate(0);
  const double secs = tm.seconds();
  Timer write_timer;
  if (!dec.module(hp).write(o.output)) die(kPeer, "cannot write " + o.output);
  const double write_seconds = write_timer.seconds();

  std::error_code ec;
  Json j;
  j.add("peer", kPeer)
      .add("input", o.input)
      .add("vertices_in", in.V.size())
      .add("triangles_in", in.F.size())
      .add("faces_rejected", rejected)
      .add("splits", collapses)
      .add("base_vertices", in.V.size() - collapses)
      .add("bytes", static_cast<std::size_t>(std::filesystem::file_size(o.output, ec)))
      .add("seconds", secs)
      .add("write_seconds", write_seconds)
      .add("peak_rss_mb", peak_rss_mb());
  j.print();
  return 0;
}

struct Split {
  Mesh::VertexHandle v0, v1, vl, vr;
};

// Reads the .pm as ProgViewer does: every vertex added up front, then the base faces.
void read_pm(const std::string& path, Mesh& mesh, std::vector<Split>& splits) {
  std::ifstream in(path, std::ios::binary);
  if (!in) die(kPeer, "cannot open " + path);
  char magic[9] = {};
  in.read(magic, 8);
  if (std::string(magic) != "ProgMesh") die(kPeer, path + ": not an OpenMesh .pm file");
  unsigned n_base_v = 0, n_base_f = 0, n_detail = 0;
  OpenMesh::IO::restore(in, n_base_v, false);
  OpenMesh::IO::restore(in, n_base_f, false);
  OpenMesh::IO::restore(in, n_detail, false);
  OpenMesh::Vec3f p;
  for (unsigned i = 0; i < n_base_v; ++i) {
    OpenMesh::IO::restore(in, p, false);
    mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
  }
  for (unsigned i = 0; i < n_base_f; ++i) {
    unsigned a = 0, b = 0, c = 0;
    OpenMesh::IO::restore(in, a, false);
    OpenMesh::IO::restore(in, b, false);
    OpenMesh::IO::restore(in, c, false);
    mesh.add_face(Mesh::VertexHandle(int(a)), Mesh::VertexHandle(int(b)),
                  Mesh::VertexHandle(int(c)));
  }
  for (unsigned i = 0; i < n_detail; ++i) {
    unsigned v1 = 0, vl = 0, vr = 0;
    OpenMesh::IO::restore(in, p, false);
    OpenMesh::IO::restore(in, v1, false);
    OpenMesh::IO::restore(in, vl, false);
    OpenMesh::IO::restore(in, vr, false);
    splits.push_back({mesh.add_vertex(Mesh::Point(p[0], p[1], p[2])), Mesh::VertexHandle(int(v1)),
                      Mesh::VertexHandle(int(vl)), Mesh::VertexHandle(int(vr))});
  }
  if (!in) die(kPeer, path + ": truncated");
}

int replay(const Options& o) {
  std::vector<double> times;
  Mesh mesh;
  std::vector<Split> splits;
  for (int r = 0; r < o.repeats; ++r) {
    mesh = Mesh();
    splits.clear();
    read_pm(o.input, mesh, splits);
    Timer tm;
    for (const Split& s : splits) mesh.vertex_split(s.v0, s.v1, s.vl, s.vr);
    times.push_back(tm.seconds());
  }
  std::sort(times.begin(), times.end());
  const double secs = times[times.size() / 2];

  std::vector<Vec3> outV;
  std::vector<Tri> outF;
  openmesh_arrays(mesh, outV, outF);
  if (auto err = write_obj(o.output, outV, outF); !err.empty()) die(kPeer, err);
  Json j;
  j.add("peer", kPeer)
      .add("input", o.input)
      .add("splits", splits.size())
      .add("vertices_out", outV.size())
      .add("faces_out", outF.size())
      .add("seconds", secs)
      .add("repeats", o.repeats)
      .add("splits_per_s", secs > 0 ? double(splits.size()) / secs : 0.0);
  j.print();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  return o.mode == "build" ? build(o) : replay(o);
}
