#include "libs/tree/source_geometry.h"

#include <gtest/gtest.h>

#include <limits>

#include "libs/tree/tests/sample_tree.h"

namespace sylva::tree {
namespace {

using testing::sample_source;

std::string first_error(const SourceGeometry& g) {
  auto e = validate_source_geometry(g);
  return e.empty() ? std::string() : e.front();
}

TEST(SourceGeometry, SampleIsValid) {
  EXPECT_TRUE(validate_source_geometry(sample_source()).empty());
  EXPECT_TRUE(validate_source_geometry(SourceGeometry{}).empty());
}

// Each primitive invariant broken once, with its exact message.
TEST(SourceGeometry, PrimitiveMessages) {
  const float inf = std::numeric_limits<float>::infinity();
  SourceGeometry g = sample_source();
  g.primitives[1].indices = {0, 1, 2, 0};
  EXPECT_EQ(first_error(g), "source primitive 1 (\"tree/crown/lf_12\"): has 4 indices, not a multiple of 3");
  g = sample_source();
  g.primitives[0].indices[4] = 9;
  EXPECT_EQ(first_error(g),
            "source primitive 0 (\"tree/trunk/br0_trunk\"): index 9 at triangle 1 is not below 4 positions");
  g = sample_source();
  g.primitives[0].normals.pop_back();
  EXPECT_EQ(first_error(g), "source primitive 0 (\"tree/trunk/br0_trunk\"): 3 normals for 4 positions");
  g = sample_source();
  g.primitives[1].uvs.push_back({0, 0});
  EXPECT_EQ(first_error(g), "source primitive 1 (\"tree/crown/lf_12\"): 4 uvs for 3 positions");
  g = sample_source();
  g.primitives[2].positions[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(first_error(g), "source primitive 2 (\"tree/misc\"): position 1 is not finite");
  g = sample_source();
  g.primitives[0].normals[2].z = inf;
  EXPECT_EQ(first_error(g), "source primitive 0 (\"tree/trunk/br0_trunk\"): normal 2 is not finite");
  g = sample_source();
  g.primitives[0].normals[3] = {0, 0, 1.002f};  // 2e-3 off: over the 1e-3 tolerance
  EXPECT_EQ(first_error(g), "source primitive 0 (\"tree/trunk/br0_trunk\"): normal 3 is not unit length");
  g.primitives[0].normals[3] = {0, 0, 1.0005f};  // within it
  EXPECT_EQ(first_error(g), "");
  g = sample_source();
  g.primitives[1].uvs[0][1] = -inf;
  EXPECT_EQ(first_error(g), "source primitive 1 (\"tree/crown/lf_12\"): uv 0 is not finite");
  g = sample_source();
  g.primitives[2].material = 3;
  EXPECT_EQ(first_error(g), "source primitive 2 (\"tree/misc\"): material 3 is not below 3 materials");
}

TEST(SourceGeometry, MaterialAndImageMessages) {
  SourceGeometry g = sample_source();
  g.materials[1].base_color[3] = 1.5f;
  EXPECT_EQ(first_error(g), "source material 1 (\"Leaves\"): base colour components must be in [0, 1]");
  g = sample_source();
  g.materials[0].base_color[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(first_error(g), "source material 0 (\"Bark\"): base colour components must be in [0, 1]");
  g = sample_source();
  g.materials[1].alpha_cutoff = -0.1f;
  EXPECT_EQ(first_error(g), "source material 1 (\"Leaves\"): alpha cutoff must be in [0, 1]");
  g = sample_source();
  g.materials[2].alpha_mode = static_cast<AlphaMode>(7);
  EXPECT_EQ(first_error(g), "source material 2 (\"Haze\"): unknown alpha mode 7");
  g = sample_source();
  g.materials[2].base_color_image = 2;
  EXPECT_EQ(first_error(g), "source material 2 (\"Haze\"): base colour image 2 is not -1 or below 2 images");
  g.materials[2].base_color_image = -2;
  EXPECT_EQ(first_error(g), "source material 2 (\"Haze\"): base colour image -2 is not -1 or below 2 images");
  g = sample_source();
  g.images[1].mime_type = "image/webp";
  EXPECT_EQ(first_error(g),
            "source image 1 (\"leaf.jpg\"): mime type \"image/webp\" is not image/png or image/jpeg");
  g = sample_source();
  g.images[0].bytes.clear();
  EXPECT_EQ(first_error(g), "source image 0 (\"bark.png\"): has no bytes");
}

// A name over the stored limit is reported once, without quoting it in the prefix.
TEST(SourceGeometry, NameLimit) {
  SourceGeometry g = sample_source();
  g.primitives[0].name.assign(kMaxTextBytes, 'p');
  EXPECT_EQ(first_error(g), "");
  g.primitives[0].name.push_back('p');
  EXPECT_EQ(first_error(g), "source primitive 0: the name is 65537 bytes, at most 65536 are stored");
  g = sample_source();
  g.materials[1].name.assign(kMaxTextBytes + 1, 'm');
  EXPECT_EQ(first_error(g), "source material 1: the name is 65537 bytes, at most 65536 are stored");
  g = sample_source();
  g.images[0].name.assign(kMaxTextBytes + 1, 'i');
  EXPECT_EQ(first_error(g), "source image 0: the name is 65537 bytes, at most 65536 are stored");
}

// The totals over all primitives: one vertex or triangle past the limit is refused.
TEST(SourceGeometry, TotalLimits) {
  SourceGeometry g = sample_source();
  g.primitives[2].positions.resize(kMaxSourceVertices - 7);  // 4 + 3 + this = the limit
  EXPECT_EQ(first_error(g), "");
  g.primitives[2].positions.push_back({});
  EXPECT_EQ(first_error(g), "source geometry: 16777217 vertices, at most 16777216");
  g = sample_source();
  g.primitives[2].indices.resize(3 * (kMaxSourceTriangles - 3) + 3);  // 2 + 1 + this = limit + 1
  EXPECT_EQ(first_error(g), "source geometry: 16777217 triangles, at most 16777216");
}

// Every problem is listed until max_errors, then the checks stop.
TEST(SourceGeometry, StopsAfterMaxErrors) {
  SourceGeometry g = sample_source();
  for (auto& i : g.primitives[0].indices) i = 100;  // 6 bad indices
  g.images[0].bytes.clear();
  EXPECT_EQ(validate_source_geometry(g).size(), 7u);
  const auto two = validate_source_geometry(g, 2);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(
      two[1],
      "source primitive 0 (\"tree/trunk/br0_trunk\"): index 100 at triangle 0 is not below 4 positions");
}

// validate_tree() lists the source geometry's messages as they are, after the tree's own.
TEST(SourceGeometry, ValidateTreeIncludesThem) {
  Tree t = testing::sample_tree();
  t.source = sample_source();
  EXPECT_TRUE(validate_tree(t).empty());
  t.source.images[1].bytes.clear();
  t.leaves[0].variant = 4;
  const auto e = validate_tree(t);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0], "leaf 0: variant 4 is not a cell of the 2x2 leaf atlas");
  EXPECT_EQ(e[1], "source image 1 (\"leaf.jpg\"): has no bytes");
  EXPECT_EQ(validate_tree(t, 1).size(), 1u);
}

}  // namespace
}  // namespace sylva::tree
