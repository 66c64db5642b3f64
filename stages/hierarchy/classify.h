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

// auto: a Celba name where the primitive has one; else, when some primitive's material marks a
// leaf (a material signal), a leaf when its material marks one AND it is small and flat; else
// (every material opaque) a leaf when small and flat. reconstruct() falls back to geometry when
// auto leaves no branch part. names: Celba's rule alone (other parts are skipped, as the thesis
// does). material: leaf when the material marks one, else branch. geometry: leaf when small and
// flat.
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

// True when the material marks leaf cards: its alpha mode is mask or blend. The texture's alpha is
// not read (glTF ignores it under an opaque material). False for a material index out of range.
bool material_marks_leaf(const tree::SourceGeometry& g, std::uint32_t material);

// True when some primitive's material marks leaf cards (auto's material signal).
bool materials_signal_leaves(const tree::SourceGeometry& g);

// One class per part, in the order of `parts`.
std::vector<PartClass> classify_parts(const std::vector<Part>& parts, const tree::SourceGeometry& g,
                                      const ClassifyOptions& options);

}  // namespace sylva::hierarchy
