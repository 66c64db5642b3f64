// The glTF reader on small files built in memory with libs/gltf's writer (and edited as JSON
// where the writer has no option): transforms, quantisation, Draco, meshopt, texture transforms,
// modes, images, node selection, and bad input with its exact message.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "libs/gltf/writer.h"
#include "stages/import/mesh_import.h"
#include "stages/import/tests/mesh_test_files.h"

namespace sylva::import {
namespace {

using testing::MapFiles;
using testing::square;

MeshOptions keep_placement() {
  MeshOptions o;
  o.recenter = false;
  return o;
}

MeshImport import_glb(const gltf::Scene& s, const MeshOptions& o = keep_placement(),
                      const gltf::WriteOptions& w = {}) {
  MapFiles files;
  return import_mesh(gltf::encode(s, w), "gltf", "/m/t.glb", "t.glb", files, o);
}

gltf::Scene one_square() {
  gltf::Scene s;
  s.meshes.push_back({"sq", {square()}, {}, 0});
  s.nodes.push_back({.name = "tree", .mesh = 0});
  s.roots = {0};
  return s;
}

void expect_near(tree::Vec3f v, float x, float y, float z, float tol = 1e-5f) {
  EXPECT_NEAR(v.x, x, tol);
  EXPECT_NEAR(v.y, y, tol);
  EXPECT_NEAR(v.z, z, tol);
}

// Parent translate (1, 0, 0) scale 2, child rotated 90 degrees about y: world = T S R.
TEST(MeshGltf, NodeTransformChainApplied) {
  gltf::Scene s = one_square();
  s.nodes = {{.name = "root", .children = {1}, .translation = {1, 0, 0}, .scale = {2, 2, 2}},
             {.name = "tree", .mesh = 0, .rotation = {0, std::sqrt(0.5), 0, std::sqrt(0.5)}}};
  const MeshImport m = import_glb(s);
  ASSERT_EQ(m.geometry.primitives.size(), 1u);
  const tree::SourcePrimitive& p = m.geometry.primitives[0];
  EXPECT_EQ(p.name, "root/tree/sq");
  expect_near(p.positions[1], 1, 0, -2);  // (1,0,0) rotated to (0,0,-1), scaled, moved
  expect_near(p.positions[2], 1, 2, -2);
  expect_near(p.normals[0], 1, 0, 0);  // +z rotated to +x
  EXPECT_EQ(m.facts.triangles, 2u);
  EXPECT_TRUE(m.warnings.empty());
}

// A mirroring scale flips the winding back to counter-clockwise.
TEST(MeshGltf, MirrorFlipsWinding) {
  gltf::Scene s = one_square();
  s.nodes[0].scale = {-1, 1, 1};
  const MeshImport m = import_glb(s);
  EXPECT_EQ(m.geometry.primitives[0].indices, (std::vector<std::uint32_t>{0, 2, 1, 0, 3, 2}));
}

// Several primitives and materials; a primitive without one gets the appended "default".
TEST(MeshGltf, SeveralPrimitivesAndMaterials) {
  gltf::Scene s = one_square();
  s.materials = {{.name = "bark", .base_color = {0.5f, 0.4f, 0.3f, 1}}, {.name = "leaf"}};
  s.meshes[0].primitives = {square(0), square(1), square(-1)};
  const MeshImport m = import_glb(s);
  ASSERT_EQ(m.geometry.primitives.size(), 3u);
  ASSERT_EQ(m.geometry.materials.size(), 3u);
  EXPECT_EQ(m.geometry.materials[2].name, "default");
  EXPECT_EQ(m.geometry.primitives[2].material, 2u);
  EXPECT_EQ(m.geometry.materials[0].base_color, (std::array<float, 4>{0.5f, 0.4f, 0.3f, 1}));
  EXPECT_EQ(m.facts.triangles, 6u);
}

// KHR_mesh_quantization: integer positions (12 bits, node scale folded in), normalised normals
// and uvs come back within the quantisation step.
TEST(MeshGltf, QuantizedAttributes) {
  gltf::Scene s = one_square();
  s.materials = {{.name = "m"}};
  s.meshes[0].primitives[0].material = 0;
  gltf::WriteOptions w;
  w.quantize.enabled = true;
  w.quantize.position_bits = {12};
  const std::string bytes = gltf::encode(s, w);
  ASSERT_NE(bytes.find("KHR_mesh_quantization"), std::string::npos);
  MapFiles files;
  const MeshImport m = import_mesh(bytes, "gltf", "/m/q.glb", "q.glb", files, keep_placement());
  const tree::SourcePrimitive& p = m.geometry.primitives[0];
  expect_near(p.positions[2], 1, 1, 0, 1e-3f);
  expect_near(p.normals[2], 0, 0, 1, 1e-2f);
  EXPECT_NEAR(p.uvs[2][0], 1, 1e-3);
}

// Draco and meshopt compressed files (libs/gltf's encoders) decode to the same triangles.
TEST(MeshGltf, DracoAndMeshoptDecoded) {
  const gltf::Scene s = one_square();
  gltf::WriteOptions draco;
  draco.draco.enabled = true;
  gltf::WriteOptions meshopt;
  meshopt.meshopt = true;
  for (const gltf::WriteOptions& w : {draco, meshopt}) {
    const std::string bytes = gltf::encode(s, w);
    ASSERT_NE(bytes.find(w.meshopt ? "EXT_meshopt_compression" : "KHR_draco_mesh_compression"),
              std::string::npos);
    const MeshImport m = import_glb(s, keep_placement(), w);
    ASSERT_EQ(m.geometry.primitives.size(), 1u);
    const tree::SourcePrimitive& p = m.geometry.primitives[0];
    EXPECT_EQ(p.indices.size(), 6u);
    float top = 0;
    for (const auto& v : p.positions) top = std::max(top, v.y);
    EXPECT_NEAR(top, 1, 1e-3);
  }
}

// The .gltf JSON of a scene with one textured material, for edits.
nlohmann::json textured_json() {
  gltf::Scene s = one_square();
  s.images = {{"bark.png", "image/png", testing::tiny_png(), ""}};
  s.materials = {{.name = "bark", .base_color_texture = {.image = 0}}};
  s.meshes[0].primitives[0].material = 0;
  gltf::WriteOptions w;
  w.format = gltf::FileFormat::kGltf;
  return nlohmann::json::parse(gltf::encode(s, w));
}

// KHR_texture_transform (offset, rotation, scale) is baked into the uvs; the embedded image is
// kept byte for byte.
TEST(MeshGltf, TextureTransformBaked) {
  nlohmann::json j = textured_json();
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = {
      {"offset", {0.5, 0.25}}, {"scale", {2, 3}}, {"rotation", M_PI / 2}};
  j["extensionsUsed"] = {"KHR_texture_transform"};
  MapFiles files;
  const MeshImport m = import_mesh(j.dump(), "gltf", "/m/t.gltf", "t.gltf", files, keep_placement());
  const tree::SourcePrimitive& p = m.geometry.primitives[0];
  // uv (1, 1): scaled (2, 3), rotated 90 degrees counter-clockwise (-3, 2), offset (-2.5, 2.25).
  EXPECT_NEAR(p.uvs[2][0], -2.5, 1e-5);
  EXPECT_NEAR(p.uvs[2][1], 2.25, 1e-5);
  ASSERT_EQ(m.geometry.images.size(), 1u);
  EXPECT_EQ(m.geometry.images[0].bytes, testing::tiny_png());
  EXPECT_EQ(m.geometry.images[0].mime_type, "image/png");
  EXPECT_EQ(m.geometry.materials[0].base_color_image, 0);
}

// An external image that is not beside the model: a warning naming image and material; the
// material keeps its colour. One that is there is read through the FileSource.
TEST(MeshGltf, ExternalImages) {
  nlohmann::json j = textured_json();
  j["images"][0] = {{"uri", "bark%20tex.png"}};
  MapFiles files;
  const MeshImport missing = import_mesh(j.dump(), "gltf", "/m/t.gltf", "t.gltf", files, keep_placement());
  EXPECT_EQ(missing.warnings,
            (std::vector<std::string>{
                "t.gltf: warning: image 'bark tex.png' (image 0) of material 'bark' could "
                "not be read (no file 'bark tex.png' beside the model): the material keeps its "
                "colour, without the texture"}));
  EXPECT_EQ(missing.geometry.materials[0].base_color_image, -1);
  EXPECT_TRUE(missing.geometry.images.empty());
  files.files["/m/bark tex.png"] = testing::tiny_png();
  const MeshImport found = import_mesh(j.dump(), "gltf", "/m/t.gltf", "t.gltf", files, keep_placement());
  EXPECT_TRUE(found.warnings.empty());
  ASSERT_EQ(found.geometry.images.size(), 1u);
  EXPECT_EQ(found.geometry.images[0].name, "bark tex.png");
}

// A uri that climbs out of the model's folder is looked for beside the model, with a warning.
TEST(MeshGltf, EscapingUriLookedForBesideTheModel) {
  nlohmann::json j = textured_json();
  j["images"][0] = {{"uri", "../../etc/bark.png"}};
  MapFiles files;
  files.files["/m/bark.png"] = testing::tiny_png();
  files.files["/etc/bark.png"] = "secret";
  const MeshImport m = import_mesh(j.dump(), "gltf", "/m/t.gltf", "t.gltf", files, keep_placement());
  ASSERT_EQ(m.geometry.images.size(), 1u);
  EXPECT_EQ(m.geometry.images[0].bytes, testing::tiny_png());
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0],
            "t.gltf: warning: '../../etc/bark.png' is an absolute path or leaves the model's folder: looking "
            "for 'bark.png' beside the model instead");
}

