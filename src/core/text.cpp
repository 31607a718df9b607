// The number rule of the text readers and the rendering of file bytes in messages (text.h).
#include <algorithm>
#include <charconv>
#include <limits>

#include "dynpm/text.h"

namespace dynpm {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// For a token std::from_chars found out of the double range: true when it is too large (its
// leading digit's decimal exponent is positive), false when too small. The mantissa's digits and
// the exponent give that exponent; out of range means it is beyond ±300, so its sign decides.
bool overflows(std::string_view s) {
  size_t i = s.empty() || (s[0] != '-' && s[0] != '+') ? 0 : 1;
  int64_t lead = 0;  // decimal exponent of the first non-zero digit, before the 'e' part
  bool seen_nonzero = false, after_point = false;
  int64_t integer_digits = 0, leading_fraction_zeros = 0;
  for (; i < s.size() && (is_digit(s[i]) || s[i] == '.'); ++i) {
    if (s[i] == '.') {
      after_point = true;
    } else if (!after_point) {
      if (seen_nonzero || s[i] != '0') ++integer_digits, seen_nonzero = true;
    } else if (!seen_nonzero) {
      if (s[i] == '0')
        ++leading_fraction_zeros;
      else
        seen_nonzero = true;
    }
  }
  lead = integer_digits > 0 ? integer_digits - 1 : -(leading_fraction_zeros + 1);
  int64_t exponent = 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    const bool minus = i < s.size() && s[i] == '-';
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) ++i;
    for (; i < s.size() && is_digit(s[i]); ++i)
      if (exponent < 1'000'000'000) exponent = exponent * 10 + (s[i] - '0');
    if (minus) exponent = -exponent;
  }
  return lead + exponent > 0;
}

// The token without its leading '+', which std::from_chars does not take; false for "+-1".
bool without_plus(std::string_view token, std::string_view& digits) {
  digits = token;
  if (digits.empty() || digits[0] != '+') return true;
  digits.remove_prefix(1);
  return digits.empty() || digits[0] != '-';
}

}  // namespace

NumberError parse_real(std::string_view token, double& out) {
  std::string_view digits;
  if (!without_plus(token, digits)) return NumberError::kNotANumber;
  const char* end = digits.data() + digits.size();
  double value = 0;
  auto [next, ec] = std::from_chars(digits.data(), end, value);
  if (next != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return NumberError::kNotANumber;
  if (ec == std::errc::result_out_of_range) {
    const bool negative = digits[0] == '-';
    value = overflows(digits) ? std::numeric_limits<double>::infinity() : 0.0;
    if (negative) value = -value;
  }
  out = value;
  return NumberError::kNone;
}

NumberError parse_integer(std::string_view token, int64_t lo, int64_t hi, int64_t& out) {
  std::string_view digits;
  if (!without_plus(token, digits)) return NumberError::kNotANumber;
  const char* end = digits.data() + digits.size();
  int64_t value = 0;
  auto [next, ec] = std::from_chars(digits.data(), end, value);
  if (next != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return NumberError::kNotANumber;
  if (ec == std::errc::result_out_of_range || value < lo || value > hi)
    return NumberError::kOutOfRange;
  out = value;
  return NumberError::kNone;
}

NumberError parse_count(std::string_view token, uint64_t& out) {
  int64_t value = 0;
  const NumberError e = parse_integer(token, 0, INT64_MAX, value);
  if (e == NumberError::kNone) out = static_cast<uint64_t>(value);
  return e;
}

namespace {

// The length of the UTF-8 sequence at bytes[i] when it is a well-formed character a terminal
// shows as itself, else 0: from U+00A0 on (not the C1 controls, which some terminals take as
// escapes), not a surrogate, and none of the invisible format characters that reorder or hide
// text (U+200B–U+200F, U+2028–U+202E, U+2060–U+206F, U+FEFF).
size_t shown_character(std::string_view bytes, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(bytes[k]); };
  const unsigned char lead = byte(i);
  const size_t length = lead >= 0xf0 && lead <= 0xf4   ? 4
                        : lead >= 0xe0                 ? (lead < 0xf0 ? 3 : 0)
                        : lead >= 0xc2 && lead <= 0xdf ? 2
                                                       : 0;
  if (length == 0 || i + length > bytes.size()) return 0;
  uint32_t code = lead & (0x7f >> length);
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
    code = code << 6 | (byte(i + k) & 0x3f);
  }
  const uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < smallest[length] || code > 0x10ffff || code < 0xa0) return 0;  // overlong, C1
  if ((code >= 0xd800 && code <= 0xdfff) || (code >= 0x200b && code <= 0x200f) ||
      (code >= 0x2028 && code <= 0x202e) || (code >= 0x2060 && code <= 0x206f) || code == 0xfeff)
    return 0;
  return length;
}

}  // namespace

std::string printable(std::string_view bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  const size_t shown = std::min(bytes.size(), kQuotedBytes);
  out.reserve(shown + 16);
  for (size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(bytes[i]);
    if (const size_t n = c >= 0x80 ? shown_character(bytes.substr(0, shown), i) : 0; n > 0) {
      out.append(bytes.substr(i, n));  // é, µ, …: a character, not its bytes
      i += n - 1;
    } else if (c == '\\')
      out += "\\\\";
    else if (c >= 0x20 && c < 0x7f)
      out += static_cast<char>(c);
    else if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += "\\t";
    else
      out.append("\\x").append(1, kHex[c >> 4]).append(1, kHex[c & 15]);
  }
  if (shown < bytes.size()) out += "… (" + std::to_string(bytes.size()) + " bytes)";
  return out;
}

// Appended, not "'" + printable(bytes): GCC 12 at -O3 warns -Wrestrict on the latter (a false
// positive in libstdc++, GCC bug 105329), which a Release build would print.
std::string quoted_bytes(std::string_view bytes) {
  std::string quoted(1, '\'');
  quoted += printable(bytes);
  quoted += '\'';
  return quoted;
}

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string xml_escaped(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

}  // namespace dynpm
