#include "collapse_mesh.h"

#include <algorithm>
#include <cassert>

#include "core/pages.h"
#include "core/parallel.h"

namespace dynpm::simplification {

CollapseMesh::CollapseMesh(const Topology& topology) : faces_(topology.faces) {
  const uint32_t n = topology.vertex_count;
  islands_.resize(1);
  if (n > 0) islands_[0].runs.push_back({0, n});
  list_start_.assign(n, 0);
  list_size_.assign(n, 0);
  list_capacity_.assign(n, 0);
  for (const Face& f : faces_)
    for (uint32_t c : f.v)
      if (c != kNoVertex) ++list_capacity_[c];
  for (uint32_t v = 0; v < n; ++v) list_capacity_[v] += 2;  // room to grow before a list must move
  Island& whole = islands_[0];
  lay_out(whole);
  for (uint32_t f = 0; f < faces_.size(); ++f)
    for (uint32_t c : faces_[f].v)
      if (c != kNoVertex) whole.pool[list_start_[c] + list_size_[c]++] = f;
  for (uint32_t v = 0; v < n; ++v) whole.live_vertices += list_size_[v] > 0 ? 1 : 0;
  whole.live_faces = faces_.size();
}

void CollapseMesh::lay_out(Island& island) {
  uint32_t total = 0;
  for_each_member(island, [&](uint32_t v) {
    list_start_[v] = total;
    total += list_capacity_[v];
  });
  island.pool.reserve(total + total / 4);  // room for lists that grow: compact_pool() keeps it
  island.pool.resize(total);
}

void CollapseMesh::split_into_islands(std::vector<uint16_t> island_of, size_t count,
                                      unsigned threads) {
  assert(islands_.size() == 1 && count <= 65536 && island_of.size() == vertex_count());
  std::vector<Island> islands(count);
  for (uint32_t v = 0; v < vertex_count(); ++v) {
    Island& island = islands[island_of[v]];
    if (island.runs.empty() || island.runs.back().second != v) island.runs.push_back({v, v});
    ++island.runs.back().second;
  }
  const std::vector<uint32_t> old_pool = std::move(islands_[0].pool);
  islands_ = std::move(islands);
  island_of_ = std::move(island_of);
  const std::vector<uint32_t> old_start = list_start_;
  // Each island lays out its own vertices' lists: on several threads at once.
  parallel_for(islands_.size(), islands_.size(), threads, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      Island& island = islands_[i];
      lay_out(island);
      for_each_member(island, [&](uint32_t v) {
        std::copy_n(old_pool.begin() + old_start[v], list_size_[v],
                    island.pool.begin() + list_start_[v]);
        island.live_vertices += list_size_[v] > 0 ? 1 : 0;
      });
    }
  });
  for (const Face& f : faces_)
    if (f.v[0] != kNoVertex) ++islands_[island_of_[f.v[0]]].live_faces;
}

uint32_t CollapseMesh::live_vertices() const {
  uint32_t live = 0;
  for (const Island& island : islands_) live += island.live_vertices;
  return live;
}

size_t CollapseMesh::live_faces() const {
  size_t live = 0;
  for (const Island& island : islands_) live += island.live_faces;
  return live;
}

void CollapseMesh::neighbours(uint32_t v, std::vector<uint32_t>& out) const {
  out.clear();
  for (uint32_t f : faces_of(v)) {
    const Face& face = faces_[f];
    const int d = face.degree();
    const int i = corner_of(face, v);
    for (uint32_t w : {face.v[(i + 1) % d], face.v[(i + d - 1) % d]})
      if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  }
}

void CollapseMesh::second_order_neighbours(uint32_t v, std::vector<uint32_t>& out) const {
  out.clear();
  for (uint32_t f : faces_of(v))
    for (uint32_t w : faces_[f].v)
      if (w != kNoVertex && w != v && std::find(out.begin(), out.end(), w) == out.end())
        out.push_back(w);
}

void CollapseMesh::remove_face_from(uint32_t v, uint32_t f) {
  uint32_t* list = islands_[island_of(v)].pool.data() + list_start_[v];
  uint32_t& size = list_size_[v];
  for (uint32_t k = 0; k < size; ++k) {
    if (list[k] != f) continue;
    list[k] = list[--size];
    return;
  }
}