// Strips and fans become lists; points and lines are skipped with a warning.
TEST(MeshGltf, ModesConvertedOrSkipped) {
  nlohmann::json j = textured_json();
  j["meshes"][0]["primitives"].push_back(j["meshes"][0]["primitives"][0]);
  j["meshes"][0]["primitives"].push_back(j["meshes"][0]["primitives"][0]);
  // Over indices 0 1 2 0 2 3: the strip's 4 triangles are (0 1 2) (2 1 0) (2 0 2) (2 0 3), the
  // fan's (1 2 0) (2 0 0) (0 2 0) (2 3 0): 3 are degenerate.
  j["meshes"][0]["primitives"][0]["mode"] = 5;
  j["meshes"][0]["primitives"][1]["mode"] = 6;
  j["meshes"][0]["primitives"][2]["mode"] = 1;  // lines
  MapFiles files;
  const MeshImport m = import_mesh(j.dump(), "gltf", "/m/t.gltf", "t.gltf", files, keep_placement());
  ASSERT_EQ(m.geometry.primitives.size(), 2u);
  EXPECT_EQ(m.geometry.primitives[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 0, 2, 0, 3}));
  EXPECT_EQ(m.geometry.primitives[1].indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0}));
  EXPECT_EQ(m.facts.triangles, 5u);
  EXPECT_EQ(m.warnings,
            (std::vector<std::string>{
                "t.gltf: warning: mesh 0 'sq' primitive 2 (in 'tree/sq'): mode 1 (points or lines) "
                "skipped: sylva imports triangles",
                "t.gltf: warning: 3 degenerate triangle(s) (a repeated vertex or zero area) dropped, "
                "in 'tree/sq', 'tree/sq'"}));
}

