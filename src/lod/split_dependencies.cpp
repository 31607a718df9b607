// Split dependencies derived from the split records (docs/selective.md "Dependencies"): one
// replay of the stream that tracks which faces hold each vertex, and per face its last writer
// and the readers since.
#include <algorithm>
#include <array>
#include <numeric>

#include "core/components.h"
#include "core/list_pool.h"
#include "core/parallel.h"
#include "core/prefetch.h"
#include "dynpm/lod.h"

namespace dynpm {
namespace {

// How many splits ahead the replay asks for a fan's faces' states (and half as many, their
// first readers).
constexpr uint32_t kFansAhead = 4;

// The faces holding each vertex as the replay goes; small lists, edited in place.
class VertexFans {
 public:
  explicit VertexFans(const ProgressiveMesh& mesh)
      // Room by the splits decoded (each creates at most 4 faces), not by HEAD's claim.
      : fans_(mesh.vertex_count(),
              std::min<size_t>(mesh.full_face_count,
                               mesh.base_face_count + size_t{4} * mesh.split_count()) *
                  6) {
    for (uint32_t f = 0; f < mesh.base_faces.size(); ++f)
      for (uint32_t c : mesh.base_faces[f].v)
        if (c != kNoVertex) fans_.push_back(c, f);
  }
  std::span<const uint32_t> of(uint32_t v) const { return fans_.of(v); }
  template <class ValuesAhead>
  void prefetch_ahead(std::span<const uint32_t> parents, uint32_t i, size_t ahead,
                      ValuesAhead&& faces_ahead) const {
    fans_.prefetch_ahead(parents, i, ahead, faces_ahead);
  }
  void add(uint32_t v, uint32_t f) { fans_.push_back(v, f); }
  void move(uint32_t f, uint32_t from, uint32_t to) {
    fans_.erase_unordered(from, f);
    fans_.push_back(to, f);
  }

 private:
  ListPool fans_;
};

// Per face: its last writer and the splits that read it since, as a singly linked list in one
// pool (a writer empties the list and its entries are reused: the pool holds the reads not yet
// followed by a write, not every read of the stream).
class FaceAccess {
 public:
  // Per face (kNoIndex each at first): its last writer and its first reader's pool entry; a
  // replay of a group of components shares them with the other groups' (they touch other faces).
  FaceAccess(std::vector<uint32_t>& last_writer, std::vector<uint32_t>& readers)
      : last_writer_(last_writer), readers_(readers) {}

  // Split i reads f: it needs f's last writer.
  void read(uint32_t f, uint32_t i, std::vector<uint32_t>& needs) {
    if (last_writer_[f] != kNoIndex) needs.push_back(last_writer_[f]);
    uint32_t entry = free_;
    if (entry != kNoIndex) {
      free_ = pool_[entry].next;
      pool_[entry] = {i, readers_[f]};
    } else {
      entry = static_cast<uint32_t>(pool_.size());
      pool_.push_back({i, readers_[f]});
    }
    readers_[f] = entry;
  }
  // Split i writes f (and reads it): it needs f's last writer and every reader since.
  void write(uint32_t f, uint32_t i, std::vector<uint32_t>& needs) {
    if (last_writer_[f] != kNoIndex) needs.push_back(last_writer_[f]);
    for (uint32_t r = readers_[f]; r != kNoIndex;) {
      needs.push_back(pool_[r].split);
      const uint32_t next = pool_[r].next;
      pool_[r].next = free_;
      free_ = r;
      r = next;
    }
    readers_[f] = kNoIndex;
    last_writer_[f] = i;
  }
  void prefetch_face(uint32_t f) const {
    prefetch(&last_writer_[f]);
    prefetch(&readers_[f]);
  }
  // The first of f's readers (after prefetch_face() has brought readers_[f]).
  void prefetch_readers(uint32_t f) const {
    if (readers_[f] != kNoIndex) prefetch(&pool_[readers_[f]]);
  }

