// Branch or leaf: which parts of an imported mesh are bark and which are leaf cards, and for
// branches the level Celba's names give (seed 000 §4.2.3–4.2.4: objects named `br<level>*` are
// branches of that level, `lf*` leaves). docs/stages/hierarchy.md, "Branch or leaf".
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "libs/tree/source_geometry.h"
#include "stages/hierarchy/parts.h"

namespace sylva::hierarchy {

// auto: a Celba name where the primitive has one, else the material (when it marks a leaf),
// else the geometry. names: Celba's rule alone (other parts are skipped, as the thesis does).
// material: leaf when the material marks one, else branch. geometry: leaf when small and flat.
enum class ClassifyMode : std::uint8_t { kAuto, kNames, kMaterial, kGeometry };

enum class PartKind : std::uint8_t { kBranch, kLeaf, kSkipped };

struct ClassifyOptions {
  ClassifyMode mode = ClassifyMode::kAuto;
  double leaf_max_size = 1.0;  // m: a geometric leaf's longest principal extent is at most this
  double leaf_flatness = 0.1;  // a geometric leaf's thinnest / middle principal extent is below it
};

struct PartClass {
  PartKind kind = PartKind::kSkipped;
  std::int32_t level = -1;  // a branch's level from its name; -1 when the name gives none
};

// What a primitive's name says by Celba's rule: its last path component ("a/b/br2Twig" ->
// "br2Twig"), case-insensitive: `br<digits>...` a branch of that level, `lf...` a leaf; nullopt
// for any other name (and for a level above 255).
std::optional<PartClass> class_from_name(std::string_view primitive_name);

// True when the material marks leaf cards: alpha mode mask or blend, or a base colour image that
// is a PNG with an alpha channel (colour type 4 or 6) or a tRNS chunk.
bool material_marks_leaf(const tree::SourceGeometry& g, std::uint32_t material);

// One class per part, in the order of `parts`.
std::vector<PartClass> classify_parts(const std::vector<Part>& parts, const tree::SourceGeometry& g,
                                      const ClassifyOptions& options);

}  // namespace sylva::hierarchy
