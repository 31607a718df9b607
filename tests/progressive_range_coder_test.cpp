// The range coder under the .dpm's split records and positions (src/progressive/range_coder.h):
// exact round trips, exact byte counts, and the refusals a decoder relies on. The same coded bytes
// are decoded by the browser's decoder in viewer/test/range_coder.test.mjs.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "progressive/range_coder.h"

namespace dynpm::progressive {
namespace {

// The sequence of the cross-language test: kind i % 3 is a signed value, an unsigned value or a
// bit, from a linear congruential generator; then the extremes and ten direct bits.
std::string fixed_sequence() {
  RangeEncoder e;
  SignedModel s;
  UnsignedModel u;
  BitModel b;
  uint32_t x = 12345;
  for (int i = 0; i < 200; ++i) {
    x = x * 1103515245u + 12345u;
    const int64_t mag = (x >> 8) % (i < 100 ? 9 : 100000);
    if (i % 3 == 0) s.encode(e, (x & 1) ? -mag : mag);
    if (i % 3 == 1) u.encode(e, static_cast<uint64_t>(mag));
    if (i % 3 == 2) e.bit(b, (x >> 20) & 1);
  }
  u.encode(e, (uint64_t{1} << 53) - 2);
  s.encode(e, -((int64_t{1} << 40) + 7));
  e.direct(0x2a5, 10);
  return e.finish();
}

std::string hex(const std::string& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (unsigned char c : bytes) {
    out.push_back(digits[c >> 4]);
    out.push_back(digits[c & 15]);
  }
  return out;
}

TEST(RangeCoder, TheFixedSequenceHasTheBytesTheJavaScriptTestDecodes) {
  EXPECT_EQ(hex(fixed_sequence()),
            "00a9ddf414c9088107e3303e9292b235f6b420802ce7114a78e3de6022a8468d220ac415d1f53e757c22b4"
            "08d1d1169a73dc9f2042cfdc004d976a004eaee3d1c33afa58178feafb18c8bfc8329d837b12b6e2c1d8c7"
            "23d33c4be70a0f9ef90da0ba8d547f50e9563c9d1c17ced92ba3b0d32d72001cacaa73811a5c8eefae6dd5"
            "720fa8f9ba12174a846bb450dbe402902966678da9544ba8711159bd24027c5ec111ad79853315c09e26f9"
            "cbd4af21416fcd34085dcefd1c4db14edcb7ab9297fd30b308981b74db6e1ee1032d1e3e84ff62a5664feb"
            "8e47e8593384b9108e41ff5a3c2a5ee0dad91243c9d8b307b63acd5007950e3305cd82f90ab1fd05b66092"
            "9ffef35934ffffffffffffff9427e67800f9b75d7800");
}

TEST(RangeCoder, RandomStreamsRoundTripAndUseEveryByte) {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 50; ++round) {
    std::vector<int64_t> values;
    const int count = 1 + static_cast<int>(rng() % 3000);
    const int spread = static_cast<int>(rng() % 52);
    for (int i = 0; i < count; ++i) {
      const int64_t m = static_cast<int64_t>(rng() >> (64 - 1 - spread)) >> 1;
      values.push_back((rng() & 1) ? -m : m);
    }
    RangeEncoder e;
    std::array<SignedModel, 3> models;
    for (size_t i = 0; i < values.size(); ++i) models[i % 3].encode(e, values[i]);
    const std::string bytes = e.finish();

    RangeDecoder d(bytes);
    std::array<SignedModel, 3> again;
    for (size_t i = 0; i < values.size(); ++i) ASSERT_EQ(again[i % 3].decode(d), values[i]) << i;
    EXPECT_TRUE(d.ok());
    EXPECT_TRUE(d.exhausted()) << "round " << round;
  }
}

TEST(RangeCoder, AStreamCutShortIsNotOk) {
  const std::string bytes = fixed_sequence();
  RangeDecoder d(std::string_view(bytes).substr(0, bytes.size() - 3));
  SignedModel s;
  UnsignedModel u;
  BitModel b;
  for (int i = 0; i < 200; ++i) {
    if (i % 3 == 0) s.decode(d);
    if (i % 3 == 1) u.decode(d);
    if (i % 3 == 2) d.bit(b);
  }
  u.decode(d);
  s.decode(d);
  d.direct(10);
  EXPECT_FALSE(d.ok());
}

TEST(RangeCoder, ANumberOf53BitsIsRefusedAndAStreamNotStartingWithZeroIsBad) {
  // 53 ones in the unary length, coded with models that start and adapt as UnsignedModel's do:
  // what no encoder writes for a value below 2^53 − 1.
  RangeEncoder e;
  std::array<BitModel, 25> length{};
  for (int i = 0; i < 53; ++i) e.bit(length[std::min(i, 24)], 1);
  const std::string bytes = e.finish();
  RangeDecoder d(bytes);
  UnsignedModel u;
  u.decode(d);
  EXPECT_TRUE(d.too_large());
  EXPECT_FALSE(d.ok());

  std::string damaged = fixed_sequence();
  damaged[0] = 1;
  RangeDecoder bad(damaged);
  EXPECT_FALSE(bad.ok());
}

}  // namespace
}  // namespace dynpm::progressive
