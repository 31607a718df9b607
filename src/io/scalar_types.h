// The binary scalar types that PLY, legacy VTK and VTK XML share, each naming them its own way
// ("uchar", "UNSIGNED_CHAR", "UInt8"): their sizes, the values they hold, their bytes as a
// number, and a token of text read as one of them.
#pragma once

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "dynpm/text.h"

namespace dynpm::io {

enum class ScalarType {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64
};

inline bool is_real(ScalarType t) { return t == ScalarType::kFloat32 || t == ScalarType::kFloat64; }

inline size_t size_of(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
    case ScalarType::kUInt8: return 1;
    case ScalarType::kInt16:
    case ScalarType::kUInt16: return 2;
    case ScalarType::kInt32:
    case ScalarType::kUInt32:
    case ScalarType::kFloat32: return 4;
    default: return 8;
  }
}

// The values an integer type holds (ascii data must keep to them as binary data do); UInt64 up
// to INT64_MAX, as far as parse_integer reads.
inline std::pair<int64_t, int64_t> integer_range(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8: return {INT8_MIN, INT8_MAX};
    case ScalarType::kUInt8: return {0, UINT8_MAX};
    case ScalarType::kInt16: return {INT16_MIN, INT16_MAX};
    case ScalarType::kUInt16: return {0, UINT16_MAX};
    case ScalarType::kInt32: return {INT32_MIN, INT32_MAX};
    case ScalarType::kUInt32: return {0, UINT32_MAX};
    case ScalarType::kUInt64: return {0, INT64_MAX};
    default: return {INT64_MIN, INT64_MAX};
  }
}

template <class T>
double load_scalar(const void* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return static_cast<double>(v);
}

// The value of type t in the size_of(t) bytes at p, widened to double; `swap` when the file's
// byte order is not the machine's.
inline double load_scalar(ScalarType t, const void* p, bool swap) {
  switch (t) {
    case ScalarType::kInt8: return load_scalar<int8_t>(p, swap);
    case ScalarType::kUInt8: return load_scalar<uint8_t>(p, swap);
    case ScalarType::kInt16: return load_scalar<int16_t>(p, swap);
    case ScalarType::kUInt16: return load_scalar<uint16_t>(p, swap);
    case ScalarType::kInt32: return load_scalar<int32_t>(p, swap);
    case ScalarType::kUInt32: return load_scalar<uint32_t>(p, swap);
    case ScalarType::kInt64: return load_scalar<int64_t>(p, swap);
    case ScalarType::kUInt64: return load_scalar<uint64_t>(p, swap);
    case ScalarType::kFloat32: return load_scalar<float>(p, swap);
    case ScalarType::kFloat64: return load_scalar<double>(p, swap);
  }
  return 0;
}

// A token of ascii data as a value of type t, by the rule of every text reader (text.h): a real
// type takes parse_real's numbers, an integer type whole integers within its range, as its
// binary form could hold.
inline NumberError parse_scalar(std::string_view token, ScalarType t, double& out) {
  if (is_real(t)) return parse_real(token, out);
  const auto [lo, hi] = integer_range(t);
  int64_t n = 0;
  const NumberError e = parse_integer(token, lo, hi, n);
  out = static_cast<double>(n);
  return e;
}

// Appends v's bytes in the given byte order (PLY and VTU write little-endian, legacy VTK
// big-endian, as that format says).
template <class T>
void append_binary(std::string& out, T v, std::endian order) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (order != std::endian::native) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

// Appends v as the shortest text that reads back as v (to_chars), then `after`.
template <class T>
void append_text(std::string& out, T v, char after = ' ') {
  char b[32];
  auto [end, ec] = std::to_chars(b, b + sizeof b, v);
  out.append(b, end);
  out += after;
}

// How a token that parse_scalar() refused as not a number is described: "a number" or "a whole
// number".
inline const char* number_kind(ScalarType t) { return is_real(t) ? "a number" : "a whole number"; }

}  // namespace dynpm::io
