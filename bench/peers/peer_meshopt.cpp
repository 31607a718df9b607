// Peer driver: meshoptimizer (Debian libmeshoptimizer-dev) meshopt_simplify.
//
// meshopt_simplify takes a target INDEX count, not a vertex count, so the driver searches the
// index target (secant steps inside a shrinking bracket, at most 24 calls, each call starting
// from the full mesh) until the number of vertices the result references is within 0.5 % of
// the requested vertex count, or the closest it can get. "seconds" is the time of the single
// call that produced the written result; "search_seconds" is the whole search.
// Settings: target_error = 1.0 (relative to the mesh extents: no error cap), options = 0
// (defaults). Positions are welded first (meshopt_generateVertexRemap on float3 positions) so
// that the simplifier sees one connected mesh even if the file repeats positions.
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>

#include "driver_common.h"
#include "obj_io.h"

using namespace peers;

namespace {
const char* kPeer = "meshoptimizer";
}

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv, kPeer);
  TriSoup in;
  if (auto err = read_obj(args.input, in); !err.empty()) die(kPeer, err);

  // Setup: float positions, flat index buffer, position welding.
  Timer setup_timer;
  const std::size_t vcount = in.V.size();
  std::vector<float> pos(vcount * 3);
  for (std::size_t i = 0; i < vcount; ++i)
    for (int c = 0; c < 3; ++c) pos[3 * i + c] = static_cast<float>(in.V[i][c]);
  std::vector<unsigned int> idx(in.F.size() * 3);
  for (std::size_t f = 0; f < in.F.size(); ++f)
    for (int c = 0; c < 3; ++c) idx[3 * f + c] = in.F[f][c];
  std::vector<unsigned int> remap(vcount);
  const std::size_t welded = meshopt_generateVertexRemap(remap.data(), idx.data(), idx.size(),
                                                         pos.data(), vcount, sizeof(float) * 3);
  std::vector<float> wpos(welded * 3);
  meshopt_remapVertexBuffer(wpos.data(), pos.data(), vcount, sizeof(float) * 3, remap.data());
  meshopt_remapIndexBuffer(idx.data(), idx.data(), idx.size(), remap.data());
  const double setup_seconds = setup_timer.seconds();

  const std::size_t I = idx.size();
  const std::size_t target_v = args.vertices;
  std::vector<unsigned int> dst(I), best_dst;
  std::vector<unsigned char> seen(welded);
  std::size_t best_r = 0, best_v = 0, best_t = 0, calls = 0;
  double best_secs = 0, best_err = 0, search_secs = 0;
  bool have_best = false, stalled = false;

  auto round3 = [&](double t) {
    auto v = static_cast<long long>(std::llround(t / 3.0)) * 3;
    return static_cast<std::size_t>(std::clamp<long long>(v, 3, static_cast<long long>(I)));
  };
  const double tol = std::max(1.0, 0.005 * static_cast<double>(target_v));
  std::size_t lo = 0, hi = I;  // bracket on the index target
  std::size_t t =
      round3(static_cast<double>(I) * static_cast<double>(target_v) / static_cast<double>(welded));

  while (calls < 24) {
    float err = 0;
    Timer tm;
    const std::size_t r = meshopt_simplify(dst.data(), idx.data(), I, wpos.data(), welded,
                                           sizeof(float) * 3, t, 1.0f, 0, &err);
    const double secs = tm.seconds();
    ++calls;
    search_secs += secs;
    std::fill(seen.begin(), seen.end(), 0);
    std::size_t v = 0;
    for (std::size_t k = 0; k < r; ++k)
      if (!seen[dst[k]]) {
        seen[dst[k]] = 1;
        ++v;
      }
    const double d = std::fabs(static_cast<double>(v) - static_cast<double>(target_v));
    if (!have_best || d < std::fabs(static_cast<double>(best_v) - static_cast<double>(target_v))) {
      have_best = true;
      best_dst.assign(dst.begin(), dst.begin() + static_cast<std::ptrdiff_t>(r));
      best_r = r;
      best_v = v;
      best_t = t;
      best_secs = secs;
      best_err = err;
    }
    if (d <= tol) break;
    if (v > target_v) {
      if (r > t) {
        stalled = true;
        break;
      }  // stopped short of the index target: cannot go lower
      hi = t;
    } else {
      lo = t;
    }
    std::size_t next = round3(static_cast<double>(t) * static_cast<double>(target_v) /
                              std::max<double>(1.0, static_cast<double>(v)));
    if (next <= lo || next >= hi) next = round3(0.5 * static_cast<double>(lo + hi));
    if (next == t || hi <= lo + 3) break;
    t = next;
  }

  // Result: compact the referenced vertices.
  std::vector<Vec3> outV(welded);
  for (std::size_t i = 0; i < welded; ++i)
    outV[i] = {wpos[3 * i], wpos[3 * i + 1], wpos[3 * i + 2]};
  std::vector<Tri> outF(best_r / 3);
  for (std::size_t f = 0; f < outF.size(); ++f)
    outF[f] = {best_dst[3 * f], best_dst[3 * f + 1], best_dst[3 * f + 2]};
  compact(outV, outF);
  if (auto err = write_obj(args.output, outV, outF); !err.empty()) die(kPeer, err);

  Json j =
      result_json(kPeer, args, in, target_v, outV.size(), outF.size(), best_secs, setup_seconds);
  j.add("welded_vertices", welded)
      .add("target_indices", best_t)
      .add("search_calls", calls)
      .add("search_seconds", search_secs)
      .add("stalled", stalled)
      .add("result_error", static_cast<double>(best_err))
      .add("version", std::string("meshoptimizer ") + std::to_string(MESHOPTIMIZER_VERSION));
  j.print();
  return 0;
}
