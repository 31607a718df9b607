// XML tags as the VTK XML readers (.vtu, .pvd) need them: a small scanner that knows tags and
// attributes, nothing else (no DTD, no namespaces; text between tags is the caller's).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace dynpm::io {

struct Tag {
  std::string_view name;
  std::string_view attributes;
  bool closing = false, empty = false;
  size_t begin = 0, end = 0;  // the '<' and one past the '>'
};

class XmlScanner {
 public:
  explicit XmlScanner(std::string_view text) : text_(text) {}

  // The next start, end or empty-element tag; comments, <?…?> and <!…> are skipped. false at the
  // end of the text or on a tag that never closes (error() says so).
  bool next(Tag& tag);

  void seek(size_t pos) { pos_ = pos; }
  const std::string& error() const { return error_; }
  size_t error_at() const { return error_at_; }

 private:
  bool broken(size_t at, const char* cause) {
    error_ = cause;
    error_at_ = at;
    return false;
  }

  std::string_view text_;
  size_t pos_ = 0;
  std::string error_;
  size_t error_at_ = 0;
};

// The value of attribute `key` in a tag's attribute text, entities (&lt; …) replaced.
std::optional<std::string> attribute(const Tag& tag, std::string_view key);

}  // namespace dynpm::io
