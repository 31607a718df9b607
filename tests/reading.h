// Opening inputs in tests: the stream with the reader's warnings collected, and one step or
// field read back with a test failure if the read fails.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <thread>
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

// Every step and every field at every step, read on `threads` threads at once, each thread
// reading all of them (a source that allows parallel_reads() must give each thread what one
// thread reads alone); for each thread: per step, its positions then its fields.
inline std::vector<std::vector<std::vector<float>>> read_everything_at_once(
    const AnimationStream& s, unsigned threads) {
  const FrameSource& frames = *s.frames;
  const size_t steps = frames.step_count(), fields = frames.fields().size();
  std::vector<std::vector<std::vector<float>>> read(threads);
  auto read_all = [&](std::vector<std::vector<float>>& out) {
    for (size_t t = 0; t < steps; ++t) {
      out.emplace_back(size_t{frames.vertex_count()} * 3, -1.0f);
      if (!frames.read_step(t, out.back()).ok()) out.back().clear();
      for (size_t f = 0; f < fields; ++f) {
        const bool element = frames.fields()[f].location == FieldLocation::kElement;
        out.emplace_back(element ? s.topology.face_count() : frames.vertex_count(), -1.0f);
        if (!frames.read_field(f, t, out.back()).ok()) out.back().clear();
      }
    }
  };
  std::vector<std::thread> running;
  for (auto& out : read) running.emplace_back([&] { read_all(out); });
  for (auto& t : running) t.join();
  return read;
}

// Reads on several threads at once are what one thread reads alone, and none failed.
inline void expect_parallel_reads_agree(const AnimationStream& s) {
  ASSERT_TRUE(s.frames->parallel_reads());
  const auto alone = read_everything_at_once(s, 1)[0];
  for (const auto& v : alone) ASSERT_FALSE(v.empty()) << "a read failed";
  for (const auto& out : read_everything_at_once(s, 4)) EXPECT_TRUE(out == alone);
}

}  // namespace dynpm::test
