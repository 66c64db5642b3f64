// Every mesh in ../shared/data/meshes imports with exact counts and exact warnings, stands on
// the origin (foot at x = z = 0, min y = 0) and has the height its file gives it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "libs/fileio/file_source.h"
#include "stages/import/import_file.h"
#include "tests/support/test_support.h"

namespace sylva::import {
namespace {

namespace fs = std::filesystem;

struct Expected {
  const char* file;  // below meshes/
  std::size_t primitives, triangles, materials, images;
  double height;                      // m
  std::vector<std::string> warnings;  // with "<file>: warning: " cut off
};

void PrintTo(const Expected& e, std::ostream* os) { *os << e.file; }

class SharedMesh : public ::testing::TestWithParam<Expected> {};

TEST_P(SharedMesh, ImportsExactly) {
  const auto data = test::data_dir();
  if (!data || !fs::exists(*data / "meshes")) GTEST_SKIP() << "no shared meshes (SYLVA_DATA_DIR)";
  const Expected& e = GetParam();
  const fs::path file = *data / "meshes" / e.file;
  const ImportResult r = import_file(test::read_file(file), file.string(), {});
  const tree::SourceGeometry& g = r.tree.source;
  std::size_t triangles = 0;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& p : g.primitives) {
    triangles += p.indices.size() / 3;
    for (const auto& v : p.positions) {
      const float c[3] = {v.x, v.y, v.z};
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
    }
  }
  std::vector<std::string> warnings;
  const std::string prefix = file.string() + ": warning: ";
  const std::string dir = file.parent_path().string();
  for (std::string w : r.warnings) {
    if (w.rfind(prefix, 0) == 0) w = w.substr(prefix.size());
    for (std::size_t at; (at = w.find(dir)) != std::string::npos;) w.replace(at, dir.size(), "<dir>");
    warnings.push_back(w);
  }
  EXPECT_EQ(g.primitives.size(), e.primitives);
  EXPECT_EQ(triangles, e.triangles);
  EXPECT_EQ(g.materials.size(), e.materials);
  EXPECT_EQ(g.images.size(), e.images);
  EXPECT_NEAR(hi[1] - lo[1], e.height, 1e-3);  // the file's height, 1 mm
  EXPECT_NEAR(r.mesh.height, e.height, 1e-3);
  // The foot: min y = 0, and the bottom 1 % band's box centred on x = z = 0.
  EXPECT_EQ(lo[1], 0.f);
  float x0 = INFINITY, x1 = -INFINITY, z0 = INFINITY, z1 = -INFINITY;
  for (const auto& p : g.primitives)
    for (const auto& v : p.positions)
      if (v.y <= 0.01f * (hi[1] - lo[1]))
        x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), z0 = std::min(z0, v.z), z1 = std::max(z1, v.z);
  EXPECT_NEAR(x0 + x1, 0, 1e-4 * e.height);
  EXPECT_NEAR(z0 + z1, 0, 1e-4 * e.height);
  EXPECT_TRUE(tree::validate_tree(r.tree).empty());
  EXPECT_EQ(warnings, e.warnings);
}

INSTANTIATE_TEST_SUITE_P(
    Files, SharedMesh,
    ::testing::Values(
        Expected{"kaykit/Tree_1_A_Color1.gltf", 1, 530, 1, 1, 4.1607, {}},
        Expected{"kaykit/Tree_Bare_1_C_Color1.gltf", 1, 936, 1, 1, 5.2554, {}},
        Expected{"kenney/tree_oak_fall.glb",
                 2,
                 194,
                 2,
                 0,
                 1.2262,
                 {"scene root node 1 'tree_oak_fall' is a child of node 0 'tmpParent', which "
                  "the scene does not list: imported as a root, without that node's transform",
                  "2 degenerate triangle(s) (a repeated vertex or zero area) dropped, in "
                  "'tree_oak_fall/Mesh tree_oak_fall'"}},
        Expected{"kenney/tree_pineRoundA.glb",
                 2,
                 204,
                 2,
                 0,
                 1.3664,
                 {"scene root node 1 'tree_pineRoundA' is a child of node 0 'tmpParent', which "
                  "the scene does not list: imported as a root, without that node's "
                  "transform"}},
        // ez-tree writes its own units (the trunk's length parameter is 24).
        Expected{"eztree/aspen_small_seed36330.glb", 2, 3616, 2, 2, 38.9663, {}},
        Expected{"eztree/bush_2_seed45590.glb", 2, 4760, 2, 2, 30.8593, {}},
        Expected{"quaternius/Pine_1.gltf",
                 2,
                 3947,
                 2,
                 1,
                 7.3169,
                 {"image 'Bark_NormalTree.png' (image 1) of material 'Bark_NormalTree' could "
                  "not be read (no file 'Bark_NormalTree.png' beside the model): the material keeps its "
                  "colour, without the texture"}},
        Expected{"quaternius/DeadTree_1.obj",
                 1,
                 6169,
                 1,
                 0,
                 9.4955,
                 {"'C:/Bark_DeadTree.png' is an absolute path or leaves the model's folder: "
                  "looking for 'Bark_DeadTree.png' beside the model instead",
                  "2820 quad(s) and 0 polygon(s) of more than 4 sides triangulated",
                  "texture 'C:/Bark_DeadTree.png' of material 'Bark_DeadTree' could not be "
                  "read (no file 'Bark_DeadTree.png' beside the model): the material keeps its colour, "
                  "without the texture"}}),
    [](const auto& param_info) {
      std::string n = fs::path(param_info.param.file).stem().string();
      std::replace_if(
          n.begin(), n.end(), [](char c) { return !std::isalnum((unsigned char)c); }, '_');
      return n;
    });

}  // namespace
}  // namespace sylva::import
