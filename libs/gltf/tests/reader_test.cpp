// The reader: what the writer writes reads back to the same scene (re-encoding gives the same
// bytes), from GLB, embedded .gltf and external .gltf alike; what it cannot represent is refused
// with the file and element named.
#include "libs/gltf/reader.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/gltf/writer.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/test_support.h"

namespace sylva::gltf {
namespace {

// Two levels as lod.gltf has them: a mesh of textured triangles and one of lines with a colour
// per vertex, linked by MSFT_lod, with extras everywhere.
Scene chain_scene() {
  Scene s;
  s.images.push_back({"leaves.png", "image/png", test::tiny_png(), ""});
  Material leaf;
  leaf.name = "leaves";
  leaf.base_color = {0.2f, 0.5f, 0.1f, 1};
  leaf.base_color_texture = {0, Wrap::kClampToEdge, Wrap::kRepeat};
  leaf.alpha_mode = AlphaMode::kMask;
  leaf.alpha_cutoff = 0.4f;
  leaf.double_sided = true;
  leaf.roughness = 0.7f;
  s.materials.push_back(leaf);
  Material lines;
  lines.name = "bark_lines";
  lines.alpha_mode = AlphaMode::kBlend;
  lines.extras = {{"alpha_eq12", 0.25}};
  s.materials.push_back(lines);
  Mesh near;
  near.name = "lod0";
  Primitive t;
  for (int i = 0; i < 12; ++i) {
    const float a = 0.5f * static_cast<float>(i);
    t.positions.insert(t.positions.end(), {std::cos(a), 0.1f * static_cast<float>(i), std::sin(a)});
    t.normals.insert(t.normals.end(), {0, 1, 0});
    t.texcoords.insert(t.texcoords.end(), {0.1f * static_cast<float>(i), 0.5f});
  }
  for (std::uint32_t i = 0; i + 2 < 12; ++i) t.indices.insert(t.indices.end(), {0, i + 1, i + 2});
  t.material = 0;
  near.primitives.push_back(t);
  Mesh far;
  far.name = "lod1";
  Primitive l;
  l.mode = PrimitiveMode::kLines;
  l.positions = {0, 0, 0, 0, 1, 0, 0, 2, 0.5f};
  l.colors = {1, 1, 1, 0.5f, 1, 1, 1, 0.25f, 1, 1, 1, 1};
  l.indices = {0, 1, 1, 2};
  l.material = 1;
  far.primitives.push_back(l);
  s.meshes = {near, far};
  Node n0;
  n0.name = "lod0";
  n0.mesh = 0;
  n0.extensions = {{"MSFT_lod", {{"ids", {1}}}}};
  n0.extras = {{"MSFT_screencoverage", {1.0, 0.1}}, {"epsilon_m", 0.001}};
  Node n1;
  n1.name = "lod1";
  n1.mesh = 1;
  n1.translation = {0, 0, 1};
  s.nodes = {n0, n1};
  s.roots = {0};
  s.extras = {{"sylva_stage", "lod"}, {"tree", "test"}};
  return s;
}

TEST(GltfReader, GlbReadsBackToTheSameBytes) {
  test::TempDir dir;
  const std::string bytes = encode(chain_scene());
  test::write_file(dir.path() / "c.glb", bytes);
  const Scene back = read_scene(dir.path() / "c.glb");
  EXPECT_EQ(encode(back), bytes);
  ASSERT_EQ(back.nodes.size(), 2u);
  EXPECT_EQ(back.nodes[0].extensions["MSFT_lod"]["ids"][0], 1);
  EXPECT_EQ(back.images.at(0).bytes.size(), test::tiny_png().size());  // the PNG as it was, not decoded
  EXPECT_EQ(back.meshes[1].primitives[0].colors[3], 0.5f);
}

TEST(GltfReader, EmbeddedAndExternalGltfRead) {
  test::TempDir dir;
  WriteOptions text;
  text.format = FileFormat::kGltf;
  test::write_file(dir.path() / "c.gltf", encode(chain_scene(), text));
  EXPECT_EQ(encode(read_scene(dir.path() / "c.gltf")), encode(chain_scene()));
  Scene ext = chain_scene();
  ext.buffer_uris = {"c.bin"};
  ext.images[0].uri = "leaves.png";
  const EncodedFiles files = encode_external(ext);
  test::write_file(dir.path() / "e.gltf", files.gltf);
  for (const auto& r : files.resources) test::write_file(dir.path() / r.name, r.bytes);
  EXPECT_EQ(encode(read_scene(dir.path() / "e.gltf")), encode(chain_scene()));
}

TEST(GltfReader, RefusesWhatItCannotRepresent) {
  test::TempDir dir;
  WriteOptions draco;
  draco.draco.enabled = true;
  test::write_file(dir.path() / "d.glb", encode(chain_scene(), draco));
  try {
    read_scene(dir.path() / "d.glb");
    FAIL();
  } catch (const ReadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir.path() / "d.glb").string() + ": ", 0), 0u) << e.what();
  }
  EXPECT_THROW(read_scene(dir.path() / "missing.glb"), ReadError);
  test::write_file(dir.path() / "bad.gltf", "{ not json");
  EXPECT_THROW(read_scene(dir.path() / "bad.gltf"), ReadError);
}

}  // namespace
}  // namespace sylva::gltf
