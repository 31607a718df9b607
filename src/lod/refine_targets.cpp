// Refine requests (docs/selective.md "Requests"): their one parser, and the splits each wants
// on the fully refined mesh at a time step.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>

#include "dynpm/lod.h"
#include "step_position.h"

namespace dynpm {
namespace {

std::optional<double> to_number(std::string_view s) {
  double x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(x)) return std::nullopt;
  return x;
}

// Comma-separated numbers, or nullopt when one is not a number.
std::optional<std::vector<double>> number_list(std::string_view s) {
  std::vector<double> out;
  while (true) {
    const size_t comma = s.find(',');
    auto x = to_number(s.substr(0, comma));
    if (!x) return std::nullopt;
    out.push_back(*x);
    if (comma == std::string_view::npos) return out;
    s.remove_prefix(comma + 1);
  }
}

Status bad(std::string_view text, const std::string& problem) {
  return Status::error("'" + std::string(text) + "': " + problem);
}

double value_at(const ProgressiveField& f, size_t i, double t) {
  const size_t last = f.values.size() - 1;
  t = std::clamp(t, 0.0, double(last));
  const size_t t0 = static_cast<size_t>(std::floor(t)), t1 = std::min(t0 + 1, last);
  const double a = t - double(t0), x0 = f.values[t0][i];
  return a == 0 ? x0 : x0 + a * (f.values[t1][i] - x0);
}

// view:KEY=VALUE;… (docs/selective.md "View-dependent").
Result<RefineTarget> parse_view(std::string_view text, std::string_view rest) {
  RefineTarget r;
  r.kind = RefineTarget::Kind::kView;
  ViewRequest& view = r.view;
  std::vector<std::string_view> seen;
  const std::string syntax =
      "a view is view:EYE=x,y,z;AT=x,y,z;FOV=deg;H=px;PX=p (and UP=x,y,z, W=px, BUDGET=vertices)";
  while (!rest.empty()) {
    const size_t end = rest.find(';');
    const std::string_view item = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    const size_t eq = item.find('=');
    if (eq == std::string_view::npos)
      return bad(text, "'" + std::string(item) + "' is not KEY=VALUE: " + syntax);
    const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
    if (std::find(seen.begin(), seen.end(), key) != seen.end())
      return bad(text, std::string(key) + " is given twice");
    seen.push_back(key);
    const auto xs = number_list(value);
    std::array<double, 3>* point = key == "EYE"  ? &view.eye
                                   : key == "AT" ? &view.at
                                   : key == "UP" ? &view.up
                                                 : nullptr;
    if (point) {
      if (!xs || xs->size() != 3) return bad(text, std::string(key) + " needs 3 numbers x,y,z");
      std::copy(xs->begin(), xs->end(), point->begin());
      continue;
    }
    double* number = key == "FOV"  ? &view.fov
                     : key == "W"  ? &view.width
                     : key == "H"  ? &view.height
                     : key == "PX" ? &view.pixels
                                   : nullptr;
    if (!number && key != "BUDGET")
      return bad(text, "unknown key '" + std::string(key) + "': " + syntax);
    if (!xs || xs->size() != 1) return bad(text, std::string(key) + " needs one number");
    const double x = xs->front();
    if (key == "BUDGET") {
      if (x < 1 || x != std::floor(x) || x > double(UINT32_MAX))
        return bad(text, "BUDGET is a vertex count, a whole number ≥ 1");
      view.budget = static_cast<uint64_t>(x);
    } else {
      *number = x;
    }
  }
  for (std::string_view key : {"EYE", "AT", "FOV", "H", "PX"})
    if (std::find(seen.begin(), seen.end(), key) == seen.end())
      return bad(text, "no " + std::string(key) + ": " + syntax);
  if (!(view.fov > 0 && view.fov < 180)) return bad(text, "FOV is in degrees, in (0, 180)");
  if (view.height < 1 || view.width < 0 || (view.width > 0 && view.width < 1))
    return bad(text, "W and H are pixels, at least 1");
  if (!(view.pixels > 0)) return bad(text, "PX, the tolerance in pixels, must be > 0");
  const std::array<double, 3> d = {view.at[0] - view.eye[0], view.at[1] - view.eye[1],
                                   view.at[2] - view.eye[2]};
  const std::array<double, 3>& u = view.up;
  const double cx = d[1] * u[2] - d[2] * u[1], cy = d[2] * u[0] - d[0] * u[2],
               cz = d[0] * u[1] - d[1] * u[0];
  if (d[0] == 0 && d[1] == 0 && d[2] == 0) return bad(text, "EYE and AT are the same point");
  if (cx == 0 && cy == 0 && cz == 0)
    return bad(text, "UP is along the view direction (or zero): give another UP");
  return r;
}

}  // namespace

