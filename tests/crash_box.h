// The shared CalculiX crash box, loaded once, and a listener that keeps every collapse as told:
// what the simplifier's island and region tests run on.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "dynpm/io.h"
#include "dynpm/simplify.h"
#include "fixtures.h"

namespace dynpm::test {

// The real crash box (CalculiX, 3,003 nodes, 26 steps), every step in memory.
inline const Animation* crashbox() {
  static TempDir dir;
  static std::optional<Animation> loaded;
  if (loaded) return &*loaded;
  const std::string frd = dir.file("crashbox-s.frd");
  const std::string unzip =
      "zcat '" + shared_data() + "/crashbox-s/crashbox-s.frd.gz' > '" + frd + "'";
  if (std::system(unzip.c_str()) != 0) return nullptr;
  auto stream = open_input(std::vector<std::string>{frd});
  if (!stream.ok()) return nullptr;
  auto all = load_all_steps(std::move(stream).value());
  if (!all.ok()) return nullptr;
  loaded = std::move(all).value();
  return &*loaded;
}

// Every collapse as told, whole.
struct Told final : CollapseListener {
  struct Collapse {
    uint32_t v0, v1;
    double error;
    std::vector<uint32_t> wings, moved;
    bool operator==(const Collapse&) const = default;
  };
  std::vector<Collapse> collapses;
  void on_collapse(const CollapseRecord& r) override {
    Collapse c{r.v0, r.v1, r.error, {}, {r.moved_faces.begin(), r.moved_faces.end()}};
    for (uint8_t w = 0; w < r.wing_count; ++w)
      c.wings.insert(c.wings.end(), {r.wings[w].face, r.wings[w].vertex, r.wings[w].flags});
    collapses.push_back(std::move(c));
  }
};

}  // namespace dynpm::test
