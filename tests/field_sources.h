// Result fields for the progressive tests: a FrameSource that adds fields to another one — a node
// field computed from the positions, or an element field that averages a node field over each
// face's corners (a stand-in for a solver's element result where the input has none).
#pragma once

#include <cmath>
#include <functional>
#include <span>
#include <vector>

#include "dynpm/core.h"

namespace dynpm::test {

class WithFields final : public FrameSource {
 public:
  using Read = std::function<Status(size_t t, std::span<float> out)>;

  WithFields(const FrameSource& inner, const Topology& topology)
      : inner_(inner), topology_(topology) {}

  uint32_t vertex_count() const override { return inner_.vertex_count(); }
  size_t step_count() const override { return inner_.step_count(); }
  double step_time(size_t t) const override { return inner_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    return inner_.read_step(t, out);
  }
  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> all = inner_.fields();
    for (const auto& [info, read] : extra_) all.push_back(info);
    return all;
  }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    const size_t own = inner_.fields().size();
    return field < own ? inner_.read_field(field, t, out) : extra_[field - own].second(t, out);
  }

  // A node field: value(x, y, z, t) at each vertex.
  void add_node_field(const std::string& name, std::function<float(const float*, size_t)> value) {
    extra_.push_back({{name, FieldLocation::kNode, "1"}, [this, value](size_t t, auto out) {
                        std::vector<float> xyz(size_t{vertex_count()} * 3);
                        DYNPM_RETURN_IF_ERROR(inner_.read_step(t, xyz));
                        for (size_t v = 0; v < out.size(); ++v) out[v] = value(&xyz[v * 3], t);
                        return Status{};
                      }});
  }
  // An element field: the mean of node field `node_field` (an index into fields()) over each
  // face's corners.
  void add_element_mean(const std::string& name, size_t node_field) {
    extra_.push_back(
        {{name, FieldLocation::kElement, "MPa"}, [this, node_field](size_t t, auto out) {
           std::vector<float> nodes(vertex_count());
           DYNPM_RETURN_IF_ERROR(read_field(node_field, t, nodes));
           for (size_t f = 0; f < out.size(); ++f) {
             const Face& face = topology_.faces[f];
             double sum = 0;
             for (int c = 0; c < face.degree(); ++c) sum += nodes[face.v[c]];
             out[f] = static_cast<float>(sum / face.degree());
           }
           return Status{};
         }});
  }

 private:
  const FrameSource& inner_;
  const Topology& topology_;
  std::vector<std::pair<FieldInfo, Read>> extra_;
};

}  // namespace dynpm::test
