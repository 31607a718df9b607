// Every validation rule, each with a fixture that breaks it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "fixtures.h"

namespace dynpm {
namespace {

using test::quad_grid;

bool has_problem(const ValidationReport& r, ProblemKind kind, Severity severity) {
  for (const Problem& p : r.problems)
    if (p.kind == kind && p.severity == severity) return true;
  return false;
}

std::string all_messages(const ValidationReport& r) {
  std::string s;
  for (const Problem& p : r.problems) s += p.message + "\n";
  return s;
}

TEST(Validate, CleanMeshesHaveNoProblems) {
  for (const auto& m : {quad_grid(5, 4), test::tri_quad_strip()}) {
    const ValidationReport r = validate(m.animation());
    EXPECT_TRUE(r.ok());
    EXPECT_TRUE(r.problems.empty()) << all_messages(r);
  }
}

TEST(Validate, ArraySizesMustMatch) {
  auto m = quad_grid(2, 2);
  m.topology.part_ids.pop_back();
  m.topology.node_ids.push_back(99);
  const ValidationReport r = validate(m.topology);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.count(ProblemKind::kArraySize), 2u);
}

TEST(Validate, IndexOutOfRange) {
  auto m = quad_grid(2, 2);
  m.topology.faces[3].v[2] = 9;  // there are 9 vertices: 0..8
  const ValidationReport r = validate(m.topology);
  ASSERT_TRUE(has_problem(r, ProblemKind::kIndexOutOfRange, Severity::kError));
  EXPECT_EQ(r.problems[0].face, 3u);
  EXPECT_NE(r.problems[0].message.find("face 3"), std::string::npos);
  EXPECT_NE(r.problems[0].message.find("vertex 9"), std::string::npos);
}

TEST(Validate, M3FaceWithTwoCornersIsAnError) {
  auto m = quad_grid(2, 1);
  m.topology.faces[1].v = {1, 2, kNoVertex, kNoVertex};
  const ValidationReport r = validate(m.topology);
  EXPECT_TRUE(has_problem(r, ProblemKind::kFaceDegree, Severity::kError));
}

TEST(Validate, RepeatedVertexInAFace) {
  auto m = quad_grid(2, 1);
  m.topology.faces[0].v[2] = m.topology.faces[0].v[0];
  const ValidationReport r = validate(m.topology);
  EXPECT_TRUE(has_problem(r, ProblemKind::kRepeatedVertex, Severity::kError));
  EXPECT_EQ(r.count(ProblemKind::kRepeatedVertex), 1u);
}

TEST(Validate, DuplicateFaceIsAWarning) {
  auto m = quad_grid(2, 1);
  const Face f = m.topology.faces[0];
  m.topology.add_quad(f.v[1], f.v[2], f.v[3], f.v[0]);  // same corners, rotated
  const ValidationReport r = validate(m.topology);
  EXPECT_TRUE(has_problem(r, ProblemKind::kDuplicateFace, Severity::kWarning));
}

TEST(Validate, M1NonManifoldEdgeIsAcceptedAsAFeature) {
  const auto m = test::t_joint();
  const ValidationReport r = validate(m.animation());
  EXPECT_TRUE(r.ok()) << all_messages(r);
  EXPECT_EQ(r.count(ProblemKind::kNonManifoldEdge), 1u);
  EXPECT_EQ(r.count(ProblemKind::kNonManifoldVertex), 2u);
  EXPECT_EQ(r.count(Severity::kFeature), 3u);
  EXPECT_NE(all_messages(r).find("shared by 3 faces"), std::string::npos);
}

TEST(Validate, M1BowTieVertexIsAcceptedAsAFeature) {
  const auto m = test::bow_tie();
  const ValidationReport r = validate(m.animation());
  EXPECT_TRUE(r.ok());
  ASSERT_EQ(r.count(ProblemKind::kNonManifoldVertex), 1u);
  EXPECT_EQ(r.problems[0].vertex, 2u);
}

TEST(Validate, M2InnerVertexOfValenceTwo) {
  const auto m = test::valence_two_quads();
  const ValidationReport r = validate(m.animation());
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.count(ProblemKind::kInnerValence), 1u) << all_messages(r);
  EXPECT_EQ(r.problems[0].vertex, 0u);
}

TEST(Validate, FlippedFaceIsReported) {
  auto m = quad_grid(2, 2);
  std::swap(m.topology.faces[0].v[1], m.topology.faces[0].v[3]);
  const ValidationReport r = validate(m.topology);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.count(ProblemKind::kInconsistentOrientation), 2u);  // its two inner edges
}

TEST(Validate, UnreferencedVertexIsAWarning) {
  auto m = quad_grid(1, 1);
  m.topology.vertex_count = 5;
  m.topology.node_ids.push_back(5);
  const ValidationReport r = validate(m.topology);
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(has_problem(r, ProblemKind::kUnreferencedVertex, Severity::kWarning));
}

