// Opening inputs in tests: the stream with the reader's warnings collected, and one step or
// field read back with a test failure if the read fails.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynpm/io.h"

namespace dynpm::test {

struct Opened {
  Result<AnimationStream> stream = Status::error("not opened");
  std::vector<std::string> warnings;
};

inline Opened open(const std::vector<std::string>& paths, ReadOptions options) {
  Opened o;
  options.warn = [&o](const std::string& w) { o.warnings.push_back(w); };
  o.stream = open_input(paths, options);
  return o;
}
inline Opened open(const std::vector<std::string>& paths, bool split_polygons = false) {
  ReadOptions options;
  options.split_polygons = split_polygons;
  return open(paths, options);
}
inline Opened open(const std::string& path) { return open(std::vector<std::string>{path}); }

inline std::vector<float> step(const AnimationStream& s, size_t t) {
  std::vector<float> xyz(size_t{s.frames->vertex_count()} * 3);
  const Status status = s.frames->read_step(t, xyz);
  EXPECT_TRUE(status.ok()) << status.message();
  return xyz;
}

// Field f at step t: one value per vertex (node field) or per face (element field).
inline std::vector<float> field(const AnimationStream& s, size_t f, size_t t) {
  const bool element = s.frames->fields().at(f).location == FieldLocation::kElement;
  std::vector<float> values(element ? s.topology.face_count() : s.frames->vertex_count());
  const Status status = s.frames->read_field(f, t, values);
  EXPECT_TRUE(status.ok()) << status.message();
  return values;
}

}  // namespace dynpm::test
