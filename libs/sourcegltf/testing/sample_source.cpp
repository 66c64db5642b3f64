#include "libs/sourcegltf/testing/sample_source.h"

#include "tests/support/gltf_fixtures.h"

namespace sylva::sourcegltf::testing {

tree::SourceGeometry strip_and_leaf() {
  tree::SourceGeometry g;
  tree::SourcePrimitive bark;
  bark.name = "Tree/br0Trunk";
  bark.positions = {{1, 0, -0.05f}, {1, 0, 0.05f}, {1, 1, 0.05f}, {1, 1, -0.05f}};
  bark.indices = {0, 1, 2, 0, 2, 3};
  tree::SourcePrimitive leaf;
  leaf.name = "Tree/lf0";
  leaf.material = 1;
  leaf.positions = {{1, 1, 0}, {1.5f, 1, 0}, {1, 5, 0}};
  leaf.uvs = {{0, 1}, {1, 1}, {0, 0}};
  leaf.indices = {0, 1, 2};
  g.primitives = {bark, leaf};
  tree::SourceMaterial m0;
  m0.name = "BarkMat";
  m0.base_color = {0.3f, 0.2f, 0.1f, 1};
  tree::SourceMaterial m1;
  m1.name = "LeafMat";
  m1.base_color_image = 0;
  m1.alpha_mode = tree::AlphaMode::kMask;
  m1.double_sided = true;
  g.materials = {m0, m1};
  g.images = {{"leaf.png", "image/png", sylva::test::tiny_png()}};
  return g;
}

}  // namespace sylva::sourcegltf::testing
