// XML tags (xml_tags.h).
#include "xml_tags.h"

#include <cctype>
#include <utility>

namespace dynpm::io {
namespace {

std::string unescape_xml(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '&') {
      static const std::pair<std::string_view, char> kEntities[] = {
          {"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
      bool done = false;
      for (const auto& [entity, c] : kEntities)
        if (s.compare(i, entity.size(), entity) == 0) {
          out += c;
          i += entity.size() - 1;
          done = true;
          break;
        }
      if (done) continue;
    }
    out += s[i];
  }
  return out;
}

}  // namespace

bool XmlScanner::next(Tag& tag) {
  while (true) {
    const size_t open = text_.find('<', pos_);
    if (open == std::string_view::npos) return false;
    if (text_.compare(open, 4, "<!--") == 0) {
      const size_t close = text_.find("-->", open + 4);
      if (close == std::string_view::npos) return broken(open, "a comment never ends");
      pos_ = close + 3;
      continue;
    }
    if (text_.compare(open, 2, "<?") == 0 || text_.compare(open, 2, "<!") == 0) {
      const size_t close = text_.find('>', open);
      if (close == std::string_view::npos) return broken(open, "a tag never ends");
      pos_ = close + 1;
      continue;
    }
    // The '>' that ends the tag, outside quoted attribute values.
    size_t i = open + 1;
    char quote = 0;
    for (; i < text_.size(); ++i) {
      const char c = text_[i];
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '>') {
        break;
      }
    }
    if (i >= text_.size()) return broken(open, "a tag never ends");
    std::string_view body = text_.substr(open + 1, i - open - 1);
    tag = Tag();
    tag.begin = open;
    tag.end = i + 1;
    if (!body.empty() && body.front() == '/') {
      tag.closing = true;
      body.remove_prefix(1);
    }
    if (!body.empty() && body.back() == '/') {
      tag.empty = true;
      body.remove_suffix(1);
    }
    size_t n = 0;
    while (n < body.size() && !std::isspace(static_cast<unsigned char>(body[n]))) ++n;
    tag.name = body.substr(0, n);
    tag.attributes = body.substr(n);
    pos_ = tag.end;
    return true;
  }
}

std::optional<std::string> attribute(const Tag& tag, std::string_view key) {
  std::string_view a = tag.attributes;
  size_t i = 0;
  while (i < a.size()) {
    while (i < a.size() && std::isspace(static_cast<unsigned char>(a[i]))) ++i;
    const size_t name_start = i;
    while (i < a.size() && a[i] != '=' && !std::isspace(static_cast<unsigned char>(a[i]))) ++i;
    const std::string_view name = a.substr(name_start, i - name_start);
    while (i < a.size() && std::isspace(static_cast<unsigned char>(a[i]))) ++i;
    if (i >= a.size() || a[i] != '=') {
      if (name.empty()) break;
      continue;  // an attribute without a value
    }
    ++i;
    while (i < a.size() && std::isspace(static_cast<unsigned char>(a[i]))) ++i;
    if (i >= a.size() || (a[i] != '"' && a[i] != '\'')) break;
    const char quote = a[i++];
    const size_t value_end = a.find(quote, i);
    if (value_end == std::string_view::npos) break;
    if (name == key) return unescape_xml(a.substr(i, value_end - i));
    i = value_end + 1;
  }
  return std::nullopt;
}

}  // namespace dynpm::io
