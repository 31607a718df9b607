// Wavefront OBJ: the subset that carries FE shell meshes. Triangles and quads stay as they are;
// `g` groups and `o` objects become part ids (a group named "part_12" or "12" is part 12, other
// names get the next free number in order of appearance and are the part's name). Written for speed
// (a 1 M-face file in well under a second): one pass over the bytes, numbers by text.h's rule
// (std::from_chars on whole tokens), no per-line allocation.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "formats.h"

namespace dynpm::io {
namespace {

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

inline const char* skip_spaces(const char* p, const char* end) {
  while (p < end && is_space(*p)) ++p;
  return p;
}

inline const char* token_end(const char* p, const char* end) {
  while (p < end && !is_space(*p)) ++p;
  return p;
}

// The next blank-separated token as a coordinate (text.h: parse_real, one rule for every text
// reader). An empty token means the line ended. The common case, a float that ends at a blank,
// is read in one pass; anything else goes through parse_real (huge values: inf).
inline NumberError parse_float(const char*& p, const char* end, float& out,
                               std::string_view& token) {
  p = skip_spaces(p, end);
  auto [next, ec] = std::from_chars(p, end, out);
  if (ec == std::errc() && next != p && (next == end || is_space(*next))) {
    p = next;
    return NumberError::kNone;
  }
  const char* stop = token_end(p, end);
  token = std::string_view(p, static_cast<size_t>(stop - p));
  double value = 0;
  const NumberError e = parse_real(token, value);
  if (e != NumberError::kNone) return e;
  out = static_cast<float>(value);  // past the float range: inf, which validation reports
  p = stop;
  return e;
}

// A face corner "i", "i/t", "i//n" or "i/t/n"; only i matters, a whole integer.
inline bool parse_corner(const char*& p, const char* end, int64_t& index) {
  auto [next, ec] = std::from_chars(p, end, index);  // the common case in one pass
  if (ec != std::errc() || next == p || (next < end && !is_space(*next) && *next != '/')) {
    const char* slash = std::find(p, token_end(p, end), '/');
    if (parse_integer(std::string_view(p, static_cast<size_t>(slash - p)), INT64_MIN + 1, INT64_MAX,
                      index) != NumberError::kNone)
      return false;
    next = slash;
  }
  const char* stop = token_end(next, end);
  for (const char* q = next; q < stop; ++q)
    if (*q != '/' && *q != '-' && *q != '+' && (*q < '0' || *q > '9')) return false;
  p = stop;
  return true;
}

bool is_binary_garbage(const char* p, const char* end) {
  for (; p < end; ++p) {
    const unsigned char c = static_cast<unsigned char>(*p);
    if ((c < 0x20 && !is_space(*p)) || c == 0x7f) return true;
  }
  return false;
}

class PartNames {
 public:
  int32_t id_of(std::string_view name) {
    if (name.empty()) return 0;
    std::string_view digits = name;
    if (digits.substr(0, 5) == "part_") digits.remove_prefix(5);
    int32_t id = 0;
    auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
    if (ec == std::errc() && p == digits.data() + digits.size()) {
      used_.insert(id);
      return id;
    }
    auto it = named_.find(std::string(name));
    if (it != named_.end()) return it->second;
    int32_t next = 1;
    while (used_.count(next)) ++next;
    used_.insert(next);
    named_.emplace(std::string(name), next);
    return next;
  }

  // The names of the parts that hold faces.
  void name_parts(Topology& topology) const {
    const std::vector<int32_t> parts = topology.parts();
    for (const auto& [name, id] : named_)
      if (std::binary_search(parts.begin(), parts.end(), id)) topology.set_part_name(id, name);
  }

