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

TEST(Classify, MaterialMarksLeaves) {
  tree::SourceGeometry g;
  g.materials.resize(3);
  g.materials[1].alpha_mode = tree::AlphaMode::kBlend;
  g.materials[2].base_color_image = 0;
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string(17, '\0');
  png += '\x06';  // colour type 6: RGBA
  g.images.push_back({"leaf.png", "image/png", png});
  EXPECT_FALSE(material_marks_leaf(g, 0));
  EXPECT_TRUE(material_marks_leaf(g, 1));
  EXPECT_TRUE(material_marks_leaf(g, 2));
  g.images[0].bytes[25] = '\x02';  // RGB, no alpha
  EXPECT_FALSE(material_marks_leaf(g, 2));
  g.images[0].mime_type = "image/jpeg";
  g.images[0].bytes = "\xff\xd8\xff";
  EXPECT_FALSE(material_marks_leaf(g, 2));
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
  // Names give the level.
  const auto named_classes = classify_parts(split_parts(named, 1e-5), named, {});
  EXPECT_EQ(named_classes[0].level, 0);
  EXPECT_EQ(named_classes[2].level, 1);
}

}  // namespace
}  // namespace sylva::hierarchy
