// Families (docs/family.md): the check that the variants share one mesh, and their distinct
// steps as one FrameSource for the build.
#include <algorithm>
#include <cstring>
#include <string_view>
#include <unordered_map>

#include "core/parallel.h"
#include "dynpm/pipeline.h"

namespace dynpm {
namespace {

std::string face_nodes(const Topology& t, size_t f) {
  std::string text;
  for (int c = 0; c < t.faces[f].degree(); ++c)
    text += (c ? " " : "") + std::to_string(t.node_ids[t.faces[f].v[c]]);
  return text;
}

// The first difference of b's mesh from a's, or "".
std::string first_difference(const Topology& a, const Topology& b, const std::string& a_name) {
  if (b.vertex_count != a.vertex_count)
    return std::to_string(b.vertex_count) + " nodes, " + a_name + " has " +
           std::to_string(a.vertex_count);
  for (uint32_t v = 0; v < a.vertex_count; ++v)
    if (b.node_ids[v] != a.node_ids[v])
      return "its node number " + std::to_string(v + 1) + " (ascending) is node " +
             std::to_string(b.node_ids[v]) + ", " + a_name + "'s is node " +
             std::to_string(a.node_ids[v]);
  if (b.faces.size() != a.faces.size())
    return std::to_string(b.faces.size()) + " elements, " + a_name + " has " +
           std::to_string(a.faces.size());
  for (size_t f = 0; f < a.faces.size(); ++f) {
    const std::string element = "element " + std::to_string(a.element_ids[f]);
    if (b.element_ids[f] != a.element_ids[f])
      return "its element number " + std::to_string(f + 1) + " is element " +
             std::to_string(b.element_ids[f]) + ", " + a_name + "'s is " + element;
    if (b.faces[f].degree() != a.faces[f].degree() ||
        std::memcmp(b.faces[f].v.data(), a.faces[f].v.data(), sizeof a.faces[f].v) != 0)
      return element + " has nodes " + face_nodes(b, f) + ", in " + a_name + " " + face_nodes(a, f);
    if (b.part_ids[f] != a.part_ids[f])
      return element + " is in part " + std::to_string(b.part_ids[f]) + ", in " + a_name +
             " in part " + std::to_string(a.part_ids[f]);
  }
  return "";
}

std::string field_list(const FrameSource& frames) {
  std::string text;
  for (const FieldInfo& f : frames.fields())
    text += (text.empty() ? "" : ", ") + f.name + " (" + to_string(f.location) + ")";
  return text.empty() ? "none" : text;
}

// A step's hash, 8 bytes at a time (a byte at a time took longer than reading the step): it
// only finds the candidates, which are then compared byte for byte.
uint64_t step_hash(std::string_view bytes) {
  uint64_t h = 0x9e3779b97f4a7c15ull ^ bytes.size();
  const auto mix = [&h](uint64_t word) {
    h = (h ^ word) * 0xff51afd7ed558ccdull;
    h ^= h >> 32;
  };
  size_t i = 0;
  for (uint64_t word; i + 8 <= bytes.size(); i += 8) {
    std::memcpy(&word, bytes.data() + i, 8);
    mix(word);
  }
  for (; i < bytes.size(); ++i) mix(static_cast<unsigned char>(bytes[i]));
  return h;
}

}  // namespace

Status check_same_mesh(std::span<const FamilyMember> members) {
  if (members.empty()) return Status::error("a family needs at least one input");
  const FamilyMember& first = members[0];
  for (size_t k = 1; k < members.size(); ++k) {
    const FamilyMember& m = members[k];
    for (size_t j = 0; j < k; ++j)
      if (members[j].name == m.name)
        return Status::error(m.source + ": its variant name '" + m.name + "' is " +
                             members[j].source + "'s (rename one)");
    std::string difference =
        m.mesh_checked ? "" : first_difference(*first.topology, *m.topology, first.source);
    if (difference.empty() && field_list(*m.frames) != field_list(*first.frames))
      difference = "its result fields are " + field_list(*m.frames) + ", " + first.source + "'s " +
                   field_list(*first.frames);
    if (!difference.empty())
      return Status::error(m.source + " is not a variant of " + first.source +
                           "'s mesh: " + difference);
  }
  return {};
}

Result<std::unique_ptr<FamilySteps>> FamilySteps::make(std::span<const FamilyMember> members,
                                                       const ProgressCallback& progress,
                                                       unsigned threads) {
  DYNPM_RETURN_IF_ERROR(check_same_mesh(members));
  auto family = std::make_unique<FamilySteps>();
  family->members_.assign(members.begin(), members.end());
  size_t total = 0, done = 0;
  for (const FamilyMember& m : members) total += m.frames->step_count();
  const size_t fields = members[0].frames->fields().size();
  const uint32_t faces = static_cast<uint32_t>(members[0].topology->faces.size());
  const uint32_t vertices = members[0].topology->vertex_count;

  // A step's bytes: its positions, then each field's values.
  auto read_all = [&](const FamilyMember& m, size_t step, std::string& bytes) -> Status {
    const std::vector<FieldInfo> infos = m.frames->fields();
    size_t floats = size_t{vertices} * 3;
    for (const FieldInfo& f : infos)
      floats += f.location == FieldLocation::kElement ? faces : vertices;
    bytes.assign(floats * sizeof(float), '\0');
    std::span<float> out(reinterpret_cast<float*>(bytes.data()), floats);
    DYNPM_RETURN_IF_ERROR(m.frames->read_step(step, out.first(size_t{vertices} * 3)));
    size_t at = size_t{vertices} * 3;
    for (size_t f = 0; f < fields; ++f) {
      const size_t n = infos[f].location == FieldLocation::kElement ? faces : vertices;
      if (Status s = m.frames->read_field(f, step, out.subspan(at, n)); !s.ok()) return s;
      at += n;
    }
    return {};
  };

  // A member's steps hashed, up to `threads` at once (each read into its own buffer) where its
  // source allows; the first step that cannot be read is the error.
  auto hash_steps = [&](const FamilyMember& m, std::vector<uint64_t>& hashes) -> Status {
    const size_t count = m.frames->step_count();
    const size_t most = std::max<size_t>(count, 1);  // a source without steps: one lane
    const size_t lanes =
        m.frames->parallel_reads() ? std::min<size_t>(thread_count(threads), most) : 1;
    std::vector<std::string> buffers(lanes);
    std::vector<Status> read(count);
    hashes.assign(count, 0);
    parallel_for(count, lanes, static_cast<unsigned>(lanes),
                 [&](size_t begin, size_t end, size_t lane) {
                   for (size_t t = begin; t < end; ++t)
                     if (read[t] = read_all(m, t, buffers[lane]); read[t].ok())
                       hashes[t] = step_hash(buffers[lane]);
                 });
    for (const Status& s : read) DYNPM_RETURN_IF_ERROR(s);
    return {};
  };

  std::unordered_multimap<uint64_t, size_t> by_hash;  // hash → stored step
  std::vector<uint64_t> hashes;
  std::string bytes, candidate;
  if (progress) progress("comparing the variants' steps", 0, total);
  for (size_t k = 0; k < members.size(); ++k) {
    const FamilyMember& m = members[k];
    MeshVariant variant{m.name, m.source, {}, {}};
    DYNPM_RETURN_IF_ERROR(hash_steps(m, hashes));
    for (size_t t = 0; t < m.frames->step_count(); ++t) {
      size_t stored = family->stored_.size();
      const auto [begin, end] = by_hash.equal_range(hashes[t]);
      if (begin != end) DYNPM_RETURN_IF_ERROR(read_all(m, t, bytes));
      for (auto it = begin; it != end && stored == family->stored_.size(); ++it) {
        const Stored& s = family->stored_[it->second];
        DYNPM_RETURN_IF_ERROR(read_all(family->members_[s.member], s.step, candidate));
        if (candidate == bytes) stored = it->second;  // exactly equal, not only the hash
      }
      if (stored == family->stored_.size()) {
        family->stored_.push_back({k, t});
        by_hash.emplace(hashes[t], stored);
      }
      variant.times.push_back(m.frames->step_time(t));
      variant.steps.push_back(static_cast<uint32_t>(stored));
      if (progress) progress("comparing the variants' steps", ++done, total);
    }
    family->variants_.push_back(std::move(variant));
  }
  family->order_for_prediction();
  return family;
}

// The file predicts each stored step's positions from the step before it (docs/FORMAT.md,
// "Positions"): in discovery order the second variant's first own step would follow the first
// variant's last, most deformed one. The first variant's steps reversed end at its undeformed
// step, which the next variants share and start from: A_n … A_1 A_0 B_1 … B_m. (Measured on the
// crash box family: 1.093x → see docs/family.md.)
void FamilySteps::order_for_prediction() {
  size_t first = 0;  // stored steps the first member made: 0 … first − 1
  while (first < stored_.size() && stored_[first].member == 0) ++first;
  std::reverse(stored_.begin(), stored_.begin() + static_cast<std::ptrdiff_t>(first));
  for (MeshVariant& v : variants_)
    for (uint32_t& s : v.steps)
      if (s < first) s = static_cast<uint32_t>(first - 1 - s);
}

uint32_t FamilySteps::vertex_count() const { return members_[0].frames->vertex_count(); }

double FamilySteps::step_time(size_t t) const {
  return members_[stored_[t].member].frames->step_time(stored_[t].step);
}

Status FamilySteps::read_step(size_t t, std::span<float> out) const {
  return members_[stored_[t].member].frames->read_step(stored_[t].step, out);
}

size_t FamilySteps::step_float_count(size_t t) const {
  return members_[stored_[t].member].frames->step_float_count(stored_[t].step);
}

bool FamilySteps::parallel_reads() const {
  for (const FamilyMember& m : members_)
    if (!m.frames->parallel_reads()) return false;
  return true;
}

std::vector<FieldInfo> FamilySteps::fields() const { return members_[0].frames->fields(); }

Status FamilySteps::read_field(size_t field, size_t t, std::span<float> out) const {
  return members_[stored_[t].member].frames->read_field(field, stored_[t].step, out);
}

}  // namespace dynpm
