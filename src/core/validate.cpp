// validate(): the paper's mesh rules (M1) manifold with boundary, (M2) inner-vertex valence ≥ 3,
// (M3) face degree ≥ 3 (Wundrak et al. 2006, §2), plus what a reader of untrusted files needs:
// indices in range, no repeated corner, finite positions, one vertex count in every step.
//
// Non-manifold edges (shells meeting in a T-joint) and non-manifold vertices are accepted and
// reported with Severity::kFeature: the simplifier keeps them instead of converting the mesh to
// a manifold one, so a T-joint can never open into a crack (docs/architecture.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dynpm/core.h"
#include "face_geometry.h"
#include "parallel.h"

namespace dynpm {
namespace {

std::string face_text(const Face& f) {
  std::string s = "(";
  for (int i = 0; i < 4 && f.v[i] != kNoVertex; ++i) {
    if (i) s += ", ";
    s += std::to_string(f.v[i]);
  }
  return s + ")";
}

void check_faces(const Topology& topology, ValidationReport& report,
                 std::vector<uint8_t>& face_ok) {
  const auto& faces = topology.faces;
  face_ok.assign(faces.size(), 1);
  for (uint32_t fi = 0; fi < faces.size(); ++fi) {
    const Face& f = faces[fi];
    auto where = [&] { return "face " + std::to_string(fi) + " " + face_text(f); };
    if (f.v[0] == kNoVertex || f.v[1] == kNoVertex || f.v[2] == kNoVertex) {
      report.add({ProblemKind::kFaceDegree, Severity::kError, fi, kNoIndex, kNoIndex,
                  where() + ": (M3) a face needs at least 3 corners, it has " +
                      std::to_string(f.degree())});
      face_ok[fi] = 0;
      continue;
    }
    for (int i = 0; i < 4; ++i) {
      if (f.v[i] != kNoVertex && f.v[i] >= topology.vertex_count) {
        report.add({ProblemKind::kIndexOutOfRange, Severity::kError, fi, f.v[i], kNoIndex,
                    where() + ": corner " + std::to_string(i) + " names vertex " +
                        std::to_string(f.v[i]) + ", but there are only " +
                        std::to_string(topology.vertex_count) + " vertices"});
        face_ok[fi] = 0;
      }
      for (int j = 0; j < i; ++j) {
        if (f.v[i] != kNoVertex && f.v[i] == f.v[j]) {
          report.add({ProblemKind::kRepeatedVertex, Severity::kError, fi, f.v[i], kNoIndex,
                      where() + ": vertex " + std::to_string(f.v[i]) + " appears twice"});
          face_ok[fi] = 0;
        }
      }
    }
  }
}

void check_array_sizes(const Topology& topology, ValidationReport& report) {
  auto check = [&](size_t have, size_t want, const char* what, const char* per) {
    if (have != want)
      report.add({ProblemKind::kArraySize, Severity::kError, kNoIndex, kNoIndex, kNoIndex,
                  std::string(what) + " has " + std::to_string(have) + " entries for " +
                      std::to_string(want) + " " + per});
  };
  check(topology.part_ids.size(), topology.faces.size(), "part_ids", "faces");
  check(topology.element_ids.size(), topology.faces.size(), "element_ids", "faces");
  check(topology.node_ids.size(), topology.vertex_count, "node_ids", "vertices");
}

// Duplicate faces, as (face, an earlier face with the same corners) in the order of their sorted
// corners: sort the faces by their sorted corners and compare neighbours. Apart from the
// adjacency, so that both can be made at once.
std::vector<std::pair<uint32_t, uint32_t>> duplicate_faces(const Topology& good) {
  std::vector<std::pair<std::array<uint32_t, 4>, uint32_t>> keyed(good.faces.size());
  for (uint32_t fi = 0; fi < good.faces.size(); ++fi) {
    keyed[fi] = {good.faces[fi].v, fi};
    std::sort(keyed[fi].first.begin(), keyed[fi].first.end());
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::pair<uint32_t, uint32_t>> duplicates;
  for (size_t k = 1; k < keyed.size(); ++k)
    if (keyed[k].first == keyed[k - 1].first)
      duplicates.emplace_back(keyed[k].second, keyed[k - 1].second);
  return duplicates;
}

void report_duplicate_faces(const Topology& good, const std::vector<uint32_t>& original_face,
                            std::span<const std::pair<uint32_t, uint32_t>> duplicates,
                            ValidationReport& report) {
  for (const auto& [fi, first] : duplicates) {
    report.add({ProblemKind::kDuplicateFace, Severity::kWarning, original_face[fi], kNoIndex,
                kNoIndex,
                "face " + std::to_string(original_face[fi]) + " " + face_text(good.faces[fi]) +
                    " has the same vertices as face " + std::to_string(original_face[first])});
  }
}

// Runs on faces whose corners are in range and distinct; face numbers are the original ones.
void check_connectivity(const Topology& good, const Adjacency& adj,
                        const std::vector<uint32_t>& original_face, ValidationReport& report) {
  std::vector<uint32_t> valence(good.vertex_count, 0);
  for (size_t e = 0; e < adj.edge_count(); ++e) {
    const Edge edge = adj.edge(e);
    ++valence[edge.a];
    ++valence[edge.b];
    auto ef = adj.faces_of_edge(e);
    auto name = [&] {
      return "edge (" + std::to_string(edge.a) + ", " + std::to_string(edge.b) + ")";
    };
    if (ef.size() >= 3) {
      std::string list;
      for (uint32_t f : ef) {
        if (!list.empty()) list += ", ";
        list += std::to_string(original_face[f]);
      }
      report.add({ProblemKind::kNonManifoldEdge, Severity::kFeature, original_face[ef[0]], edge.a,
                  kNoIndex,
                  name() + ": (M1) shared by " + std::to_string(ef.size()) + " faces (" + list +
                      "); kept as a feature"});
    } else if (ef.size() == 2) {
      // Consistent orientation: the two faces walk the edge in opposite directions.
      auto walks_a_to_b = [&](const Face& f) {
        const int d = f.degree();
        for (int i = 0; i < d; ++i)
          if (f.v[i] == edge.a && f.v[(i + 1) % d] == edge.b) return true;
        return false;
      };
      if (walks_a_to_b(good.faces[ef[0]]) == walks_a_to_b(good.faces[ef[1]]))
        report.add({ProblemKind::kInconsistentOrientation, Severity::kWarning, original_face[ef[1]],
                    edge.a, kNoIndex,
                    name() + ": faces " + std::to_string(original_face[ef[0]]) + " and " +
                        std::to_string(original_face[ef[1]]) +
                        " walk it in the same direction (flipped normal)"});
    }
  }

  for (uint32_t v = 0; v < good.vertex_count; ++v) {
    const uint8_t kind = adj.vertex_kind(v);
    auto name = [&] { return "vertex " + std::to_string(v); };
    if (kind & kUnreferencedVertex) {
      report.add({ProblemKind::kUnreferencedVertex, Severity::kWarning, kNoIndex, v, kNoIndex,
                  name() + ": in no face"});
    } else if (adj.is_feature_vertex(v)) {
      report.add({ProblemKind::kNonManifoldVertex, Severity::kFeature, kNoIndex, v, kNoIndex,
                  name() + ": (M1) its neighbourhood is not a disc or half-disc" +
                      ((kind & kOnNonManifoldEdge) ? " (on a non-manifold edge)"
                                                   : " (faces form several fans)") +
                      "; kept as a feature"});
    } else if (!(kind & kBoundaryVertex) && valence[v] < 3) {
      report.add({ProblemKind::kInnerValence, Severity::kError, kNoIndex, v, kNoIndex,
                  name() + ": (M2) inner vertex with valence " + std::to_string(valence[v]) +
                      ", at least 3 needed"});
    }
  }
}

// Twice the area of face f at positions xyz, against its longest edge squared: a face is of zero
// area when 2A <= kFlat · L², i.e. (for a triangle) its height is below 1e-6 of its longest edge.
// The vector area (diagonals' cross product for a quad) also catches a quad folded flat.
constexpr double kFlat = 1e-6;
bool has_zero_area(const Face& f, const float* xyz) {
  const int d = f.degree();
  Vec3 p[4];
  for (int i = 0; i < d; ++i) p[i] = load(&xyz[size_t{f.v[i]} * 3]);
  double longest = 0;
  for (int i = 0; i < d; ++i) {
    const Vec3 e = p[(i + 1) % d] - p[i];
    longest = std::max(longest, dot(e, e));
  }
  return length(doubled_vector_area(p, d)) <= kFlat * longest;
}

// Steps read and checked at once where the source allows it (12 B a vertex each).
constexpr size_t kStepsAtOnce = 4;

// What the check of one step found, reported afterwards in step order.
struct StepFindings {
  size_t floats = 0;                 // the step's size as the source gives it
  Status read;                       // the read's outcome (when the size was right)
  std::vector<uint32_t> non_finite;  // vertices, ascending
  std::vector<uint32_t> zero_area;   // faces, ascending (only those face_ok)
};

// Reads step t into xyz and finds its problems, scanning the faces on `threads` threads; writes
// nothing but its own findings and xyz.
StepFindings find_step_problems(const Topology& topology, const std::vector<uint8_t>& face_ok,
                                const FrameSource& frames, uint32_t t, std::vector<float>& xyz,
                                unsigned threads) {
  StepFindings found;
  found.floats = frames.step_float_count(t);
  if (found.floats != xyz.size()) return found;
  found.read = frames.read_step(t, xyz);
  if (!found.read.ok()) return found;
  for (uint32_t v = 0; v < topology.vertex_count; ++v) {
    const float* p = &xyz[size_t{v} * 3];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      found.non_finite.push_back(v);
  }
  const size_t faces = topology.faces.size(), parts = std::max<size_t>(1, faces / 65536);
  std::vector<std::vector<uint32_t>> part_faces(parts);
  parallel_for(faces, parts, threads, [&](size_t begin, size_t end, size_t part) {
    for (size_t fi = begin; fi < end; ++fi)
      if (face_ok[fi] && has_zero_area(topology.faces[fi], xyz.data()))
        part_faces[part].push_back(static_cast<uint32_t>(fi));
  });
  for (const auto& some : part_faces)
    found.zero_area.insert(found.zero_area.end(), some.begin(), some.end());
  return found;
}

void check_frames(const Topology& topology, const std::vector<uint8_t>& face_ok,
                  const FrameSource& frames, ValidationReport& report) {
  if (frames.step_count() == 0) {
    report.add({ProblemKind::kNoSteps, Severity::kError, kNoIndex, kNoIndex, kNoIndex,
                "the animation has no time step"});
    return;
  }
  if (frames.vertex_count() != topology.vertex_count) {
    report.add({ProblemKind::kStepVertexCount, Severity::kError, kNoIndex, kNoIndex, kNoIndex,
                "the time steps hold " + std::to_string(frames.vertex_count()) +
                    " vertices, the faces use " + std::to_string(topology.vertex_count)});
    return;
  }
  const size_t steps = frames.step_count();
  const unsigned threads = thread_count(0);
  // Several steps on as many threads where the source reads them at once, else one step with
  // its faces scanned on every thread; each step's findings are reported in step order, so the
  // report is the same either way.
  const size_t batch =
      frames.parallel_reads() ? std::min<size_t>({threads, kStepsAtOnce, steps}) : 1;
  const unsigned face_threads = static_cast<unsigned>(std::max<size_t>(1, threads / batch));
  std::vector<std::vector<float>> xyz(batch, std::vector<float>(size_t{topology.vertex_count} * 3));
  std::vector<StepFindings> found(batch);
  std::vector<uint8_t> flat_seen(topology.faces.size(), 0);  // each face reported once
  for (size_t first = 0; first < steps; first += batch) {
    const size_t count = std::min(batch, steps - first);
    parallel_for(count, count, static_cast<unsigned>(count), [&](size_t begin, size_t end, size_t) {
      for (size_t j = begin; j < end; ++j)
        found[j] = find_step_problems(topology, face_ok, frames, static_cast<uint32_t>(first + j),
                                      xyz[j], face_threads);
    });
    for (size_t j = 0; j < count; ++j) {
      const uint32_t t = static_cast<uint32_t>(first + j);
      const StepFindings& f = found[j];
      const std::string step = "step " + std::to_string(t);
      if (f.floats != xyz[j].size()) {
        report.add({ProblemKind::kStepVertexCount, Severity::kError, kNoIndex, kNoIndex, t,
                    step + ": holds " + std::to_string(f.floats / 3) +
                        (f.floats % 3 ? " and a partial" : "") + " vertices, expected " +
                        std::to_string(topology.vertex_count)});
        continue;
      }
      if (!f.read.ok()) {
        report.add({ProblemKind::kUnreadableStep, Severity::kError, kNoIndex, kNoIndex, t,
                    step + ": " + f.read.message()});
        continue;
      }
      for (uint32_t v : f.non_finite) {
        const float* p = &xyz[j][size_t{v} * 3];
        char text[96];
        std::snprintf(text, sizeof text, "(%g, %g, %g)", double(p[0]), double(p[1]), double(p[2]));
        const std::string node = v < topology.node_ids.size()
                                     ? " (node " + std::to_string(topology.node_ids[v]) + ")"
                                     : "";
        report.add({ProblemKind::kNonFinitePosition, Severity::kError, kNoIndex, v, t,
                    step + ", vertex " + std::to_string(v) + node + ": position " + text +
                        " is not finite"});
      }
      for (uint32_t fi : f.zero_area) {
        if (flat_seen[fi]) continue;
        flat_seen[fi] = 1;
        report.add({ProblemKind::kZeroAreaFace, Severity::kWarning, fi, kNoIndex, t,
                    "face " + std::to_string(fi) + " " + face_text(topology.faces[fi]) +
                        ": zero area at " + step + " (its corners lie on a line or coincide)"});
      }
    }
  }
}

void check_fields(const Topology& topology, size_t steps, std::span<const ScalarField> fields,
                  ValidationReport& report) {
  for (const ScalarField& field : fields) {
    if (field.steps.size() != steps) {
      report.add({ProblemKind::kFieldSize, Severity::kError, kNoIndex, kNoIndex, kNoIndex,
                  "field '" + field.name + "' has " + std::to_string(field.steps.size()) +
                      " steps, the animation " + std::to_string(steps)});
      continue;
    }
    const bool per_face = field.location == FieldLocation::kElement;
    const size_t expected = per_face ? topology.faces.size() : size_t{topology.vertex_count};
    for (uint32_t t = 0; t < field.steps.size(); ++t)
      if (field.steps[t].size() != expected)
        report.add({ProblemKind::kFieldSize, Severity::kError, kNoIndex, kNoIndex, t,
                    "field '" + field.name + "', step " + std::to_string(t) + ": " +
                        std::to_string(field.steps[t].size()) + " values for " +
                        std::to_string(expected) + (per_face ? " faces" : " vertices")});
  }
}

}  // namespace

void ValidationReport::add(Problem problem) {
  size_t& total = totals[static_cast<size_t>(problem.kind)];
  ++severity_totals[static_cast<size_t>(problem.severity)];
  if (total++ < kMaxListedPerKind) problems.push_back(std::move(problem));
}

ValidationReport validate(const Topology& topology, const FrameSource* frames,
                          std::span<const ScalarField> fields) {
  std::optional<Adjacency> unused;
  return validate(topology, unused, frames, fields);
}

ValidationReport validate(const Topology& topology, std::optional<Adjacency>& adjacency,
                          const FrameSource* frames, std::span<const ScalarField> fields) {
  ValidationReport report;
  adjacency.reset();
  check_array_sizes(topology, report);

  std::vector<uint8_t> face_ok;
  check_faces(topology, report, face_ok);
  if (std::all_of(face_ok.begin(), face_ok.end(), [](uint8_t ok) { return ok; })) {
    std::vector<uint32_t> identity(topology.faces.size());
    for (uint32_t i = 0; i < identity.size(); ++i) identity[i] = i;
    // The duplicates' sort and the adjacency on two threads (a large mesh's check is most of
    // the time before a simplification starts).
    std::vector<std::pair<uint32_t, uint32_t>> duplicates;
    const unsigned threads = topology.faces.size() >= (1u << 16) ? 2 : 1;
    parallel_for(2, 2, threads, [&](size_t part, size_t, size_t) {
      if (part == 0)
        duplicates = duplicate_faces(topology);
      else
        adjacency = Adjacency::build(topology);
    });
    report_duplicate_faces(topology, identity, duplicates, report);
    check_connectivity(topology, *adjacency, identity, report);
  } else {
    // Check the rest of the mesh over the faces that can be trusted.
    Topology good;
    good.vertex_count = topology.vertex_count;
    std::vector<uint32_t> original;
    for (uint32_t fi = 0; fi < topology.faces.size(); ++fi) {
      if (!face_ok[fi]) continue;
      good.faces.push_back(topology.faces[fi]);
      original.push_back(fi);
    }
    report_duplicate_faces(good, original, duplicate_faces(good), report);
    check_connectivity(good, Adjacency::build(good), original, report);
  }

  if (frames) {
    check_frames(topology, face_ok, *frames, report);
    check_fields(topology, frames->step_count(), fields, report);
  }
  return report;
}

// What validate() without steps reads: the vertex count, the id arrays' sizes and every
// corner. A 64-bit mix per value (splitmix64's finaliser): a few milliseconds at a million faces,
// against the check's second or so.
uint64_t ValidationProof::fingerprint(const Topology& topology) {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  const auto mix = [&h](uint64_t x) {
    h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 30, h *= 0xbf58476d1ce4e5b9ull;
    h ^= h >> 27, h *= 0x94d049bb133111ebull;
    h ^= h >> 31;
  };
  for (uint64_t size : {uint64_t{topology.vertex_count}, uint64_t{topology.faces.size()},
                        uint64_t{topology.part_ids.size()}, uint64_t{topology.element_ids.size()},
                        uint64_t{topology.node_ids.size()}})
    mix(size);
  for (const Face& f : topology.faces)
    mix(uint64_t{f.v[0]} | uint64_t{f.v[1]} << 32), mix(uint64_t{f.v[2]} | uint64_t{f.v[3]} << 32);
  return h;
}

ValidationProof::ValidationProof(uint64_t fingerprint, std::optional<Adjacency> adjacency)
    : fingerprint_(fingerprint),
      adjacency_(std::make_shared<std::optional<Adjacency>>(std::move(adjacency))) {}

std::optional<Adjacency> ValidationProof::take_adjacency() const {
  std::optional<Adjacency> taken;
  taken.swap(*adjacency_);
  return taken;
}

ValidationReport check_topology(const Topology& topology, std::optional<ValidationProof>& proof) {
  std::optional<Adjacency> adjacency;
  ValidationReport report = validate(topology, adjacency);
  proof.reset();
  if (report.ok())
    proof = ValidationProof(ValidationProof::fingerprint(topology), std::move(adjacency));
  return report;
}

const char* to_string(ProblemKind kind) {
  switch (kind) {
    case ProblemKind::kArraySize: return "array-size";
    case ProblemKind::kIndexOutOfRange: return "index-out-of-range";
    case ProblemKind::kFaceDegree: return "face-degree (M3)";
    case ProblemKind::kRepeatedVertex: return "repeated-vertex";
    case ProblemKind::kDuplicateFace: return "duplicate-face";
    case ProblemKind::kNonManifoldEdge: return "non-manifold-edge (M1)";
    case ProblemKind::kNonManifoldVertex: return "non-manifold-vertex (M1)";
    case ProblemKind::kInnerValence: return "inner-valence (M2)";
    case ProblemKind::kInconsistentOrientation: return "inconsistent-orientation";
    case ProblemKind::kUnreferencedVertex: return "unreferenced-vertex";
    case ProblemKind::kStepVertexCount: return "step-vertex-count";
    case ProblemKind::kNonFinitePosition: return "non-finite-position";
    case ProblemKind::kZeroAreaFace: return "zero-area-face";
    case ProblemKind::kFieldSize: return "field-size";
    case ProblemKind::kUnreadableStep: return "unreadable-step";
    case ProblemKind::kNoSteps: return "no-steps";
  }
  return "unknown";
}

const char* to_string(Severity severity) {
  switch (severity) {
    case Severity::kError: return "error";
    case Severity::kFeature: return "feature";
    case Severity::kWarning: return "warning";
  }
  return "unknown";
}

}  // namespace dynpm
