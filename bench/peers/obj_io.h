// Small OBJ reader/writer shared by the peer drivers and hausdorff_cgal (bench/peers only).
//
// Reads `v x y z` and `f a b c [d ...]` lines (also `a/t/n` corner forms and negative indices);
// everything else is ignored. Every face is turned into triangles:
//   - triangle: kept as is;
//   - quad a b c d: split into two triangles along its SHORTER diagonal
//     (|ac| <= |bd| gives abc + acd, otherwise abd + bcd; orientation kept);
//   - polygon with more than 4 corners: fan from its first corner (none in our inputs).
// Vertices are kept exactly as in the file (no welding, unreferenced ones included).
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace peers {

using Vec3 = std::array<double, 3>;
using Tri = std::array<std::uint32_t, 3>;

struct TriSoup {
  std::vector<Vec3> V;
  std::vector<Tri> F;
  std::size_t faces_in = 0;  // faces in the file (a quad counts once)
  std::size_t quads_in = 0;  // quads split in two
  std::size_t polys_in = 0;  // faces with more than 4 corners, fanned
};

inline double dist2(const Vec3& a, const Vec3& b) {
  const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

namespace detail {

inline void skip_ws(const char*& p, const char* e) {
  while (p < e && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
}

inline bool parse_double(const char*& p, const char* e, double& out) {
  skip_ws(p, e);
  if (p < e && *p == '+') ++p;
  auto r = std::from_chars(p, e, out);
  if (r.ec != std::errc()) return false;
  p = r.ptr;
  return true;
}

// Parses one face corner ("12", "12/3", "12//5", "-1/2/3"); returns false at end of line.
inline bool parse_corner(const char*& p, const char* e, long long& out) {
  skip_ws(p, e);
  if (p >= e || *p == '\n' || *p == '#') return false;
  auto r = std::from_chars(p, e, out);
  if (r.ec != std::errc()) return false;
  p = r.ptr;
  while (p < e && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;  // skip /vt/vn
  return true;
}

}  // namespace detail

// Returns an empty string on success, an error message otherwise.
inline std::string read_obj(const std::string& path, TriSoup& m) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot open " + path;
  std::string buf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* p = buf.data();
  const char* e = p + buf.size();
  std::vector<long long> poly;
  std::size_t line = 0;
  while (p < e) {
    ++line;
    const char* eol =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(e - p)));
    if (!eol) eol = e;
    detail::skip_ws(p, eol);
    if (eol - p >= 2 && p[0] == 'v' && (p[1] == ' ' || p[1] == '\t')) {
      p += 2;
      Vec3 v{};
      for (double& c : v)
        if (!detail::parse_double(p, eol, c))
          return path + ":" + std::to_string(line) + ": bad vertex";
      m.V.push_back(v);
    } else if (eol - p >= 2 && p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) {
      p += 2;
      poly.clear();
      long long idx = 0;
      while (detail::parse_corner(p, eol, idx)) {
        long long i = idx > 0 ? idx - 1 : static_cast<long long>(m.V.size()) + idx;
        if (idx == 0 || i < 0 || i >= static_cast<long long>(m.V.size()))
          return path + ":" + std::to_string(line) + ": face index out of range";
        poly.push_back(i);
      }
      if (poly.size() < 3) return path + ":" + std::to_string(line) + ": face with < 3 corners";
      ++m.faces_in;
      auto u = [&](std::size_t k) { return static_cast<std::uint32_t>(poly[k]); };
      if (poly.size() == 3) {
        m.F.push_back({u(0), u(1), u(2)});
      } else if (poly.size() == 4) {
        ++m.quads_in;
        if (dist2(m.V[u(0)], m.V[u(2)]) <= dist2(m.V[u(1)], m.V[u(3)])) {
          m.F.push_back({u(0), u(1), u(2)});
          m.F.push_back({u(0), u(2), u(3)});
        } else {
          m.F.push_back({u(0), u(1), u(3)});
          m.F.push_back({u(1), u(2), u(3)});
        }
      } else {
        ++m.polys_in;
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) m.F.push_back({u(0), u(k), u(k + 1)});
      }
    }
    p = eol + 1;
  }
  if (m.V.empty() || m.F.empty()) return path + ": no vertices or faces";
  return {};
}

// Writes a triangle mesh (positions with %.9g: round-trips floats, near-exact for doubles).
inline std::string write_obj(const std::string& path, const std::vector<Vec3>& V,
                             const std::vector<Tri>& F) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return "cannot write " + path;
  std::vector<char> buf(1 << 20);
  std::setvbuf(f, buf.data(), _IOFBF, buf.size());
  std::fprintf(f, "# %zu vertices, %zu triangles\n", V.size(), F.size());
  for (const Vec3& v : V) std::fprintf(f, "v %.9g %.9g %.9g\n", v[0], v[1], v[2]);
  for (const Tri& t : F) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  const bool ok = std::fclose(f) == 0;
  return ok ? std::string() : "error writing " + path;
}

// Drops vertices no triangle references, renumbering the triangles.
inline void compact(std::vector<Vec3>& V, std::vector<Tri>& F) {
  std::vector<std::uint32_t> map(V.size(), UINT32_MAX);
  std::vector<Vec3> out;
  out.reserve(V.size());
  for (Tri& t : F)
    for (std::uint32_t& i : t) {
      if (map[i] == UINT32_MAX) {
        map[i] = static_cast<std::uint32_t>(out.size());
        out.push_back(V[i]);
      }
      i = map[i];
    }
  V.swap(out);
}

}  // namespace peers
