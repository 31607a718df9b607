// The text readers' shared rules (dynpm/text.h): one number tokenizer, and file bytes rendered
// printable and bounded in messages.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>

#include "dynpm/text.h"

namespace dynpm {
namespace {

double real(std::string_view token) {
  double v = -12345;
  EXPECT_EQ(parse_real(token, v), NumberError::kNone) << token;
  return v;
}

TEST(TextNumbers, RealsAreWholeTokens) {
  EXPECT_EQ(real("2.5"), 2.5);
  EXPECT_EQ(real("+2.5"), 2.5);
  EXPECT_EQ(real("-1e-3"), -1e-3);
  EXPECT_EQ(real(".5"), 0.5);
  EXPECT_TRUE(std::isnan(real("nan")));
  EXPECT_EQ(real("-inf"), -std::numeric_limits<double>::infinity());
  double v = 0;
  for (std::string_view bad : {"", "+", "2x", "1.5.3", "1e", "+-1", "0x10", " 1", "1 ", "--1"})
    EXPECT_EQ(parse_real(bad, v), NumberError::kNotANumber) << "'" << bad << "'";
}

// Beyond the double range: the nearest value, ±inf or ±0, never an error and never 0 for a huge
// number (VTK and VTU read 1e400 as 0, OBJ and PLY refused it).
TEST(TextNumbers, RealsBeyondTheDoubleRangeAreInfinityOrZero) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(real("1e400"), inf);
  EXPECT_EQ(real("-1e400"), -inf);
  EXPECT_EQ(real("123456.7e400"), inf);
  EXPECT_EQ(real("0.01e311"), inf);
  EXPECT_EQ(real("1e-400"), 0.0);
  EXPECT_TRUE(std::signbit(real("-1e-400")));
  EXPECT_EQ(real("0.00001e-320"), 0.0);
  EXPECT_EQ(real("1000e-320"), 1000e-320);  // a denormal keeps its value
  // Beyond the float range, a float cast gives inf: validation reports it (infinite.obj).
  EXPECT_EQ(static_cast<float>(real("1e39")), std::numeric_limits<float>::infinity());
}

TEST(TextNumbers, IntegersAreWholeTokensWithinTheirRange) {
  int64_t v = 0;
  EXPECT_EQ(parse_integer("255", 0, 255, v), NumberError::kNone);
  EXPECT_EQ(v, 255);
  EXPECT_EQ(parse_integer("+7", 0, 255, v), NumberError::kNone);
  EXPECT_EQ(v, 7);
  EXPECT_EQ(parse_integer("256", 0, 255, v), NumberError::kOutOfRange);
  EXPECT_EQ(parse_integer("-1", 0, 255, v), NumberError::kOutOfRange);
  EXPECT_EQ(parse_integer("99999999999999999999", INT64_MIN, INT64_MAX, v),
            NumberError::kOutOfRange);
  for (std::string_view bad : {"", "2x", "2.0", "1e3", "+-1", " 1"})
    EXPECT_EQ(parse_integer(bad, INT64_MIN, INT64_MAX, v), NumberError::kNotANumber) << bad;
  uint64_t n = 0;
  EXPECT_EQ(parse_count("2x", n), NumberError::kNotANumber);  // `element face 2x`
  EXPECT_EQ(parse_count("-2", n), NumberError::kOutOfRange);
  EXPECT_EQ(parse_count("2937", n), NumberError::kNone);
  EXPECT_EQ(n, 2937u);
}

TEST(TextQuoting, ControlBytesAreEscaped) {
  EXPECT_EQ(printable("POINTS"), "POINTS");
  EXPECT_EQ(printable(std::string_view("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable("\x1b]0;title\x07\x1b[2J"), "\\x1b]0;title\\x07\\x1b[2J");
  EXPECT_EQ(printable("tab\there\r\n"), "tab\\there\\r\\n");
  EXPECT_EQ(printable("back\\slash"), "back\\\\slash");
  EXPECT_EQ(printable("\x7f\xc3\xa9"), "\\x7f\xc3\xa9");  // DEL escaped, é shown
  // UTF-8: characters that show as themselves are kept (a note dynpm writes ends in "…"); the
  // C1 controls (U+009B is CSI on some terminals), text-reordering marks (U+202E), a BOM,
  // overlong forms, surrogates, stray continuation bytes and a character cut short are not.
  EXPECT_EQ(printable("frame_000.obj \xe2\x80\xa6 Tr\xc3\xa4ger 5 \xc2\xb5m \xe6\x9d\xbf"),
            "frame_000.obj \xe2\x80\xa6 Tr\xc3\xa4ger 5 \xc2\xb5m \xe6\x9d\xbf");
  EXPECT_EQ(printable("\xc2\x9b"
                      "2J"),
            "\\xc2\\x9b2J");
  EXPECT_EQ(printable("a\xe2\x80\xae"
                      "b"),
            "a\\xe2\\x80\\xaeb");
  EXPECT_EQ(printable("\xef\xbb\xbfx"), "\\xef\\xbb\\xbfx");
  EXPECT_EQ(printable("\xc0\xaf\xe0\x80\xaf"), "\\xc0\\xaf\\xe0\\x80\\xaf");
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");
  EXPECT_EQ(printable("\x80x\xe2\x80"), "\\x80x\\xe2\\x80");
  EXPECT_EQ(printable("\xf0\x9f\x98\x80"), "\xf0\x9f\x98\x80");
  EXPECT_EQ(quoted_bytes("x"), "'x'");
}

// A 100 KB statement is shown as its first 80 bytes and its length.
TEST(TextQuoting, LongTextIsCut) {
  const std::string statement(100000, 's');
  const std::string shown = printable(statement);
  EXPECT_EQ(shown, std::string(kQuotedBytes, 's') + "… (100000 bytes)");
  EXPECT_EQ(printable(std::string(kQuotedBytes, 'a')), std::string(kQuotedBytes, 'a'));
  // Escapes count as the byte they show: the output stays bounded.
  EXPECT_LE(printable(std::string(100000, '\0')).size(), 4 * kQuotedBytes + 32);
}

}  // namespace
}  // namespace dynpm
