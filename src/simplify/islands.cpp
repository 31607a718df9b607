#include "islands.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>

namespace dynpm::simplification {

std::vector<uint16_t> form_islands(const CollapseRules& rules, const CollapseMesh& mesh,
                                   uint32_t least, size_t& count) {
  const size_t components = rules.component_count();
  std::vector<uint16_t> island_of_component(components);
  count = 0;
  uint32_t open = 0;  // live vertices of the last island so far
  for (size_t c = 0; c < components; ++c) {
    if (count == 0 || (open >= least && count < 65536)) ++count, open = 0;
    island_of_component[c] = static_cast<uint16_t>(count - 1);
    open += rules.component_live(static_cast<uint32_t>(c));
  }
  std::vector<uint16_t> island_of(mesh.vertex_count());
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    island_of[v] = island_of_component[rules.component_of(v)];
  return island_of;
}

void IslandLog::add(const CollapseRecord& record) {
  entries_.push_back({record.v0, record.v1, static_cast<uint32_t>(record.moved_faces.size()),
                      record.wing_count, record.error});
  for (uint8_t w = 0; w < record.wing_count; ++w) wings_.push_back(record.wings[w]);
  for (uint32_t f : record.moved_faces) moved_faces_.push_back(f);
}

bool IslandLog::tell_next(CollapseListener& listener, CollapseRecord& record,
                          std::vector<uint32_t>& moved) {
  const Entry& e = entries_[next_];
  record.v0 = e.v0;
  record.v1 = e.v1;
  record.error = e.error;
  record.wing_count = e.wing_count;
  for (uint8_t w = 0; w < e.wing_count; ++w) record.wings[w] = wings_[next_wing_++];
  moved.clear();
  for (uint32_t m = 0; m < e.moved_count; ++m) moved.push_back(moved_faces_[next_moved_++]);
  record.moved_faces = moved;
  listener.on_collapse(record);
  ++next_;
  entries_.release_before(next_);
  wings_.release_before(next_wing_);
  moved_faces_.release_before(next_moved_);
  if (next_ < entries_.size()) return true;
  *this = IslandLog{};
  return false;
}

void IslandLog::tell_in_key_order(std::vector<IslandLog*> logs, CollapseListener& listener,
                                  const std::function<bool()>& stop) {
  using Head = std::pair<float, uint32_t>;  // an island's key so far, and the island
  std::priority_queue<Head, std::vector<Head>, std::greater<Head>> heads;
  for (uint32_t i = 0; i < logs.size(); ++i)
    if (logs[i]->size() > 0) heads.push({logs[i]->next_key(), i});
  CollapseRecord record;
  std::vector<uint32_t> moved;
  while (!heads.empty() && !(stop && stop())) {
    const auto [key, i] = heads.top();
    heads.pop();
    if (logs[i]->tell_next(listener, record, moved))
      heads.push({std::max(key, logs[i]->next_key()), i});
  }
}

}  // namespace dynpm::simplification