 private:
  struct Reader {
    uint32_t split, next;
  };
  std::vector<uint32_t>&last_writer_, &readers_;
  std::vector<Reader> pool_;
  uint32_t free_ = kNoIndex;  // the first reusable entry of the pool
};

// Appends split i's sorted, unique dependencies to the CSR.
void close_split(std::vector<uint32_t>& needs, SplitDependencies& out) {
  std::sort(needs.begin(), needs.end());
  needs.erase(std::unique(needs.begin(), needs.end()), needs.end());
  out.deps.insert(out.deps.end(), needs.begin(), needs.end());
  out.dep_start.push_back(static_cast<uint32_t>(out.deps.size()));
}

// kFaceCreators: a split moves a corner by value and a quad wing inserts a corner by slot, so
// the writes of one face commute and each face's state depends only on which of its writers are
// applied, not on their order. Split i needs what makes its own step legal: its parent and its
// triangle wings' vertices; every face it writes existing (its creator) and, if a quad wing made
// it a quad, as a quad (without it a moved quad side opens a crack: 9 boundary loops instead of
// 5, measured); and the faces on its quad wings' sides at v1 existing (Hoppe's fn0..fn3).
SplitDependencies derive_face_creators(const ProgressiveMesh& mesh, SplitDependencies out) {
  const uint32_t n = mesh.split_count(), b = mesh.base_vertex_count, total = out.faces_after[n];
  VertexFans fans(mesh);
  std::vector<Face> faces = mesh.base_faces;
  faces.resize(total);
  std::vector<uint32_t> created_by(total, kNoIndex), quad_by(total, kNoIndex);
  out.last_writer.assign(total, kNoIndex);
  std::vector<uint32_t> needs;
  auto need = [&](uint32_t split) {
    if (split != kNoIndex) needs.push_back(split);
  };
  auto need_vertex = [&](uint32_t v) { need(v >= b ? v - b : kNoIndex); };
  auto need_face = [&](uint32_t f) {
    need(created_by[f]);
    need(quad_by[f]);
  };
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t v0 = b + i, v1 = mesh.parent[i];
    needs.clear();
    need_vertex(v1);
    for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
      need_face(mesh.moved_faces[m]);
    for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
      const SplitWing& w = mesh.wings[k];
      // A triangle wing's face names w, which must exist. The faces on its edge (v1, w) need
      // nothing more: the one moved to v0 is a written face; the one staying at v1, if not
      // made by w's or v1's split, is a triangle an earlier wing put on that same edge, and
      // without it the face that wing moved off the edge takes its place (measured valid:
      // docs/selective.md "Narrower: what a wing reads").
      if (w.was_triangle()) {
        need_vertex(w.vertex);
        continue;
      }
      // A quad wing inserts v0 by slot and never reads w; its face must exist as the triangle
      // the stream had, and Hoppe's fn0..fn3, the faces of v1's fan on the triangle's sides at
      // v1, must exist (their shape does not matter); without them a vertex can end up with two
      // faces (measured: (M2) fails).
      need_face(w.face);
      for (uint32_t f : fans.of(v1))
        for (uint32_t e : faces[w.face].v)
          if (e != kNoVertex && e != v1 && faces[f].contains(e)) need(created_by[f]);
    }
    uint32_t next = out.faces_after[i];
    for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
      const SplitWing& w = mesh.wings[k];
      if (w.was_triangle()) {
        created_by[next] = out.last_writer[next] = i;
        fans.add(v0, next);
        fans.add(v1, next);
        fans.add(w.vertex, next);
        ++next;
      } else {
        quad_by[w.face] = out.last_writer[w.face] = i;
        fans.add(v0, w.face);
      }
    }
    for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m) {
      out.last_writer[mesh.moved_faces[m]] = i;
      fans.move(mesh.moved_faces[m], v1, v0);
    }
    uint32_t count = out.faces_after[i];
    apply_split(mesh, i, faces, count);
    close_split(needs, out);
  }
  return out;
}

// Fewer splits than this are replayed on one thread (the groups cost more than they save).
constexpr uint32_t kSplitsForGroups = 1 << 16;

