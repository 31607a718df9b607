// Topology, Frames and bounding boxes: the plain data every module shares.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "components.h"
#include "dynpm/core.h"

namespace dynpm {

bool Face::contains(uint32_t vertex) const {
  return std::find(v.begin(), v.end(), vertex) != v.end();
}

Topology Topology::with_vertices(uint32_t n) {
  Topology t;
  t.vertex_count = n;
  t.node_ids.resize(n);
  for (uint32_t i = 0; i < n; ++i) t.node_ids[i] = int64_t{i} + 1;
  return t;
}

void Topology::reserve_faces(size_t count) {
  faces.reserve(count);
  part_ids.reserve(count);
  element_ids.reserve(count);
}

void Topology::add_face(const Face& face, int32_t part, int64_t element_id) {
  if (element_id == 0) element_id = element_ids.empty() ? 1 : element_ids.back() + 1;
  faces.push_back(face);
  part_ids.push_back(part);
  element_ids.push_back(element_id);
}

void Topology::add_triangle(uint32_t a, uint32_t b, uint32_t c, int32_t part, int64_t element_id) {
  add_face(Face{{a, b, c, kNoVertex}}, part, element_id);
}

void Topology::add_quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d, int32_t part,
                        int64_t element_id) {
  add_face(Face{{a, b, c, d}}, part, element_id);
}

size_t Topology::triangle_count() const {
  return static_cast<size_t>(std::count_if(faces.begin(), faces.end(), [](const Face& f) {
    return f.is_triangle() && f.degree() == 3;
  }));
}

void Topology::release_faces() {
  std::vector<Face>().swap(faces);  // `= {}` would keep the capacity
  std::vector<int32_t>().swap(part_ids);
  std::vector<int64_t>().swap(element_ids);
}

size_t Topology::quad_count() const {
  return static_cast<size_t>(
      std::count_if(faces.begin(), faces.end(), [](const Face& f) { return f.degree() == 4; }));
}

std::vector<int32_t> Topology::parts() const {
  // Faces come in runs of one part, and models have few parts: a sorted list of those seen,
  // without a copy of every face's id and its sort (50 ms a call at a million faces). Past a
  // thousand parts, the copy and sort, which bounds the time whatever the file holds.
  constexpr size_t kFewParts = 1024;
  std::vector<int32_t> ids;
  for (size_t f = 0; f < part_ids.size(); ++f) {
    const int32_t id = part_ids[f];
    if (f > 0 && id == part_ids[f - 1]) continue;
    const auto at = std::lower_bound(ids.begin(), ids.end(), id);
    if (at != ids.end() && *at == id) continue;
    if (ids.size() == kFewParts) {
      ids = part_ids;
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      return ids;
    }
    ids.insert(at, id);
  }
  return ids;
}

void Frames::add_step(std::vector<float> xyz, double time) {
  steps_.push_back(std::move(xyz));
  times_.push_back(time);
}

Status Frames::read_step(size_t t, std::span<float> out) const {
  assert(t < steps_.size());
  if (out.size() != steps_[t].size()) {
    return Status::error("time step " + std::to_string(t) + " holds " +
                         std::to_string(steps_[t].size() / 3) + " vertices, expected " +
                         std::to_string(out.size() / 3));
  }
  std::memcpy(out.data(), steps_[t].data(), out.size() * sizeof(float));
  return {};
}

const char* to_string(FieldLocation location) {
  return location == FieldLocation::kElement ? "element" : "node";
}

std::vector<std::string> FrameSource::field_names() const {
  std::vector<std::string> names;
  for (const FieldInfo& field : fields()) names.push_back(field.name);
  return names;
}

Status FrameSource::read_field(size_t field, size_t /*t*/, std::span<float> /*out*/) const {
  return Status::error("this input has no result field " + std::to_string(field));
}

Result<Animation> load_all_steps(AnimationStream stream) {
  assert(stream.frames);
  Animation animation;
  animation.topology = std::move(stream.topology);
  const FrameSource& source = *stream.frames;
  animation.frames.set_vertex_count(source.vertex_count());
  for (size_t t = 0; t < source.step_count(); ++t) {
    std::vector<float> xyz(size_t{source.vertex_count()} * 3);
    DYNPM_RETURN_IF_ERROR(source.read_step(t, xyz));
    animation.frames.add_step(std::move(xyz), source.step_time(t));
  }
  const std::vector<FieldInfo> infos = source.fields();
  for (size_t f = 0; f < infos.size(); ++f) {
    ScalarField field{infos[f].name, {}, infos[f].location, infos[f].unit};
    const size_t count = infos[f].location == FieldLocation::kElement
                             ? animation.topology.face_count()
                             : size_t{source.vertex_count()};
    for (size_t t = 0; t < source.step_count(); ++t) {
      std::vector<float> values(count);
      DYNPM_RETURN_IF_ERROR(source.read_field(f, t, values));
      field.steps.push_back(std::move(values));
    }
    animation.fields.push_back(std::move(field));
  }
  return animation;
}

void BoundingBox::extend(std::span<const float> xyz) {
  for (size_t i = 0; i + 2 < xyz.size(); i += 3) {
    const float* p = &xyz[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int k = 0; k < 3; ++k) {
      min[k] = empty ? p[k] : std::min(min[k], p[k]);
      max[k] = empty ? p[k] : std::max(max[k], p[k]);
    }
    empty = false;
  }
}

void BoundingBox::extend(const BoundingBox& other) {
  if (other.empty) return;
  if (empty) {
    *this = other;
    return;
  }
  for (int k = 0; k < 3; ++k) {
    min[k] = std::min(min[k], other.min[k]);
    max[k] = std::max(max[k], other.max[k]);
  }
}

double BoundingBox::diagonal() const {
  if (empty) return 0.0;
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    double d = double{max[k]} - double{min[k]};
    s += d * d;
  }
  return std::sqrt(s);
}

std::vector<uint32_t> connected_components(const Topology& topology, size_t& count) {
  const uint32_t n = topology.vertex_count;
  std::vector<uint32_t> root(n);
  for (uint32_t v = 0; v < n; ++v) root[v] = v;
  auto find = [&](uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const Face& f : topology.faces)  // a face's corners are one component
    for (int c = 1; c < f.degree(); ++c) root[find(f.v[c])] = find(f.v[0]);
  for (uint32_t v = 0; v < n; ++v) root[v] = find(v);
  std::vector<uint32_t> number(n, kNoVertex);  // root → component
  count = 0;
  for (uint32_t v = 0; v < n; ++v) {  // root[v] is read once, then holds v's component
    uint32_t& c = number[root[v]];
    if (c == kNoVertex) c = static_cast<uint32_t>(count++);
    root[v] = c;
  }
  return root;
}

}  // namespace dynpm
