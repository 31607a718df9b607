// A small streaming JSON writer for --json output (objects, arrays, numbers, strings).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dynpm {
struct ProgressiveField;
}

namespace dynpm::cli {

class Json {
 public:
  Json& begin_object(std::string_view key = {});
  Json& end_object();
  Json& begin_array(std::string_view key = {});
  Json& end_array();
  Json& value(std::string_view key, std::string_view text);
  Json& value(std::string_view key, const char* text) { return value(key, std::string_view(text)); }
  Json& value(std::string_view key, double number);
  Json& value(std::string_view key, int64_t number);
  Json& value(std::string_view key, uint64_t number);
  Json& value(std::string_view key, int number) { return value(key, int64_t{number}); }
  Json& value(std::string_view key, bool flag);
  // A JSON value made by another Json (an object, say), indented to fit here.
  Json& raw(std::string_view key, std::string_view json);
  // Array elements.
  Json& item(std::string_view text) { return value({}, text); }
  Json& item(double number) { return value({}, number); }
  Json& item(int64_t number) { return value({}, number); }

  const std::string& str() const { return out_; }

 private:
  void key(std::string_view k);
  void quoted(std::string_view text);

  std::string out_;
  std::vector<bool> first_;  // per open container: no element written yet
};

// A .dpm's field as 'info --json' and the catalogue show it: "name", "location", "unit", "min",
// "max" (into the object the caller has begun).
void json_field_range(Json& j, const ProgressiveField& field);

}  // namespace dynpm::cli