// The splits in groups of whole connected components, about equal in splits, for replays on
// several threads (kFan, kWingEdges): a split reads and writes only faces of its parent's
// component, so a group's replay gives each of its splits what one replay of all gives it.
// Each group's splits ascending; none when one group would do (a single component, or one that
// holds three quarters of the splits, or few splits).
std::vector<std::vector<uint32_t>> component_groups(const ProgressiveMesh& mesh, unsigned count) {
  const uint32_t n = mesh.split_count(), b = mesh.base_vertex_count;
  if (count < 2 || n < kSplitsForGroups) return {};
  // The base mesh's components (core/components.h); a split vertex belongs to its parent's.
  Topology base;
  base.vertex_count = b;
  base.faces = mesh.base_faces;
  size_t components = 0;
  const std::vector<uint32_t> base_component = connected_components(base, components);
  std::vector<uint32_t> component(n), splits_of(components, 0);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t p = mesh.parent[i];
    component[i] = p < b ? base_component[p] : component[p - b];
    ++splits_of[component[i]];
  }
  // The largest components first, each to the group with the fewest splits so far.
  std::vector<uint32_t> order;
  for (uint32_t r = 0; r < components; ++r)
    if (splits_of[r] > 0) order.push_back(r);
  std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
    return splits_of[x] != splits_of[y] ? splits_of[x] > splits_of[y] : x < y;
  });
  std::vector<uint64_t> load(count, 0);
  std::vector<uint32_t> group(components, 0);
  for (uint32_t r : order) {
    const auto least = std::min_element(load.begin(), load.end()) - load.begin();
    group[r] = static_cast<uint32_t>(least);
    load[least] += splits_of[r];
  }
  if (*std::max_element(load.begin(), load.end()) * 4 > uint64_t{n} * 3) return {};
  std::vector<std::vector<uint32_t>> groups(count);
  for (uint32_t i = 0; i < n; ++i) groups[group[component[i]]].push_back(i);
  return groups;
}

// One replay of the stream for kFan and kWingEdges over the splits given (ascending: all of
// them, or a group of components'), appending their dependencies to a CSR. The per-face states
// are shared by every group's replay; the vertex fans and the readers' pool are each replay's.
struct Replay {
  const ProgressiveMesh& mesh;
  SplitReads reads;
  const std::vector<uint32_t>& faces_after;
  std::vector<uint32_t> last_writer, readers;
  std::vector<uint32_t> written_by;  // == i: f is in W(i)
  std::vector<Face> faces;           // the stream's faces, kept only for kWingEdges

  void run(std::span<const uint32_t> splits, SplitDependencies& out) {
    const uint32_t b = mesh.base_vertex_count;
    VertexFans fans(mesh);
    FaceAccess access(last_writer, readers);
    const bool wing_edges = reads == SplitReads::kWingEdges;
    auto on_wing_edge = [&](uint32_t f, uint32_t i) {
      for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
        if (faces[f].contains(mesh.wings[k].vertex)) return true;
      return false;
    };
    std::vector<uint32_t> parents(splits.size()), needs;
    for (size_t j = 0; j < splits.size(); ++j) parents[j] = mesh.parent[splits[j]];
    for (size_t j = 0; j < splits.size(); ++j) {
      const uint32_t i = splits[j], v0 = b + i, v1 = parents[j];
      // Parents come in no spatial order: their fans, those faces' states and then their first
      // readers are asked for ahead (ListPool::prefetch_ahead()).
      fans.prefetch_ahead(parents, j, 2 * kFansAhead, [&](uint32_t f) {
        access.prefetch_face(f);
        prefetch(&written_by[f]);
      });
      if (j + kFansAhead / 2 < splits.size())
        for (uint32_t f : fans.of(parents[j + kFansAhead / 2])) access.prefetch_readers(f);
      needs.clear();
      if (v1 >= b) needs.push_back(v1 - b);
      for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
        written_by[mesh.moved_faces[m]] = i;
      for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
        if (!mesh.wings[k].was_triangle()) written_by[mesh.wings[k].face] = i;
      // R(i): v1's fan right before i; W(i) ⊂ R(i) except the faces i creates.
      for (uint32_t f : fans.of(v1)) {
        if (written_by[f] == i) {
          access.write(f, i, needs);
          continue;
        }
        if (reads == SplitReads::kFan || (wing_edges && on_wing_edge(f, i)))
          access.read(f, i, needs);
      }
      if (reads != SplitReads::kFan)
        for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
          if (mesh.wings[k].vertex >= b) needs.push_back(mesh.wings[k].vertex - b);
      uint32_t next = faces_after[i];
      for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
        const SplitWing& w = mesh.wings[k];
        if (w.was_triangle()) {
          access.write(next, i, needs);
          fans.add(v0, next);
          fans.add(v1, next);
          fans.add(w.vertex, next);
          ++next;
        } else {
          fans.add(v0, w.face);
        }
      }
      for (uint32_t m = mesh.moved_start[i]; m < mesh.moved_start[i + 1]; ++m)
        fans.move(mesh.moved_faces[m], v1, v0);
      if (uint32_t count = faces_after[i]; wing_edges) apply_split(mesh, i, faces, count);
      close_split(needs, out);
    }
  }
};

}  // namespace