// `node` imports one subtree with its ancestors' transforms; an unknown name lists the nodes.
TEST(MeshGltf, NodeSelection) {
  gltf::Scene s = one_square();
  s.nodes = {{.name = "forest", .children = {1, 2}, .translation = {0, 5, 0}},
             {.name = "oak", .mesh = 0, .translation = {10, 0, 0}},
             {.name = "pine", .mesh = 0, .translation = {20, 0, 0}}};
  MeshOptions o = keep_placement();
  o.node = "pine";
  const MeshImport m = import_glb(s, o);
  ASSERT_EQ(m.geometry.primitives.size(), 1u);
  EXPECT_EQ(m.geometry.primitives[0].name, "pine/sq");
  expect_near(m.geometry.primitives[0].positions[0], 20, 5, 0);
  o.node = "birch";
  EXPECT_THROW(
      {
        try {
          import_glb(s, o);
        } catch (const MeshError& e) {
          EXPECT_STREQ(e.what(),
                       "t.glb: error: no node is named 'birch'; the nodes are 'forest', 'oak', 'pine'");
          throw;
        }
      },
      MeshError);
}

// Several top-level trees in the scene are imported together, with a warning naming them.
TEST(MeshGltf, SeveralRootsWarned) {
  gltf::Scene s = one_square();
  s.nodes = {{.name = "oak", .mesh = 0}, {.name = "pine", .mesh = 0, .translation = {3, 0, 0}}};
  s.roots = {0, 1};
  const MeshImport m = import_glb(s);
  EXPECT_EQ(m.geometry.primitives.size(), 2u);
  EXPECT_EQ(m.warnings,
            (std::vector<std::string>{
                "t.glb: warning: the scene has 2 top-level nodes with geometry (node 0 'oak', node 1 "
                "'pine'): imported together as one model; set `node` to import one"}));
}

