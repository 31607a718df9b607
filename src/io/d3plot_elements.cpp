// LS-DYNA d3plot element results on the faces (d3plot_elements.h). The words of each element
// kind are described in d3plot_layout.h (ShellWords); solids write 6 stresses, the plastic
// strain and NEIPH history values at one point (NV3D = 7 + NEIPH); other solid layouts (several
// integration points, thermal words) are left out.
#include "d3plot_elements.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace dynpm::io::d3plot {
namespace {

// The integration point of `points` to read; -1 for the largest value over all of them.
// MAXINT = 3 writes mid, bottom, top; any other count goes from bottom to top.
int point_index(IntegrationPoint point, int points) {
  if (point == IntegrationPoint::kMax) return -1;
  if (points == 3)
    return point == IntegrationPoint::kMid ? 0 : point == IntegrationPoint::kBottom ? 1 : 2;
  if (point == IntegrationPoint::kBottom) return 0;
  if (point == IntegrationPoint::kTop) return points - 1;
  return (points - 1) / 2;  // an even count: the lower of the two middle points
}

const char* quantity_name(int q) {
  static constexpr const char* kNames[] = {"von Mises", "plastic strain", "thickness"};
  return kNames[q];
}

const char* kind_name(ElementKind kind) {
  switch (kind) {
    case ElementKind::kShell: return "shells";
    case ElementKind::kSolid: return "solids";
    case ElementKind::kThickShell: return "thick shells";
  }
  return "elements";
}

}  // namespace

bool ElementFields::Block::has(Quantity q) const {
  switch (q) {
    case Quantity::kVonMises: return stress && points > 0;
    case Quantity::kPlasticStrain: return plastic_strain && points > 0;
    case Quantity::kThickness: return thickness.has_value();
  }
  return false;
}

Result<ElementFields> ElementFields::make(const std::string& path, const Control& c,
                                          std::vector<FaceElement> faces, IntegrationPoint point,
                                          const std::function<void(const std::string&)>& warn) {
  ElementFields e;
  e.words_ = c.words;
  e.point_ = point;
  e.faces_ = std::move(faces);
  auto shell = shell_words(path, c);
  if (!shell) return shell.status();
  const ElementData at = element_data(c);
  // Shells: their words as the control block says.
  Block& shells = e.blocks_[size_t(ElementKind::kShell)];
  shells = {at.shells,        uint64_t(c.nel4), uint64_t(c.nv2d),      shell->points,
            shell->per_point, shell->stress,    shell->plastic_strain, shell->thickness};
  // Thick shells: the shells' integration points (and maybe 12 strains), nothing else.
  Block& thick = e.blocks_[size_t(ElementKind::kThickShell)];
  thick = {at.thick_shells, uint64_t(c.nelt), uint64_t(c.nv3dt), 0, 0, false, false, {}};
  const int64_t thick_points = int64_t{shell->points} * shell->per_point;
  if (c.nv3dt == thick_points || c.nv3dt == thick_points + 12) {
    thick.points = shell->points, thick.per_point = shell->per_point;
    thick.stress = shell->stress, thick.plastic_strain = shell->plastic_strain;
  }
  // Solids: one point of 6 stresses and the plastic strain, when that is all they write.
  Block& solids = e.blocks_[size_t(ElementKind::kSolid)];
  solids = {at.solids, uint64_t(c.nel8), uint64_t(c.nt3d + c.nv3d), 0, 0, false, false, {}};
  if (c.nt3d == 0 && c.nv3d >= 7 && c.nv3d == 7 + c.neiph)
    solids.points = 1, solids.per_point = static_cast<int>(c.nv3d), solids.stress = true,
    solids.plastic_strain = true;

  // One note per kind of element whose faces lack a field the others have.
  std::array<bool, 3> used{};
  for (const FaceElement& f : e.faces_) used[size_t(f.kind)] = true;
  std::array<std::string, 3> lacking;
  for (int q = 0; q < 3; ++q) {
    const Quantity quantity = static_cast<Quantity>(q);
    bool any = false;
    for (size_t kind = 0; kind < 3; ++kind) any |= used[kind] && e.blocks_[kind].has(quantity);
    if (!any) continue;
    e.fields_.push_back({quantity_name(q), FieldLocation::kElement, {}});
    e.quantities_.push_back(quantity);
    for (size_t kind = 0; kind < 3; ++kind)
      if (used[kind] && !e.blocks_[kind].has(quantity))
        lacking[kind] += std::string(lacking[kind].empty() ? "" : ", ") + quantity_name(q);
  }
  for (ElementKind kind : {ElementKind::kSolid, ElementKind::kThickShell}) {
    if (lacking[size_t(kind)].empty() || !warn) continue;
    const bool understood = e.blocks_[size_t(kind)].points > 0;
    warn(path + ": the faces of the " + kind_name(kind) + " show 0 for " + lacking[size_t(kind)] +
         (understood
              ? " (not written for them)"
              : " (their element data is not understood: " +
                    std::string(kind == ElementKind::kSolid ? "NV3D = " : "NV3DT = ") +
                    std::to_string(kind == ElementKind::kSolid ? c.nv3d : c.nv3dt) + " words)"));
  }
  return e;
}

float ElementFields::value(const Block& block, const char* element, Quantity q) const {
  const int ws = words_.size;
  auto word = [&](int k) { return words_.real(element + size_t(k) * ws); };
  if (q == Quantity::kThickness) return static_cast<float>(word(*block.thickness));
  auto at_point = [&](int k) {
    const int first = k * block.per_point;
    if (q == Quantity::kPlasticStrain) return word(first + (block.stress ? 6 : 0));
    const double xx = word(first), yy = word(first + 1), zz = word(first + 2);
    const double xy = word(first + 3), yz = word(first + 4), zx = word(first + 5);
    return std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)) +
                     3.0 * (xy * xy + yz * yz + zx * zx));
  };
  const int k = point_index(point_, block.points);
  if (k >= 0) return static_cast<float>(at_point(k));
  double largest = at_point(0);
  for (int p = 1; p < block.points; ++p) largest = std::max(largest, at_point(p));
  return static_cast<float>(largest);
}

Status ElementFields::read(size_t field, const StateWords& read_words, std::span<float> out) const {
  assert(field < fields_.size() && out.size() == faces_.size());
  const Quantity q = quantities_[field];
  const size_t ws = static_cast<size_t>(words_.size);
  std::array<std::vector<char>, 3> bytes;
  for (size_t kind = 0; kind < 3; ++kind) {
    const Block& block = blocks_[kind];
    if (!block.has(q) || block.count == 0) continue;
    if (std::none_of(faces_.begin(), faces_.end(),
                     [&](const FaceElement& f) { return size_t(f.kind) == kind; }))
      continue;
    bytes[kind].resize(block.count * block.words * ws);
    DYNPM_RETURN_IF_ERROR(read_words(block.start, block.count * block.words, bytes[kind].data()));
  }
  for (size_t i = 0; i < faces_.size(); ++i) {
    const FaceElement f = faces_[i];
    const Block& block = blocks_[size_t(f.kind)];
    out[i] = bytes[size_t(f.kind)].empty()
                 ? 0.0f
                 : value(block, bytes[size_t(f.kind)].data() + f.index * block.words * ws, q);
  }
  return {};
}

}  // namespace dynpm::io::d3plot