void CollapseMesh::reserve_list(uint32_t v, uint32_t size) {
  if (size <= list_capacity_[v]) return;
  // Move the list to the end of the pool with room to grow; the old block is abandoned.
  const uint32_t capacity = size + size / 2 + 2;
  Island& island = islands_[island_of(v)];
  std::vector<uint32_t>& pool = island.pool;
  if (pool.size() + capacity > pool.capacity()) compact_pool(island, capacity);
  const uint32_t start = static_cast<uint32_t>(pool.size());
  pool.resize(pool.size() + capacity);
  std::copy_n(pool.begin() + list_start_[v], list_size_[v], pool.begin() + start);
  list_start_[v] = start;
  list_capacity_[v] = capacity;
}

// An island's pool is full. Growing it would keep every block that moved lists abandoned: instead
// the live vertices' lists (with their room to grow, each in its order: the quadrics sum faces in
// list order) move to the front of the pool in the order they lie there, removed vertices give
// theirs up, and the pages past them go back to the system. In place: a fresh pool beside the
// old one was the simplifier's peak. The pool grows only when the lists and `extra` need more
// than it holds, to a quarter more.
void CollapseMesh::compact_pool(Island& island, uint32_t extra) {
  std::vector<uint32_t>& pool = island.pool;
  std::vector<uint64_t> live;  // start << 32 | vertex: sorted by start as plain integers
  size_t needed = extra;
  for_each_member(island, [&](uint32_t v) {
    if (list_size_[v] == 0) {
      list_start_[v] = list_capacity_[v] = 0;
      return;
    }
    live.push_back(uint64_t{list_start_[v]} << 32 | v);
    needed += list_capacity_[v];
  });
  std::sort(live.begin(), live.end());
  uint32_t end = 0;
  for (uint64_t key : live) {  // end ≤ list_start_[v]: each list moves down or stays
    const auto v = static_cast<uint32_t>(key);
    std::copy_n(pool.begin() + list_start_[v], list_size_[v], pool.begin() + end);
    list_start_[v] = end;
    end += list_capacity_[v];
  }
  pool.resize(end);
  if (needed + needed / 4 > pool.capacity())
    pool.reserve(needed + needed / 4);
  else
    release_unused_capacity(pool);
}

void CollapseMesh::collapse(uint32_t v0, uint32_t v1, CollapseRecord& record,
                            std::vector<uint32_t>& moved) {
  record.v0 = v0;
  record.v1 = v1;
  record.wing_count = 0;
  moved.clear();
  // Copy: v0's list is rewritten below while we walk it.
  std::array<uint32_t, 64> local;
  std::vector<uint32_t> spill;
  std::span<const uint32_t> v0_faces = faces_of(v0);
  if (v0_faces.size() <= local.size()) {
    std::copy(v0_faces.begin(), v0_faces.end(), local.begin());
    v0_faces = {local.data(), v0_faces.size()};
  } else {
    spill.assign(v0_faces.begin(), v0_faces.end());
    v0_faces = spill;
  }

  for (uint32_t f : v0_faces) {
    Face& face = faces_[f];
    const int d = face.degree();
    const int i0 = corner_of(face, v0);
    const int i1 = corner_of(face, v1);
    if (i1 < 0) {  // the face moves to v1
      face.v[i0] = v1;
      moved.push_back(f);
      continue;
    }
    // A face of the edge: record its wing, then shrink it.
    const bool v1_follows = face.v[(i0 + 1) % d] == v1;
    assert((v1_follows || face.v[(i0 + d - 1) % d] == v1) && "collapse across a quad diagonal");
    if (record.wing_count < record.wings.size()) {
      SplitWing& wing = record.wings[record.wing_count++];
      wing.face = f;
      wing.vertex = v1_follows ? face.v[(i0 + d - 1) % d] : face.v[(i0 + 1) % d];
      wing.flags = static_cast<uint8_t>((d == 3 ? SplitWing::kWasTriangle : 0) |
                                        (v1_follows ? SplitWing::kV1FollowsV0 : 0) |
                                        (i0 << SplitWing::kSlotShift));
    }
    if (d == 3) {  // a triangle vanishes
      for (uint32_t c : face.v)
        if (c != v0 && c != kNoVertex) remove_face_from(c, f);
      face.v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
      --islands_[island_of(v0)].live_faces;
    } else {  // a quad becomes a triangle: drop v0, keep the cyclic order
      for (int k = i0; k < 3; ++k) face.v[k] = face.v[k + 1];
      face.v[3] = kNoVertex;
    }
  }

  reserve_list(v1, list_size_[v1] + static_cast<uint32_t>(moved.size()));
  Island& island = islands_[island_of(v1)];
  for (uint32_t f : moved) island.pool[list_start_[v1] + list_size_[v1]++] = f;
  list_size_[v0] = 0;
  --islands_[island_of(v0)].live_vertices;  // v1's island but for a collapse across regions
  // Legality ((P2), (P1*)) guarantees no vertex but v0 is left without faces.
  for (uint8_t k = 0; k < record.wing_count; ++k)
    assert(list_size_[record.wings[k].vertex] > 0 && "a collapse orphaned a wing vertex");
  assert(list_size_[v1] > 0 && "a collapse orphaned v1");
  record.moved_faces = moved;
}