 private:
  std::map<std::string, int32_t> named_;
  std::set<int32_t> used_;
};

}  // namespace

Result<std::optional<double>> time_from_comment(std::string_view comment) {
  for (size_t at = comment.find("time"); at != std::string_view::npos;
       at = comment.find("time", at + 4)) {
    const char* p = comment.data() + at + 4;
    const char* end = comment.data() + comment.size();
    if (p < end && *p == '=') ++p;
    p = skip_spaces(p, end);
    std::string_view token(p, static_cast<size_t>(token_end(p, end) - p));
    if (!token.empty() && (token.back() == ',' || token.back() == ';' || token.back() == ')'))
      token.remove_suffix(1);
    double t = 0;
    if (parse_real(token, t) != NumberError::kNone) continue;  // words, not a time note
    if (!std::isfinite(t))
      return Status::error("the time note " + quoted_bytes(token) + " is not a finite number");
    return std::optional<double>(t);
  }
  return std::optional<double>();
}

Status add_polygon(std::span<const uint32_t> corners, int32_t part, int64_t element_id,
                   uint32_t place, const std::string& where, const ReadOptions& options,
                   ParsedMesh& mesh, size_t& split_count) {
  const size_t n = corners.size();
  if (n < 3)
    return Status::error(where + ": a face needs at least 3 corners, this one has " +
                         std::to_string(n));
  if (n <= 4) {
    Face f;
    std::copy(corners.begin(), corners.end(), f.v.begin());
    mesh.topology.add_face(f, part, element_id);
    mesh.face_places.push_back(place);
    return {};
  }
  if (!options.split_polygons)
    return Status::error(where + ": a face with " + std::to_string(n) +
                         " corners; dynpm takes triangles and quads (pass --split-polygons to "
                         "fan-split larger polygons)");
  for (size_t i = 1; i + 1 < n; ++i) {
    mesh.topology.add_triangle(corners[0], corners[i], corners[i + 1], part,
                               i == 1 ? element_id : 0);
    mesh.face_places.push_back(place);
  }
  ++split_count;
  return {};
}

namespace {

// ---------------------------------------------------------------------------------------------
// parse_obj()'s phases

// The faces' corners as 0-based vertices: an index counts from 1, a negative one back from the
// last vertex so far. Corners past the vertices so far are allowed (a later 'v' may define
// them); needs_later_check says the face must be checked once every vertex is known. where()
// gives the place for a message (made only then: this runs for every face).
template <class Where>
Status face_corners(std::span<const int64_t> raw, int64_t vertex_count, const Where& where,
                    std::vector<uint32_t>& corners, bool& needs_later_check) {
  corners.clear();
  needs_later_check = false;
  for (int64_t index : raw) {
    if (index == 0) return Status::error(where() + ": face index 0 (OBJ counts from 1)");
    const int64_t zero_based = index > 0 ? index - 1 : vertex_count + index;
    if (zero_based < 0)
      return Status::error(where() + ": relative index " + std::to_string(index) +
                           " reaches before the first vertex");
    if (zero_based >= 0xfffffffeLL)
      return Status::error(where() + ": face index " + std::to_string(index) + " is too large");
    needs_later_check |= zero_based >= vertex_count;
    corners.push_back(static_cast<uint32_t>(zero_based));
  }
  return {};
}

// The faces that named a vertex past the ones before them, (face, line): every corner must be a
// vertex once the file has been read.
Status check_forward_corners(std::span<const std::pair<uint32_t, int64_t>> forward,
                             const Topology& topology, uint32_t vertex_count,
                             const std::string& path) {
  for (auto [face, face_line] : forward) {
    for (uint32_t c : topology.faces[face].v) {
      if (c != kNoVertex && c >= vertex_count)
        return Status::error(path + ":" + std::to_string(face_line) + ": face index " +
                             std::to_string(c + 1) + " is past the last vertex (" +
                             std::to_string(vertex_count) + ")");
    }
  }
  return {};
}

// The lines that start with 'f': the faces, give or take split polygons. Counted first (a few ms
// for a million faces), as the arrays grown past an estimate from the file's size were copied.
// At most one per 8 bytes ("f 1 2 3" and its line end): a file of bare 'f' lines, which fails
// at its first, reserves no more than a file of faces could fill.
size_t face_lines(std::string_view text) {
  size_t count = 0;
  for (const char* p = text.data(); p < text.data() + text.size();) {
    count += *p == 'f';
    const auto left = static_cast<size_t>(text.data() + text.size() - p);
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', left));
    if (!eol) break;
    p = eol + 1;
  }
  return std::min(count, text.size() / 8);
}

}  // namespace

Result<ParsedMesh> parse_obj(std::string_view text, const std::string& path,
                             const ReadOptions& options, FaceParsing faces) {
  const bool parse_faces = faces == FaceParsing::kParse;
  ParsedMesh mesh;
  mesh.places_are_lines = true;
  PartNames parts;
  int32_t part = 0;
  std::set<std::string, std::less<>> ignored;
  size_t split_count = 0;
  bool seen_data = false;
  std::vector<int64_t> raw;  // raw corner indices of the current face
  std::vector<uint32_t> corners;
  // (face, line) with indices past the vertices seen so far
  std::vector<std::pair<uint32_t, int64_t>> forward;
  ByteHash faces_hash;  // of the f and g lines, each as written

  mesh.positions.reserve(text.size() / 24);
  if (parse_faces) mesh.topology.reserve_faces(face_lines(text));

  // 1. One pass over the lines: v, f and g statements; a time note in a comment before them;
  //    the rest skipped.
  const char* p = text.data();
  const char* const end = p + text.size();
  uint32_t line = 0;
  while (p < end) {
    ++line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    if (!eol) eol = end;
    const char* q = skip_spaces(p, eol);
    const char* line_start = p;
    p = eol + 1;
    if (q == eol) continue;
    auto where = [&] { return path + ":" + std::to_string(line); };

    if (*q == '#') {
      if (!seen_data && !mesh.time) {
        auto time = time_from_comment(std::string_view(q, static_cast<size_t>(eol - q)));
        if (!time) return Status::error(where() + ": " + time.message());
        mesh.time = *time;
      }
      continue;
    }
    const char* kw_end = q;
    while (kw_end < eol && !is_space(*kw_end)) ++kw_end;
    const std::string_view keyword(q, static_cast<size_t>(kw_end - q));
    q = kw_end;

    if (keyword == "v") {
      seen_data = true;
      float xyz[3];
      for (float& c : xyz) {
        std::string_view token;
        if (parse_float(q, eol, c, token) == NumberError::kNone) continue;
        if (token.empty())
          return Status::error(where() + ": a vertex needs three numbers (v x y z)");
        return Status::error(where() + ": vertex coordinate " + quoted_bytes(token) +
                             " is not a number");
      }
      mesh.positions.insert(mesh.positions.end(), xyz, xyz + 3);
    } else if (keyword == "f") {
      seen_data = true;
      faces_hash.add(
          std::string_view(line_start, static_cast<size_t>(std::min(eol + 1, end) - line_start)));
      if (!parse_faces) continue;
      raw.clear();
      for (q = skip_spaces(q, eol); q < eol; q = skip_spaces(q, eol)) {
        int64_t index = 0;
        if (!parse_corner(q, eol, index))
          return Status::error(
              where() + ": face corner " +
              quoted_bytes(std::string_view(q, static_cast<size_t>(token_end(q, eol) - q))) +
              " is not i, i/t, i//n or i/t/n (whole numbers)");
        raw.push_back(index);
      }
      bool needs_later_check = false;
      DYNPM_RETURN_IF_ERROR(face_corners(raw, static_cast<int64_t>(mesh.positions.size() / 3),
                                         where, corners, needs_later_check));
      const auto first_face = static_cast<uint32_t>(mesh.topology.faces.size());
      DYNPM_RETURN_IF_ERROR(
          add_polygon(corners, part, 0, line, where(), options, mesh, split_count));
      // A split polygon adds several faces: every one of them waits for the check.
      if (needs_later_check)
        for (uint32_t f = first_face; f < mesh.topology.faces.size(); ++f)
          forward.emplace_back(f, line);
    } else if (keyword == "g" || keyword == "o") {
      faces_hash.add(
          std::string_view(line_start, static_cast<size_t>(std::min(eol + 1, end) - line_start)));
      if (!parse_faces) continue;
      q = skip_spaces(q, eol);
      const char* name_end = eol;
      while (name_end > q && is_space(name_end[-1])) --name_end;
      part = parts.id_of(std::string_view(q, static_cast<size_t>(name_end - q)));
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vp" || keyword == "s" ||
               keyword == "usemtl" || keyword == "mtllib") {
      // Texture coordinates, normals, smoothing groups and materials do not
      // describe an FE shell; skip them silently.
    } else {
      if (is_binary_garbage(line_start, eol))
        return Status::error(where() + ": binary data in a text OBJ file");
      if (ignored.insert(std::string(keyword)).second && options.warn)
        options.warn(where() + ": OBJ statement " + quoted_bytes(keyword) +
                     " ignored (only v, f, g and o carry a shell mesh)");
    }
  }

  // 2. The faces that named a later vertex, checked now that every vertex is known.
  const auto vertex_count = static_cast<uint32_t>(mesh.positions.size() / 3);
  DYNPM_RETURN_IF_ERROR(check_forward_corners(forward, mesh.topology, vertex_count, path));
  // 3. A mesh needs both; vertices are numbered 1, 2, … as OBJ counts them.
  if (vertex_count == 0) return Status::error(path + ": no vertices (no 'v x y z' line)");
  if (parse_faces && mesh.topology.faces.empty())
    return Status::error(path + ": no faces (no 'f' line)");
  if (split_count && options.warn)
    options.warn(path + ": " + std::to_string(split_count) +
                 " faces with more than 4 corners split into triangle fans");

  mesh.topology.vertex_count = vertex_count;
  mesh.faces_hash = faces_hash.value();
  if (!parse_faces) return mesh;
  mesh.topology.node_ids.resize(vertex_count);
  for (uint32_t i = 0; i < vertex_count; ++i) mesh.topology.node_ids[i] = int64_t{i} + 1;
  parts.name_parts(mesh.topology);
  return mesh;
}

std::string write_obj(const Topology& topology, std::span<const float> positions,
                      const WriteOptions& options) {
  std::string out;
  out.reserve(positions.size() * 10 + topology.faces.size() * 32);
  if (!options.comment.empty()) out += "# " + options.comment + "\n";
  out += "# " + std::to_string(topology.vertex_count) + " vertices, " +
         std::to_string(topology.faces.size()) + " faces (" +
         std::to_string(topology.quad_count()) + " quads, " +
         std::to_string(topology.triangle_count()) + " triangles)\n";
  char buffer[32];
  auto append_number = [&](auto value) {
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, end);
  };
  for (size_t i = 0; i + 2 < positions.size(); i += 3) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(positions[i + k]);  // shortest text that reads back to the same float
    }
    out += '\n';
  }
  const bool write_groups =
      topology.parts().size() > 1 || (!topology.part_ids.empty() && topology.part_ids[0] != 0);
  int64_t current_part = int64_t{INT32_MIN} - 1;
  for (size_t fi = 0; fi < topology.faces.size(); ++fi) {
    if (write_groups && topology.part_ids[fi] != current_part) {
      current_part = topology.part_ids[fi];
      out += "g part_";
      append_number(current_part);
      out += '\n';
    }
    out += 'f';
    for (uint32_t c : topology.faces[fi].v) {
      if (c == kNoVertex) break;
      out += ' ';
      append_number(c + 1);
    }
    out += '\n';
  }
  return out;
}

}  // namespace dynpm::io