TEST(Validate, EveryStepMustHaveTheSameVertexCount) {
  auto a = quad_grid(2, 2).animation();
  std::vector<float> short_step(a.frames.step(0).begin(), a.frames.step(0).end() - 3);
  a.frames.add_step(short_step, 1.0);
  a.frames.add_step(std::vector<float>(a.frames.step(0).begin(), a.frames.step(0).end()), 2.0);
  const ValidationReport r = validate(a);
  ASSERT_EQ(r.count(ProblemKind::kStepVertexCount), 1u);
  EXPECT_EQ(r.problems[0].step, 1u);
}

TEST(Validate, NonFinitePositionsAreErrorsWithStepAndVertex) {
  auto a = quad_grid(2, 2).animation();
  std::vector<float> step(a.frames.step(0).begin(), a.frames.step(0).end());
  step[3 * 4 + 1] = std::numeric_limits<float>::quiet_NaN();
  step[3 * 7 + 2] = std::numeric_limits<float>::infinity();
  a.frames.add_step(step, 1.0);
  const ValidationReport r = validate(a);
  ASSERT_EQ(r.count(ProblemKind::kNonFinitePosition), 2u);
  EXPECT_EQ(r.problems[0].step, 1u);
  EXPECT_EQ(r.problems[0].vertex, 4u);
  EXPECT_EQ(r.problems[1].vertex, 7u);
}

// A source over in-memory steps that reads them one at a time or several at once, and fails
// to read one step.
class StepsRead final : public FrameSource {
 public:
  StepsRead(const Frames& frames, bool parallel, size_t unreadable)
      : frames_(frames), parallel_(parallel), unreadable_(unreadable) {}
  uint32_t vertex_count() const override { return frames_.vertex_count(); }
  size_t step_count() const override { return frames_.step_count(); }
  double step_time(size_t t) const override { return frames_.step_time(t); }
  size_t step_float_count(size_t t) const override { return frames_.step_float_count(t); }
  bool parallel_reads() const override { return parallel_; }
  Status read_step(size_t t, std::span<float> out) const override {
    if (t == unreadable_) return Status::error("step.bin: cut short");
    return frames_.read_step(t, out);
  }

 private:
  const Frames& frames_;
  bool parallel_;
  size_t unreadable_;
};

