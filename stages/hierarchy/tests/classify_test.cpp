// Branch or leaf: Celba's names, the material rule, the geometry rule, and the modes.
#include "stages/hierarchy/classify.h"

#include <gtest/gtest.h>

#include "stages/hierarchy/tests/test_meshes.h"

namespace sylva::hierarchy {
namespace {

std::vector<PartKind> kinds(const tree::SourceGeometry& g, ClassifyMode mode) {
  ClassifyOptions o;
  o.mode = mode;
  std::vector<PartKind> out;
  for (const PartClass& c : classify_parts(split_parts(g, 1e-5), g, o)) out.push_back(c.kind);
  return out;
}

TEST(Classify, CelbaNames) {
  EXPECT_EQ(class_from_name("tree/br0Trunk")->level, 0);
  EXPECT_EQ(class_from_name("tree/br0Trunk")->kind, PartKind::kBranch);
  EXPECT_EQ(class_from_name("br12x")->level, 12);
  EXPECT_EQ(class_from_name("a/BR2")->level, 2);  // case-insensitive
  EXPECT_EQ(class_from_name("x/lf_1")->kind, PartKind::kLeaf);
  EXPECT_FALSE(class_from_name("branch").has_value());  // no level digits
  EXPECT_FALSE(class_from_name("leaf").has_value());
  EXPECT_FALSE(class_from_name("br0/trunk").has_value());  // only the last component counts
  EXPECT_FALSE(class_from_name("br999").has_value());
}

TEST(Classify, MaterialMarksLeavesByAlphaModeOnly) {
  tree::SourceGeometry g;
  g.materials.resize(4);
  g.materials[1].alpha_mode = tree::AlphaMode::kBlend;
  g.materials[2].alpha_mode = tree::AlphaMode::kMask;
  g.materials[3].base_color_image = 0;  // opaque with an RGBA PNG: glTF ignores the alpha
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string(17, '\0');
  png += '\x06';  // colour type 6: RGBA
  g.images.push_back({"forest_texture.png", "image/png", png});
  EXPECT_FALSE(material_marks_leaf(g, 0));
  EXPECT_TRUE(material_marks_leaf(g, 1));
  EXPECT_TRUE(material_marks_leaf(g, 2));
  EXPECT_FALSE(material_marks_leaf(g, 3));
  EXPECT_FALSE(material_marks_leaf(g, 4));  // out of range
  g.primitives.resize(1);
  g.primitives[0].material = 3;
  EXPECT_FALSE(materials_signal_leaves(g));
  g.primitives[0].material = 2;
  EXPECT_TRUE(materials_signal_leaves(g));
}

TEST(Classify, Modes) {
  using K = PartKind;
  const auto named = testing::named_tree();
  const std::vector<K> tree_kinds{K::kBranch, K::kBranch, K::kBranch, K::kLeaf, K::kLeaf};
  EXPECT_EQ(kinds(named, ClassifyMode::kAuto), tree_kinds);
  EXPECT_EQ(kinds(named, ClassifyMode::kNames), tree_kinds);
  const auto nameless = testing::nameless_tree();
  EXPECT_EQ(kinds(nameless, ClassifyMode::kAuto), tree_kinds);
  EXPECT_EQ(kinds(nameless, ClassifyMode::kMaterial), tree_kinds);
  EXPECT_EQ(kinds(nameless, ClassifyMode::kGeometry), tree_kinds);  // 20 x 10 cm quads: small, flat
  EXPECT_EQ(kinds(nameless, ClassifyMode::kNames), std::vector<K>(5, K::kSkipped));
  ClassifyOptions o;
  o.mode = ClassifyMode::kGeometry;
  o.leaf_max_size = 0.1;  // the quads are 0.2 m long: too big for leaves now
  const auto parts = split_parts(nameless, 1e-5);
  EXPECT_EQ(classify_parts(parts, nameless, o)[3].kind, K::kBranch);
  // auto with a material signal: a masked part is a leaf only when also small and flat (Pine_1's
  // masked bark), an opaque part is bark even when small and flat.
  auto masked_bark = nameless;
  masked_bark.materials[0].alpha_mode = tree::AlphaMode::kMask;
  EXPECT_EQ(kinds(masked_bark, ClassifyMode::kAuto), tree_kinds);
  EXPECT_EQ(kinds(masked_bark, ClassifyMode::kMaterial), std::vector<K>(5, K::kLeaf));
  auto opaque_leaves = nameless;
  opaque_leaves.materials[1].alpha_mode = tree::AlphaMode::kOpaque;  // no signal: geometry alone
  EXPECT_EQ(kinds(opaque_leaves, ClassifyMode::kAuto), tree_kinds);
  auto one_masked = nameless;  // opaque quads beside masked ones: the opaque ones are bark
  one_masked.primitives[1].material = 0;
  one_masked.primitives.push_back(testing::leaves("tree/masked"));
  EXPECT_EQ(kinds(one_masked, ClassifyMode::kAuto),
            (std::vector<K>{K::kBranch, K::kBranch, K::kBranch, K::kBranch, K::kBranch, K::kLeaf, K::kLeaf}));
  // Names give the level.
  const auto named_classes = classify_parts(split_parts(named, 1e-5), named, {});
  EXPECT_EQ(named_classes[0].level, 0);
  EXPECT_EQ(named_classes[2].level, 1);
}

}  // namespace
}  // namespace sylva::hierarchy