void collapse_faces(std::span<Face> faces, const CollapseRecord& record) {
  for (uint32_t f : record.moved_faces)
    for (uint32_t& c : faces[f].v)
      if (c == record.v0) c = record.v1;
  for (uint8_t w = 0; w < record.wing_count; ++w) {
    Face& face = faces[record.wings[w].face];
    if (record.wings[w].was_triangle()) {
      face.v = {kNoVertex, kNoVertex, kNoVertex, kNoVertex};
      continue;
    }
    for (int k = record.wings[w].v0_slot(); k < 3; ++k) face.v[k] = face.v[k + 1];
    face.v[3] = kNoVertex;
  }
}

Topology live_topology(const Topology& input, std::span<const Face> faces,
                       std::vector<uint32_t>& original_vertex) {
  std::vector<uint32_t> new_id(input.vertex_count, kNoVertex);
  size_t live = 0;
  for (const Face& face : faces) {
    if (face.v[0] == kNoVertex) continue;
    ++live;
    for (uint32_t c : face.v)
      if (c != kNoVertex) new_id[c] = 0;  // alive; numbered below
  }
  original_vertex.clear();
  for (uint32_t v = 0; v < input.vertex_count; ++v) {
    if (new_id[v] == kNoVertex) continue;
    new_id[v] = static_cast<uint32_t>(original_vertex.size());
    original_vertex.push_back(v);
  }
  Topology out;
  out.vertex_count = static_cast<uint32_t>(original_vertex.size());
  out.node_ids.reserve(original_vertex.size());
  for (uint32_t v : original_vertex) out.node_ids.push_back(input.node_ids[v]);
  out.faces.reserve(live);
  out.part_ids.reserve(live);
  out.element_ids.reserve(live);
  for (uint32_t f = 0; f < faces.size(); ++f) {
    if (faces[f].v[0] == kNoVertex) continue;
    Face face = faces[f];
    for (uint32_t& c : face.v)
      if (c != kNoVertex) c = new_id[c];
    out.faces.push_back(face);
    out.part_ids.push_back(input.part_ids[f]);
    out.element_ids.push_back(input.element_ids[f]);
  }
  return out;
}

Status check_simplified(const Topology& now, const TopologyStats& initial, bool keep_parts,
                        const std::string& where) {
  const ValidationReport report = validate(now);
  for (const Problem& p : report.problems)
    if (p.severity == Severity::kError) return Status::error(where + p.message);
  const TopologyStats stats = topology_stats(now, Adjacency::build(now));
  if (stats.euler_characteristic != initial.euler_characteristic)
    return Status::error(where + "Euler characteristic changed from " +
                         std::to_string(initial.euler_characteristic) + " to " +
                         std::to_string(stats.euler_characteristic));
  if (stats.boundary_loops != initial.boundary_loops)
    return Status::error(where + "boundary loops changed from " +
                         std::to_string(initial.boundary_loops) + " to " +
                         std::to_string(stats.boundary_loops));
  if (stats.components != initial.components) return Status::error(where + "components changed");
  if (keep_parts && stats.parts != initial.parts)  // a part is gone
    return Status::error(where + "parts changed from " + std::to_string(initial.parts) + " to " +
                         std::to_string(stats.parts));
  if (report.count(ProblemKind::kRepeatedVertex) || report.count(ProblemKind::kDuplicateFace))
    return Status::error(where + "a face repeats a vertex or another face");
  return {};
}

}  // namespace dynpm::simplification