// validate() reads several steps at once where the source allows it; the problems come in step
// order all the same, a face flat at several steps once (at its first), and a step of the wrong
// size or unreadable inside a batch does not hide the others' problems.
TEST(Validate, StepsReadAtOnceReportAsStepsReadInTurn) {
  test::Mesh m = quad_grid(3, 2);  // 4 × 3 vertices, 6 quads
  Animation a = m.animation();
  const auto step_with = [&](std::initializer_list<std::pair<size_t, float>> changes) {
    std::vector<float> xyz = m.positions;
    for (auto [i, value] : changes) xyz[i] = value;
    return xyz;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> flat = m.positions;
  for (size_t v = 4; v < 12; ++v) flat[v * 3 + 1] = 0;    // the upper rows on the lowest: 3 faces
  a.frames.add_step(step_with({{3 * 5 + 0, nan}}), 1.0);  // vertex 5
  a.frames.add_step(flat, 2.0);                           // faces 0 1 2 … flat
  a.frames.add_step(std::vector<float>(m.positions.begin(), m.positions.end() - 3), 3.0);
  a.frames.add_step(flat, 4.0);                                             // unreadable (below)
  a.frames.add_step(step_with({{3 * 2 + 1, nan}, {3 * 9 + 2, nan}}), 5.0);  // vertices 2, 9
  a.frames.add_step(flat, 6.0);                                             // the same faces again
  const auto messages = [&](bool parallel) {
    std::vector<std::string> out;
    const StepsRead source(a.frames, parallel, 4);
    for (const Problem& p : validate(a.topology, &source).problems)
      out.push_back(std::to_string(p.step) + " " + p.message);
    return out;
  };
  const std::vector<std::string> in_turn = messages(false), at_once = messages(true);
  EXPECT_EQ(at_once, in_turn);
  std::vector<uint32_t> steps;
  const StepsRead source(a.frames, true, 4);
  const ValidationReport r = validate(a.topology, &source);
  for (const Problem& p : r.problems) steps.push_back(p.step);
  EXPECT_TRUE(std::is_sorted(steps.begin(), steps.end())) << all_messages(r);
  EXPECT_EQ(r.count(ProblemKind::kNonFinitePosition), 3u);
  EXPECT_EQ(r.count(ProblemKind::kStepVertexCount), 1u);
  EXPECT_EQ(r.count(ProblemKind::kUnreadableStep), 1u);
  EXPECT_GE(r.count(ProblemKind::kZeroAreaFace), 3u);
  for (const Problem& p : r.problems) {
    if (p.kind == ProblemKind::kZeroAreaFace) {
      EXPECT_EQ(p.step, 2u) << p.message;
    }
  }
}

TEST(Validate, AnimationWithoutStepsIsAnError) {
  Animation a = quad_grid(1, 1).animation();
  a.frames = Frames(a.topology.vertex_count);
  EXPECT_TRUE(has_problem(validate(a), ProblemKind::kNoSteps, Severity::kError));
}

TEST(Validate, FieldSizesMustMatch) {
  auto a = quad_grid(1, 1).animation();
  a.fields.push_back({"plastic strain", {std::vector<float>(3, 0.f)}, FieldLocation::kNode, {}});
  a.fields.push_back({"stress",
                      {std::vector<float>(4, 0.f), std::vector<float>(4, 0.f)},
                      FieldLocation::kNode,
                      {}});
  const ValidationReport r = validate(a);
  EXPECT_EQ(r.count(ProblemKind::kFieldSize), 2u);
}

TEST(Validate, ReportsEveryProblemNotJustTheFirst) {
  auto m = quad_grid(3, 3);
  m.topology.faces[0].v[1] = m.topology.faces[0].v[0];  // repeated vertex
  m.topology.faces[4].v[3] = 1000;                      // out of range
  m.topology.part_ids.push_back(0);                     // array size
  auto a = m.animation();
  a.frames.step(0)[0] = std::nanf("");  // non-finite
  const ValidationReport r = validate(a);
  EXPECT_EQ(r.count(ProblemKind::kRepeatedVertex), 1u);
  EXPECT_EQ(r.count(ProblemKind::kIndexOutOfRange), 1u);
  EXPECT_EQ(r.count(ProblemKind::kArraySize), 1u);
  EXPECT_EQ(r.count(ProblemKind::kNonFinitePosition), 1u);
  EXPECT_EQ(r.count(Severity::kError), 4u);
}

TEST(Validate, ManyProblemsAreCountedButTheListIsBounded) {
  auto a = quad_grid(60, 60).animation();
  for (float& c : a.frames.step(0)) c = std::nanf("");
  const ValidationReport r = validate(a);
  EXPECT_EQ(r.count(ProblemKind::kNonFinitePosition), 61u * 61u);
  EXPECT_EQ(r.problems.size(), ValidationReport::kMaxListedPerKind);
}

// check_topology() proves only the mesh it checked: a broken one gets no proof, and the proof
// of a good one proves the same faces anywhere but not a face, the vertex count or an id
// array changed since (the simplifier then checks that mesh itself).
TEST(Validate, AProofProvesTheCheckedMeshOnly) {
  const Topology good = quad_grid(3, 3).topology;
  std::optional<ValidationProof> proof;
  ASSERT_TRUE(check_topology(good, proof).ok());
  ASSERT_TRUE(proof.has_value());
  Topology other = good;
  EXPECT_TRUE(proof->proves(other));
  other.faces[4].v[3] = 1000;
  EXPECT_FALSE(proof->proves(other));
  std::optional<ValidationProof> none = proof;
  EXPECT_FALSE(check_topology(other, none).ok());
  EXPECT_FALSE(none.has_value());
  other = good;
  std::swap(other.faces[0].v[0], other.faces[0].v[2]);
  EXPECT_FALSE(proof->proves(other));
  other = good;
  ++other.vertex_count;
  EXPECT_FALSE(proof->proves(other));
  other = good;
  other.part_ids.pop_back();
  EXPECT_FALSE(proof->proves(other));
}

// The proof hands the check's adjacency to one taker (the simplifier), any copy of it: the mesh's
// own adjacency, then none.
TEST(Validate, AProofHandsTheChecksAdjacencyOnce) {
  const Topology good = quad_grid(4, 3).topology;
  std::optional<ValidationProof> proof;
  ASSERT_TRUE(check_topology(good, proof).ok());
  const ValidationProof copy = *proof;
  const uint64_t held = proof->adjacency_bytes();
  const std::optional<Adjacency> taken = copy.take_adjacency();
  ASSERT_TRUE(taken.has_value());
  EXPECT_EQ(held, taken->bytes());
  EXPECT_GE(held, good.faces.size() * 4 * 4);  // at least each corner's face and edge's faces
  EXPECT_EQ(proof->adjacency_bytes(), 0u);
  const Adjacency built = Adjacency::build(good);
  ASSERT_EQ(taken->edge_count(), built.edge_count());
  for (size_t e = 0; e < built.edge_count(); ++e) {
    EXPECT_EQ(taken->edge(e).a, built.edge(e).a);
    EXPECT_EQ(taken->edge(e).b, built.edge(e).b);
    EXPECT_TRUE(std::ranges::equal(taken->faces_of_edge(e), built.faces_of_edge(e)));
  }
  for (uint32_t v = 0; v < good.vertex_count; ++v)
    EXPECT_TRUE(std::ranges::equal(taken->faces_of_vertex(v), built.faces_of_vertex(v)));
  EXPECT_FALSE(proof->take_adjacency().has_value());
  EXPECT_FALSE(copy.take_adjacency().has_value());
}

}  // namespace
}  // namespace dynpm
