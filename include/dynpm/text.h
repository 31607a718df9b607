// dynpm/text.h — text from files: one number rule for every text reader (OBJ, PLY, VTK, VTU,
// PVD, FRD), and file bytes shown safely in messages.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace dynpm {

// How a token of text failed to be a number.
enum class NumberError { kNone, kNotANumber, kOutOfRange };

// A real number: the whole token ("2x", "1.5.3" and "" are not numbers), an optional sign ('+'
// too), decimal or exponent form, inf and nan. A value beyond the double range becomes ±inf and
// one below it ±0, the nearest value, as a cast to float does beyond the float range: 1e39 is
// read as inf in every format alike, and validation reports a non-finite position.
NumberError parse_real(std::string_view token, double& out);
// An integer: the whole token, decimal digits with an optional sign, within [lo, hi].
NumberError parse_integer(std::string_view token, int64_t lo, int64_t hi, int64_t& out);
// A count: parse_integer within [0, 2^63 - 1].
NumberError parse_count(std::string_view token, uint64_t& out);

// `text` with & < > " as XML entities, for an attribute value or element text (SVG, VTU).
std::string xml_escaped(std::string_view text);

// `s` without the spaces and tabs at either end (fixed-column fields, HTTP header values).
std::string_view trim_blanks(std::string_view s);

// Bytes from a file as a message may show them: printable ASCII as it is, and well-formed UTF-8
// characters from U+00A0 on that show as themselves (é, µ, …; not the C1 controls, nor the
// invisible ones that reorder text); '\n', '\r', '\t' and '\\' escaped, every other byte as \xNN,
// so that a message never carries a terminal escape sequence or a NUL; at most kQuotedBytes
// bytes, then "… (N bytes)".
inline constexpr size_t kQuotedBytes = 80;
std::string printable(std::string_view bytes);
// printable() in single quotes (not std::quoted, which ADL would find for a std::string): 'abc'.
std::string quoted_bytes(std::string_view bytes);

}  // namespace dynpm
