// A .dpm file's chunks in tests: found by tag and offset, and made (docs/FORMAT.md), to damage,
// insert or cut a chunk and still give the checksums a reader checks.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm::test {

// The chunks of a .dpm, by tag and offset (docs/FORMAT.md: 12 bytes of signature and version,
// then 24-byte chunk headers, each followed by its stored bytes).
inline std::vector<std::pair<std::string, size_t>> chunks_of(const std::string& bytes) {
  std::vector<std::pair<std::string, size_t>> chunks;
  for (size_t at = 12; at + 24 <= bytes.size();) {
    uint32_t stored;
    std::memcpy(&stored, bytes.data() + at + 8, 4);
    chunks.emplace_back(bytes.substr(at, 4), at);
    at += 24 + stored;
  }
  return chunks;
}

inline uint32_t crc32_of(std::string_view bytes) {
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xffffffffu;
}

inline std::string chunk(const std::string& tag, uint32_t flags, uint32_t raw,
                         const std::string& stored) {
  std::string c = tag;
  for (uint32_t v : {flags, uint32_t(stored.size()), raw, crc32_of(stored), 0u})
    c.append(reinterpret_cast<const char*>(&v), 4);
  return c + stored;
}

// `bytes` with the chunk at `at` replaced by an uncompressed one holding `payload`.
inline std::string with_payload(const std::string& bytes, size_t at, const std::string& payload) {
  uint32_t stored;
  std::memcpy(&stored, bytes.data() + at + 8, 4);
  return bytes.substr(0, at) + chunk(bytes.substr(at, 4), 0, uint32_t(payload.size()), payload) +
         bytes.substr(at + 24 + stored);
}

template <typename T>
inline std::string put(std::string s, size_t at, T value) {
  std::memcpy(s.data() + at, &value, sizeof value);
  return s;
}

// That `bytes` is refused at file byte `byte`, with a message that holds `what`.
inline void expect_refused_at(const std::string& bytes, size_t byte, const std::string& what) {
  auto r = decode_dpm(bytes, "damaged.dpm");
  ASSERT_FALSE(r.ok()) << "accepted; expected: " << what;
  EXPECT_NE(r.message().find("damaged.dpm: byte " + std::to_string(byte) + ": "), std::string::npos)
      << r.message();
  EXPECT_NE(r.message().find(what), std::string::npos) << r.message();
}

}  // namespace dynpm::test