SplitDependencies derive_split_dependencies(const ProgressiveMesh& mesh, SplitReads reads,
                                            unsigned threads) {
  const uint32_t n = mesh.split_count();
  SplitDependencies out;
  // Room for about 7 a split (6.6 on the crash data, docs/selective.md): grown by doubling, the
  // copies were a tenth of the build's reordering.
  out.deps.reserve(size_t{n} * 8);
  out.dep_start.reserve(size_t{n} + 1);
  out.faces_after.resize(n + 1);
  out.faces_after[0] = mesh.base_face_count;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t created = 0;
    for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k)
      created += mesh.wings[k].was_triangle();
    out.faces_after[i + 1] = out.faces_after[i] + created;
  }
  if (reads == SplitReads::kFaceCreators) return derive_face_creators(mesh, std::move(out));
  const uint32_t faces_total = out.faces_after[n];
  Replay replay{mesh, reads, out.faces_after, {}, {}, {}, {}};
  replay.last_writer.assign(faces_total, kNoIndex);
  replay.readers.assign(faces_total, kNoIndex);
  replay.written_by.assign(faces_total, kNoIndex);
  if (reads == SplitReads::kWingEdges) {
    replay.faces = mesh.base_faces;
    replay.faces.resize(faces_total);
  }
  const std::vector<std::vector<uint32_t>> groups = component_groups(mesh, thread_count(threads));
  if (groups.size() < 2) {
    std::vector<uint32_t> all(n);
    std::iota(all.begin(), all.end(), 0u);
    replay.run(all, out);
  } else {
    std::vector<SplitDependencies> parts(groups.size());
    parallel_for(groups.size(), groups.size(), static_cast<unsigned>(groups.size()),
                 [&](size_t begin, size_t end, size_t) {
                   for (size_t g = begin; g < end; ++g) {
                     parts[g].deps.reserve(groups[g].size() * 8);
                     parts[g].dep_start.reserve(groups[g].size() + 1);
                     replay.run(groups[g], parts[g]);
                   }
                 });
    // Each split's dependencies from its group's part, in split order.
    std::vector<uint32_t> group_of(n), next(groups.size(), 0);
    for (uint32_t g = 0; g < groups.size(); ++g)
      for (uint32_t i : groups[g]) group_of[i] = g;
    for (uint32_t i = 0; i < n; ++i) {
      const SplitDependencies& part = parts[group_of[i]];
      const std::span<const uint32_t> deps = part.of(next[group_of[i]]++);
      out.deps.insert(out.deps.end(), deps.begin(), deps.end());
      out.dep_start.push_back(static_cast<uint32_t>(out.deps.size()));
    }
  }
  out.last_writer = std::move(replay.last_writer);
  return out;
}

size_t SplitDependencies::max_count() const {
  size_t most = 0;
  for (uint32_t i = 0; i < split_count(); ++i) most = std::max<size_t>(most, of(i).size());
  return most;
}

double SplitDependencies::mean_count() const {
  return split_count() ? double(deps.size()) / split_count() : 0.0;
}

namespace {

// Flags what the splits on `stack` depend on, transitively (splits below `closed_prefix` count
// as flagged); returns how many it flagged.
uint32_t flag_dependencies(const SplitDependencies& deps, std::vector<uint8_t>& splits,
                           std::vector<uint32_t>& stack, uint32_t closed_prefix) {
  uint32_t flagged = 0;
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    for (uint32_t d : deps.of(i))
      if (d >= closed_prefix && !splits[d]) {
        splits[d] = 1;
        ++flagged;
        stack.push_back(d);
      }
  }
  return flagged;
}

}  // namespace

void close_under_dependencies(const SplitDependencies& deps, std::vector<uint8_t>& splits,
                              uint32_t closed_prefix) {
  std::fill_n(splits.begin(), closed_prefix, uint8_t{1});
  std::vector<uint32_t> stack;
  for (uint32_t i = closed_prefix; i < deps.split_count(); ++i)
    if (splits[i]) stack.push_back(i);
  flag_dependencies(deps, splits, stack, closed_prefix);
}

uint32_t add_with_dependencies(const SplitDependencies& deps, std::vector<uint8_t>& splits,
                               uint32_t i, std::vector<uint32_t>& stack) {
  if (splits[i]) return 0;
  splits[i] = 1;
  stack.assign(1, i);
  return 1 + flag_dependencies(deps, splits, stack, 0);
}

}  // namespace dynpm
