// Branch or leaf. Celba's names come first because a modeller wrote them; they are often absent
// in files from other tools (glTF from Blender or ez-tree, FBX from SpeedTree), so two
// fallbacks follow: a leaf card is drawn with an alpha-tested or blended material (the cut-out
// is in the texture's alpha), and a leaf is small and flat where a branch is a tube (its two
// smaller principal extents are both about its diameter). Only the material's alpha mode counts:
// glTF ignores a texture's alpha under an opaque material, and atlas textures shared by bark and
// leaves (KayKit's forest_texture.png) are RGBA anyway. Neither rule is trusted alone in `auto`:
// files alpha-test their bark too (Quaternius Pine_1), so a masked part is a leaf only when it is
// also small and flat.
#include "stages/hierarchy/classify.h"

#include <algorithm>
#include <cctype>

#include "stages/hierarchy/part_geometry.h"

namespace sylva::hierarchy {

namespace {

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
  return true;
}

bool geometric_leaf(const Part& part, const ClassifyOptions& o) {
  const Principal pc = principal_axes(part.points);
  if (pc.extent[0] > o.leaf_max_size) return false;
  if (pc.extent[1] <= 0) return true;  // a sliver: degenerate, but never a tube
  return pc.extent[2] < o.leaf_flatness * pc.extent[1];
}

}  // namespace

std::optional<PartClass> class_from_name(std::string_view name) {
  const std::size_t slash = name.rfind('/');
  const std::string_view last = slash == std::string_view::npos ? name : name.substr(slash + 1);
  if (starts_with_nocase(last, "lf")) return PartClass{PartKind::kLeaf, -1};
  if (!starts_with_nocase(last, "br")) return std::nullopt;
  std::size_t i = 2;
  std::int32_t level = 0;
  while (i < last.size() && std::isdigit(static_cast<unsigned char>(last[i]))) {
    level = level * 10 + (last[i] - '0');
    if (level > 255) return std::nullopt;
    ++i;
  }
  if (i == 2) return std::nullopt;  // "branch", "bright": no level digits, not Celba's name
  return PartClass{PartKind::kBranch, level};
}

bool material_marks_leaf(const tree::SourceGeometry& g, std::uint32_t material) {
  if (material >= g.materials.size()) return false;
  return g.materials[material].alpha_mode != tree::AlphaMode::kOpaque;
}

bool materials_signal_leaves(const tree::SourceGeometry& g) {
  return std::any_of(g.primitives.begin(), g.primitives.end(),
                     [&](const tree::SourcePrimitive& p) { return material_marks_leaf(g, p.material); });
}

std::vector<PartClass> classify_parts(const std::vector<Part>& parts, const tree::SourceGeometry& g,
                                      const ClassifyOptions& o) {
  const bool material_signal = materials_signal_leaves(g);
  std::vector<PartClass> out;
  out.reserve(parts.size());
  for (const Part& part : parts) {
    const tree::SourcePrimitive& prim = g.primitives[part.primitive];
    const bool leaf_material = material_marks_leaf(g, prim.material);
    PartClass c;
    switch (o.mode) {
      case ClassifyMode::kNames:
        c = class_from_name(prim.name).value_or(PartClass{});
        break;
      case ClassifyMode::kMaterial:
        c.kind = leaf_material ? PartKind::kLeaf : PartKind::kBranch;
        break;
      case ClassifyMode::kGeometry:
        c.kind = geometric_leaf(part, o) ? PartKind::kLeaf : PartKind::kBranch;
        break;
      case ClassifyMode::kAuto:
        if (const auto named = class_from_name(prim.name)) {
          c = *named;
        } else {
          // With a material signal, an opaque part is bark and a masked one must also look like a
          // leaf; without one (every material opaque) the geometry decides alone.
          const bool leaf = (leaf_material || !material_signal) && geometric_leaf(part, o);
          c.kind = leaf ? PartKind::kLeaf : PartKind::kBranch;
        }
        break;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace sylva::hierarchy
