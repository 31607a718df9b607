// LS-DYNA d3plot element results as fields on the faces: von Mises stress, effective plastic
// strain and thickness of the element each face comes from (a shell, or the solid or thick
// shell whose outer face it is), at the integration point the reader was asked for.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "d3plot_layout.h"
#include "dynpm/io.h"

namespace dynpm::io::d3plot {

enum class ElementKind : uint8_t { kShell, kSolid, kThickShell };

// The element a face stands for: its kind and its index among the elements of that kind.
struct FaceElement {
  ElementKind kind;
  uint32_t index;
};

// Reads n words from word `first` of a state on.
using StateWords = std::function<Status(uint64_t first, size_t n, char* out)>;

class ElementFields {
 public:
  // The element results the faces can show; warns (once each) about element kinds whose data
  // is not understood (left out) and about fields some faces lack (zero there).
  static Result<ElementFields> make(const std::string& path, const Control& control,
                                    std::vector<FaceElement> faces, IntegrationPoint point,
                                    const std::function<void(const std::string&)>& warn);

  // "von Mises", "plastic strain", "thickness": those the file writes.
  const std::vector<FieldInfo>& fields() const { return fields_; }
  // Fills out (one value per face) with field `field` of the state read through `words`.
  Status read(size_t field, const StateWords& words, std::span<float> out) const;

 private:
  enum class Quantity { kVonMises, kPlasticStrain, kThickness };
  // The words one kind of element writes per state, and which quantities they hold.
  struct Block {
    uint64_t start = 0;  // word of the first element in a state
    uint64_t count = 0;  // elements
    uint64_t words = 0;  // per element
    int points = 0, per_point = 0;
    bool stress = false, plastic_strain = false;
    std::optional<int> thickness;
    bool has(Quantity q) const;
  };

  float value(const Block& block, const char* element, Quantity q) const;

  Words words_;
  IntegrationPoint point_ = IntegrationPoint::kMid;
  std::array<Block, 3> blocks_;  // by ElementKind
  std::vector<FaceElement> faces_;
  std::vector<FieldInfo> fields_;
  std::vector<Quantity> quantities_;  // of fields_
};

}  // namespace dynpm::io::d3plot