Result<RefineTarget> parse_refine_target(std::string_view text) {
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos)
    return bad(text, "a request is KIND:VALUES, KIND one of box, sphere, part, field, moved, view");
  const std::string_view kind = text.substr(0, colon), rest = text.substr(colon + 1);
  RefineTarget r;
  if (kind == "box" || kind == "sphere") {
    const bool box = kind == "box";
    r.kind = box ? RefineTarget::Kind::kBox : RefineTarget::Kind::kSphere;
    const auto xs = number_list(rest);
    if (!xs || xs->size() != (box ? 6u : 4u))
      return bad(text, box ? "a box is box:X0,Y0,Z0,X1,Y1,Z1 (6 numbers)"
                           : "a sphere is sphere:X,Y,Z,R (4 numbers)");
    std::copy(xs->begin(), xs->end(), r.box.begin());
    if (box && (r.box[0] > r.box[3] || r.box[1] > r.box[4] || r.box[2] > r.box[5]))
      return bad(text, "the box's first corner must be its smallest (X0 ≤ X1, Y0 ≤ Y1, Z0 ≤ Z1)");
    if (!box && r.box[3] < 0) return bad(text, "a sphere's radius cannot be negative");
    return r;
  }
  if (kind == "part") {
    r.kind = RefineTarget::Kind::kPart;
    const auto xs = number_list(rest);
    if (!xs) return bad(text, "parts are part:ID,ID,... (whole numbers)");
    for (double x : *xs) {
      if (x != std::floor(x) || x < INT32_MIN || x > INT32_MAX)
        return bad(text, "a part id is a whole number, got " + std::to_string(x));
      r.parts.push_back(static_cast<int32_t>(x));
    }
    return r;
  }
  if (kind == "field") {
    r.kind = RefineTarget::Kind::kField;
    const size_t op = rest.find_first_of("<>");
    if (op == std::string_view::npos || op == 0)
      return bad(text, "a field request is field:NAME>V or field:NAME<V");
    r.field = std::string(rest.substr(0, op));
    r.above = rest[op] == '>';
    const auto x = to_number(rest.substr(op + 1));
    if (!x)
      return bad(text, "the threshold after '" + std::string(1, rest[op]) + "' is not a number");
    r.threshold = *x;
    return r;
  }
  if (kind == "moved") {
    r.kind = RefineTarget::Kind::kMoved;
    const auto x = rest.starts_with('>') ? to_number(rest.substr(1)) : std::nullopt;
    if (!x || *x < 0) return bad(text, "a displacement request is moved:>D, D ≥ 0");
    r.threshold = *x;
    return r;
  }
  if (kind == "view") return parse_view(text, rest);
  return bad(text, "unknown kind '" + std::string(kind) +
                       "': use box, sphere, part, field, moved or view");
}

Result<ElsewhereLevel> parse_elsewhere(std::string_view text) {
  ElsewhereLevel level;
  if (text.starts_with("error:")) {
    const auto x = to_number(text.substr(6));
    if (!x || *x < 0) return bad(text, "error:E needs a number E ≥ 0 (absolute units)");
    level.error = *x;
  } else if (text.ends_with('%')) {
    const auto x = to_number(text.substr(0, text.size() - 1));
    if (!x || *x <= 0 || *x > 100) return bad(text, "a ratio is a percentage in (0, 100]");
    level.ratio = *x / 100;
  } else {
    const auto x = to_number(text);
    if (!x || *x < 1 || *x != std::floor(*x) || *x > UINT32_MAX)
      return bad(text, "give a ratio (5%), a vertex count (20000) or an error (error:0.01)");
    level.vertices = static_cast<uint64_t>(*x);
  }
  return level;
}

uint32_t elsewhere_splits(const ProgressiveMesh& mesh, const ElsewhereLevel& level) {
  double vertices = 0;
  if (level.error) return std::min(level_of_error(mesh, *level.error), mesh.split_count());
  if (level.ratio) vertices = std::round(*level.ratio * mesh.full_vertex_count);
  if (level.vertices) vertices = double(*level.vertices);
  const double k = vertices - mesh.base_vertex_count;
  return k <= 0 ? 0 : static_cast<uint32_t>(std::min<double>(k, mesh.split_count()));
}

RefineTargets::RefineTargets(const ProgressiveMesh& mesh, const SplitDependencies& deps)
    : mesh_(&mesh), deps_(&deps) {
  Navigator full(mesh);
  full.set_level(mesh.split_count());
  full_faces_.assign(full.faces().begin(), full.faces().end());
}

