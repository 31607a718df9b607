// The chunks' CRC-32 (src/progressive/dpm_format.h, eight bytes a step) against zlib's, which
// PNG and the JavaScript decoder's check agree with: every length's tail, every alignment, and
// the standard check value.
#include <gtest/gtest.h>
#include <zlib.h>

#include <random>
#include <string>

#include "progressive/dpm_format.h"

namespace dynpm {
namespace {

uint32_t zlib_crc(std::string_view bytes) {
  return static_cast<uint32_t>(
      ::crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

TEST(ChunkChecksum, IsTheStandardCrc32) {
  EXPECT_EQ(progressive::crc32("123456789"), 0xcbf43926u);
  EXPECT_EQ(progressive::crc32(""), 0u);
}

TEST(ChunkChecksum, AgreesWithZlibOnEveryLengthAndAlignment) {
  std::mt19937 random(20261205);
  std::string bytes(4096 + 64, '\0');
  for (char& b : bytes) b = static_cast<char>(random());
  for (size_t offset = 0; offset < 8; ++offset)
    for (size_t length = 0; length <= 300; ++length) {
      const std::string_view part(bytes.data() + offset, length);
      ASSERT_EQ(progressive::crc32(part), zlib_crc(part)) << offset << " " << length;
    }
  EXPECT_EQ(progressive::crc32(bytes), zlib_crc(bytes));
  const std::string ones(1000, '\xff');
  EXPECT_EQ(progressive::crc32(ones), zlib_crc(ones));
}

}  // namespace
}  // namespace dynpm
