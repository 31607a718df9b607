// Part names: made safe where a reader takes them from a file (clean_part_name), checked where
// the .dpm readers take them back (is_clean_part_name), kept by id in Topology::part_names.
#include <algorithm>

#include "dynpm/core.h"

namespace dynpm {
namespace {

// The UTF-8 character at s[i]: its code point and length, or length 0 when the bytes there are
// not one (overlong forms, surrogates and values above U+10FFFF are not).
struct Decoded {
  uint32_t code = 0;
  size_t length = 0;
};
Decoded decode_utf8(std::string_view s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(i);
  if (b < 0x80) return {b, 1};
  size_t n = 0;
  uint32_t code = 0, least = 0;
  if ((b & 0xe0) == 0xc0)
    n = 2, code = b & 0x1fu, least = 0x80;
  else if ((b & 0xf0) == 0xe0)
    n = 3, code = b & 0x0fu, least = 0x800;
  else if ((b & 0xf8) == 0xf0)
    n = 4, code = b & 0x07u, least = 0x10000;
  else
    return {};
  if (i + n > s.size()) return {};
  for (size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return {};
    code = (code << 6) | (byte(i + k) & 0x3fu);
  }
  if (code < least || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return {};
  return {code, n};
}

// C0, DEL and C1: nothing a name should carry into a terminal or a page.
bool is_control(uint32_t code) { return code < 0x20 || (code >= 0x7f && code <= 0x9f); }

constexpr std::string_view kReplacement = "\xef\xbf\xbd";  // U+FFFD

std::string_view trimmed(std::string_view s, std::string_view blanks) {
  const size_t first = s.find_first_not_of(blanks);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(blanks) - first + 1);
}

}  // namespace

std::string clean_part_name(std::string_view raw) {
  raw = trimmed(raw, std::string_view(" \t\r\n\0", 5));
  std::string out;
  for (size_t i = 0; i < raw.size();) {
    const Decoded d = decode_utf8(raw, i);
    const size_t length = std::max<size_t>(d.length, 1);
    const std::string_view piece =
        d.length == 0 || is_control(d.code) ? kReplacement : raw.substr(i, length);
    if (out.size() + piece.size() > kMaxPartName) break;  // cut at a character boundary
    out += piece;
    i += length;
  }
  return std::string(trimmed(out, " "));
}

bool is_clean_part_name(std::string_view name) {
  if (name.empty() || name.size() > kMaxPartName || name.front() == ' ' || name.back() == ' ')
    return false;
  for (size_t i = 0; i < name.size();) {
    const Decoded d = decode_utf8(name, i);
    if (d.length == 0 || is_control(d.code)) return false;
    i += d.length;
  }
  return true;
}

std::string_view Topology::part_name(int32_t id) const {
  auto it = std::lower_bound(part_names.begin(), part_names.end(), id,
                             [](const PartName& p, int32_t v) { return p.id < v; });
  return it != part_names.end() && it->id == id ? std::string_view(it->name) : std::string_view();
}

void Topology::set_part_name(int32_t id, std::string_view raw) {
  std::string name = clean_part_name(raw);
  if (name.empty()) return;
  auto it = std::lower_bound(part_names.begin(), part_names.end(), id,
                             [](const PartName& p, int32_t v) { return p.id < v; });
  if (it != part_names.end() && it->id == id)
    it->name = std::move(name);
  else
    part_names.insert(it, PartName{id, std::move(name)});
}

}  // namespace dynpm