Status RefineTargets::select(const RefineTarget& target, double t, std::vector<uint8_t>& vertices,
                             std::vector<uint8_t>& faces) const {
  const ProgressiveMesh& m = *mesh_;
  vertices.assign(m.vertex_count(), 0);
  faces.assign(full_faces_.size(), 0);
  bool by_face = false;  // the target picks faces (their corners follow), else vertices
  switch (target.kind) {
    case RefineTarget::Kind::kView:
      return Status::error("a view request selects splits, not vertices: see view_splits()");
    case RefineTarget::Kind::kBox:
    case RefineTarget::Kind::kSphere: {
      const auto& b = target.box;
      for (uint32_t v = 0; v < m.vertex_count(); ++v) {
        const auto p = position_at(m, v, t);
        if (target.kind == RefineTarget::Kind::kBox) {
          vertices[v] = p[0] >= b[0] && p[1] >= b[1] && p[2] >= b[2] && p[0] <= b[3] &&
                        p[1] <= b[4] && p[2] <= b[5];
        } else {
          const double dx = p[0] - b[0], dy = p[1] - b[1], dz = p[2] - b[2];
          vertices[v] = dx * dx + dy * dy + dz * dz <= b[3] * b[3];
        }
      }
      break;
    }
    case RefineTarget::Kind::kMoved:
      for (uint32_t v = 0; v < m.vertex_count(); ++v) {
        const auto p = position_at(m, v, t), q = position_at(m, v, 0);
        const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        vertices[v] = std::sqrt(dx * dx + dy * dy + dz * dz) > target.threshold;
      }
      break;
    case RefineTarget::Kind::kPart:
      by_face = true;
      for (int32_t id : target.parts)
        if (std::find(m.part_ids.begin(), m.part_ids.end(), id) == m.part_ids.end())
          return Status::error("part:" + std::to_string(id) + ": the model has no part " +
                               std::to_string(id));
      for (uint32_t f = 0; f < full_faces_.size(); ++f)
        faces[f] = std::find(target.parts.begin(), target.parts.end(), m.part_ids[f]) !=
                   target.parts.end();
      break;
    case RefineTarget::Kind::kField: {
      const auto it = std::find_if(m.fields.begin(), m.fields.end(),
                                   [&](const auto& f) { return f.info.name == target.field; });
      if (it == m.fields.end()) {
        std::string names;
        for (const ProgressiveField& f : m.fields)
          names += (names.empty() ? "" : ", ") + f.info.name;
        return Status::error("field:" + target.field + ": the model has no field '" + target.field +
                             "' (it has " + (names.empty() ? "none" : names) + ")");
      }
      by_face = it->info.location == FieldLocation::kElement;
      std::vector<uint8_t>& picked = by_face ? faces : vertices;
      for (size_t i = 0; i < picked.size(); ++i) {
        const double x = value_at(*it, i, t);
        picked[i] = target.above ? x > target.threshold : x < target.threshold;
      }
      break;
    }
  }
  for (uint32_t f = 0; f < full_faces_.size(); ++f) {
    if (by_face) {
      if (faces[f])
        for (uint32_t c : full_faces_[f].v)
          if (c != kNoVertex) vertices[c] = 1;
      continue;
    }
    bool all = true;
    for (uint32_t c : full_faces_[f].v) all = all && (c == kNoVertex || vertices[c]);
    faces[f] = all;
  }
  return {};
}

Status RefineTargets::mark(const RefineTarget& target, double t,
                           std::vector<uint8_t>& splits) const {
  if (target.kind == RefineTarget::Kind::kView) {
    for (const auto& [error, i] : view_splits(target.view, t)) splits[i] = 1;
    return {};
  }
  std::vector<uint8_t> vertices, faces;
  DYNPM_RETURN_IF_ERROR(select(target, t, vertices, faces));
  const uint32_t b = mesh_->base_vertex_count;
  for (uint32_t v = b; v < vertices.size(); ++v)
    if (vertices[v]) splits[v - b] = 1;
  for (uint32_t f = 0; f < faces.size(); ++f)
    if (faces[f] && deps_->last_writer[f] != kNoIndex) splits[deps_->last_writer[f]] = 1;
  return {};
}

Result<std::vector<uint8_t>> RefineTargets::request(const ElsewhereLevel& elsewhere,
                                                    std::span<const RefineTarget> targets,
                                                    double t) const {
  std::vector<uint8_t> splits(mesh_->split_count(), 0);
  for (const RefineTarget& target : targets)
    if (target.kind != RefineTarget::Kind::kView) DYNPM_RETURN_IF_ERROR(mark(target, t, splits));
  close_under_dependencies(*deps_, splits, elsewhere_splits(*mesh_, elsewhere));
  // Views last, by decreasing screen error, each split with its closure: a budget stops them
  // when the vertices reach it (the last closure may pass it).
  for (const RefineTarget& target : targets)
    if (target.kind == RefineTarget::Kind::kView) add_view(target.view, t, splits);
  return splits;
}

}  // namespace dynpm
