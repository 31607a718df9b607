#include "json.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "dynpm/progressive.h"

namespace dynpm::cli {

void Json::key(std::string_view k) {
  if (!first_.empty()) {
    if (!first_.back()) out_ += ',';
    first_.back() = false;
    out_ += '\n';
    out_.append(first_.size() * 2, ' ');
  }
  if (!k.empty()) {
    quoted(k);
    out_ += ": ";
  }
}

void Json::quoted(std::string_view text) {
  out_ += '"';
  for (char c : text) {
    switch (c) {
      case '"': out_ += "\\\""; break;
      case '\\': out_ += "\\\\"; break;
      case '\n': out_ += "\\n"; break;
      case '\t': out_ += "\\t"; break;
      case '\r': out_ += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
          out_ += buffer;
        } else {
          out_ += c;
        }
    }
  }
  out_ += '"';
}

Json& Json::raw(std::string_view k, std::string_view json) {
  key(k);
  for (char c : json) {
    out_ += c;
    if (c == '\n') out_.append(first_.size() * 2, ' ');
  }
  return *this;
}

Json& Json::begin_object(std::string_view k) {
  key(k);
  out_ += '{';
  first_.push_back(true);
  return *this;
}

Json& Json::end_object() {
  const bool empty = first_.back();
  first_.pop_back();
  if (!empty) {
    out_ += '\n';
    out_.append(first_.size() * 2, ' ');
  }
  out_ += '}';
  if (first_.empty()) out_ += '\n';
  return *this;
}

Json& Json::begin_array(std::string_view k) {
  key(k);
  out_ += '[';
  first_.push_back(true);
  return *this;
}

Json& Json::end_array() {
  const bool empty = first_.back();
  first_.pop_back();
  if (!empty) {
    out_ += '\n';
    out_.append(first_.size() * 2, ' ');
  }
  out_ += ']';
  return *this;
}

Json& Json::value(std::string_view k, std::string_view text) {
  key(k);
  quoted(text);
  return *this;
}

Json& Json::value(std::string_view k, double number) {
  key(k);
  if (!std::isfinite(number)) {
    out_ += "null";
    return *this;
  }
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, number);
  out_.append(buffer, end);
  return *this;
}

Json& Json::value(std::string_view k, int64_t number) {
  key(k);
  out_ += std::to_string(number);
  return *this;
}

Json& Json::value(std::string_view k, uint64_t number) {
  key(k);
  out_ += std::to_string(number);
  return *this;
}

Json& Json::value(std::string_view k, bool flag) {
  key(k);
  out_ += flag ? "true" : "false";
  return *this;
}

void json_field_range(Json& j, const ProgressiveField& field) {
  j.value("name", field.info.name);
  j.value("location", to_string(field.info.location));
  j.value("unit", field.info.unit);
  j.value("min", field.min);
  j.value("max", field.max);
}

}  // namespace dynpm::cli