std::string error_of(const std::string& bytes, const std::string& name) {
  MapFiles files;
  try {
    import_mesh(bytes, "gltf", "/m/" + name, name, files, {});
  } catch (const MeshError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshGltf, BadInputNamesTheFile) {
  const std::string glb = gltf::encode(one_square());
  EXPECT_EQ(error_of(glb.substr(0, 40), "cut.glb"), "cut.glb: error: invalid glTF: Invalid glTF binary.");
  EXPECT_EQ(
      error_of("{\"asset\": [1, 2", "bad.gltf"),
      "bad.gltf: error: invalid glTF: [json.exception.parse_error.101] parse error at line 1, column 16: "
      "syntax error while parsing array - unexpected end of input; expected ']'");
  EXPECT_EQ(error_of("", "empty.glb"), "empty.glb: error: empty file: nothing to import");
  nlohmann::json j = textured_json();
  j["meshes"][0]["primitives"][0]["indices"] = 99;
  EXPECT_EQ(error_of(j.dump(), "idx.gltf"),
            "idx.gltf: error: invalid glTF: primitive indices accessor out of bounds");
}

// The nodes form a tree: a child listed twice, a node under two parents, a scene listing a node
// and its descendant are refused naming the node (not imported twice, nor exponentially often);
// a chain deeper than 1000 levels is refused without exhausting the stack.
TEST(MeshGltf, NodeGraphMustBeATree) {
  gltf::WriteOptions w;
  w.format = gltf::FileFormat::kGltf;
  nlohmann::json j = nlohmann::json::parse(gltf::encode(one_square(), w));
  const auto with_nodes = [&](nlohmann::json nodes, std::vector<int> scene) {
    nlohmann::json e = j;
    e["nodes"] = std::move(nodes);
    e["scenes"][0]["nodes"] = std::move(scene);
    return e.dump();
  };
  const nlohmann::json leaf = {{"name", "leaf"}, {"mesh", 0}};
  EXPECT_EQ(error_of(with_nodes({{{"children", {1, 1}}}, leaf}, {0}), "twice.gltf"),
            "twice.gltf: error: node 1 'leaf' is reached twice (glTF nodes form a tree)");
  EXPECT_EQ(error_of(with_nodes({{{"children", {2}}}, {{"children", {2}}}, leaf}, {0, 1}), "two.gltf"),
            "two.gltf: error: node 2 'leaf' is reached twice (glTF nodes form a tree)");
  EXPECT_EQ(error_of(with_nodes({{{"children", {1}}}, leaf}, {0, 1}), "desc.gltf"),
            "desc.gltf: error: node 1 'leaf' is reached twice (glTF nodes form a tree)");
  // 40 levels, each node listing the next twice: 2^40 paths without the check.
  nlohmann::json diamond = nlohmann::json::array();
  for (int i = 0; i < 40; ++i) diamond.push_back({{"children", {i + 1, i + 1}}});
  diamond.push_back(leaf);
  EXPECT_EQ(error_of(with_nodes(diamond, {0}), "diamond.gltf"),
            "diamond.gltf: error: node 40 'leaf' is reached twice (glTF nodes form a tree)");
  // A chain of n nodes is n - 1 levels below its root: 1001 nodes read, 1002 refused.
  const auto chain = [&](int n) {
    nlohmann::json nodes = nlohmann::json::array();
    for (int i = 0; i + 1 < n; ++i) nodes.push_back({{"children", {i + 1}}});
    nodes.push_back(leaf);
    return with_nodes(nodes, {0});
  };
  MapFiles files;
  EXPECT_EQ(import_mesh(chain(1001), "gltf", "/m/c.gltf", "c.gltf", files, {}).geometry.primitives.size(),
            1u);
  EXPECT_EQ(error_of(chain(1002), "deep.gltf"),
            "deep.gltf: error: the node hierarchy is deeper than 1000 levels");
  EXPECT_EQ(error_of(chain(20000), "deep.gltf"),
            "deep.gltf: error: the node hierarchy is deeper than 1000 levels");
}

// An accessor without a buffer view is zeros of its declared count: a count of 2^28 fails on the
// limits before anything is allocated for it (POSITION on the vertex limit, another attribute on
// the accessor limit, max(vertices, 3 triangles)).
TEST(MeshGltf, HugeAccessorCountRefusedBeforeAllocating) {
  nlohmann::json j = textured_json();
  const auto huge = [&](const char* attribute) {
    nlohmann::json e = j;
    nlohmann::json& acc = e["accessors"][e["meshes"][0]["primitives"][0]["attributes"][attribute].get<int>()];
    acc.erase("bufferView");
    acc.erase("byteOffset");
    acc["count"] = 1 << 28;
    return e.dump();
  };
  EXPECT_EQ(error_of(huge("POSITION"), "p.gltf"),
            "p.gltf: error: the model has more than 16777216 vertices (the import's limit, "
            "tree::kMaxSourceVertices)");
  EXPECT_EQ(
      error_of(huge("NORMAL"), "n.gltf"),
      "n.gltf: error: mesh 0 'sq' primitive 0 attribute NORMAL: accessor 1 declares 268435456 elements, more "
      "than the limit of 50331648");
}

// The same bytes in two folders import to the same geometry (an unnamed embedded image is named
// by the file name) and the same warnings once their "<source>" prefix is the file name, as
// import_report.json writes them: no folder in image names or inside warnings.
TEST(MeshGltf, SameBytesInTwoFoldersSameResult) {
  nlohmann::json j = textured_json();
  j["images"][0].erase("name");
  j["images"].push_back({{"uri", "../up/gone.png"}});
  j["textures"].push_back({{"source", 1}});
  j["materials"].push_back(
      {{"name", "leaf"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}});
  MapFiles files;
  const auto run = [&](const std::string& path) {
    MeshImport m = import_mesh(j.dump(), "gltf", path, path, files, keep_placement());
    for (std::string& w : m.warnings) {
      EXPECT_EQ(w.rfind(path + ": ", 0), 0u) << w;
      w = "t.gltf" + w.substr(path.size());
    }
    return m;
  };
  const MeshImport a = run("/a/t.gltf"), b = run("/b/c/t.gltf");
  ASSERT_EQ(a.geometry.images.size(), 1u);
  EXPECT_EQ(a.geometry.images[0].name, "t.gltf.image0");
  EXPECT_EQ(a.geometry, b.geometry);
  EXPECT_EQ(
      a.warnings,
      (std::vector<std::string>{
          "t.gltf: warning: '../up/gone.png' is an absolute path or leaves the model's folder: looking "
          "for 'gone.png' beside the model instead",
          "t.gltf: warning: image '../up/gone.png' (image 1) of material 'leaf' could not be read (no file "
          "'gone.png' beside the model): the material keeps its colour, without the texture"}));
  EXPECT_EQ(a.warnings, b.warnings);
}

}  // namespace
}  // namespace sylva::import
