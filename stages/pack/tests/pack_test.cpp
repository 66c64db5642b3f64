// Stage `pack`'s core on a two-level chain written as the lod stage writes it (lod.gltf with
// MSFT_lod over lod0/lod1.gltf sharing .bin files and a PNG): the files and their names, the
// chain's MSFT_lod and screen coverage kept, lod.json's numbers, determinism, compression, the
// validator, and refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"
#include "stages/pack/pack_core.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::pack {
namespace {

const unsigned char kPng[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49,
                              0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x06,
                              0x00, 0x00, 0x00, 0x72, 0xb6, 0x0d, 0x24, 0x00, 0x00, 0x00, 0x11, 0x49, 0x44,
                              0x41, 0x54, 0x78, 0xda, 0x63, 0x38, 0x51, 0xa1, 0xf1, 0x1f, 0x84, 0x19, 0x60,
                              0x0c, 0x00, 0x55, 0xe4, 0x09, 0x9d, 0x58, 0x11, 0xe5, 0x51, 0x00, 0x00, 0x00,
                              0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

gltf::Mesh tube(int rings, int sides, int buffer) {
  gltf::Mesh m;
  m.name = "lod" + std::to_string(buffer);
  m.buffer = buffer;
  gltf::Primitive p;
  for (int r = 0; r <= rings; ++r)
    for (int k = 0; k < sides; ++k) {
      const float a = 6.2831853f * float(k) / float(sides);
      p.positions.insert(p.positions.end(), {0.1f * std::cos(a), 0.2f * float(r), 0.1f * std::sin(a)});
      p.normals.insert(p.normals.end(), {std::cos(a), 0, std::sin(a)});
      p.texcoords.insert(p.texcoords.end(), {float(k) / float(sides), float(r) / float(rings)});
    }
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < sides; ++k) {
      const auto at = [&](int rr, int kk) { return std::uint32_t(rr * sides + (kk % sides)); };
      p.indices.insert(p.indices.end(),
                       {at(r, k), at(r + 1, k), at(r + 1, k + 1), at(r, k), at(r + 1, k + 1), at(r, k + 1)});
    }
  p.material = 0;
  m.primitives.push_back(p);
  return m;
}

gltf::Node level_node(int i, double eps, double d) {
  gltf::Node n;
  n.name = "lod" + std::to_string(i);
  n.mesh = i;
  n.extras = {{"epsilon_m", eps}, {"pixel_error_px", 0.5}, {"switch_distance_m", d}};
  return n;
}

// Writes lod.gltf, lod0.gltf, lod1.gltf, lod0.bin, lod1.bin, bark.png into dir.
void write_chain(const std::filesystem::path& dir) {
  gltf::Scene s;
  s.images.push_back(
      {"bark.png", "image/png", std::string(reinterpret_cast<const char*>(kPng), sizeof kPng), "bark.png"});
  gltf::Material bark;
  bark.name = "bark";
  bark.base_color_texture.image = 0;
  s.materials.push_back(bark);
  s.meshes = {tube(40, 12, 0), tube(10, 4, 1)};
  s.buffer_uris = {"lod0.bin", "lod1.bin"};
  s.nodes = {level_node(0, 0.001, 2.5), level_node(1, 0.01, 25)};
  s.nodes[0].extensions = {{"MSFT_lod", {{"ids", {1}}}}};
  s.nodes[0].extras["MSFT_screencoverage"] = {1.0, 0.05};
  s.roots = {0};
  s.extras = {{"sylva_stage", "lod"}};
  const gltf::EncodedFiles chain = gltf::encode_external(s);
  test::write_file(dir / "lod.gltf", chain.gltf);
  for (const auto& r : chain.resources) test::write_file(dir / r.name, r.bytes);
  for (int i = 0; i < 2; ++i) {
    gltf::Scene l = s;
    l.meshes = {s.meshes[std::size_t(i)]};
    l.meshes[0].buffer = 0;
    l.buffer_uris = {"lod" + std::to_string(i) + ".bin"};
    l.nodes = {s.nodes[std::size_t(i)]};
    l.nodes[0].mesh = 0;
    l.nodes[0].extensions = nullptr;
    const gltf::EncodedFiles f = gltf::encode_external(l);
    test::write_file(dir / ("lod" + std::to_string(i) + ".gltf"), f.gltf);
  }
}

SpeciesInput read_input(const std::filesystem::path& dir) {
  SpeciesInput in;
  in.species = "oak";
  in.chain = gltf::read_scene(dir / "lod.gltf");
  in.levels = {gltf::read_scene(dir / "lod0.gltf"), gltf::read_scene(dir / "lod1.gltf")};
  in.chain_inputs = {"lod.gltf", "lod0.bin", "lod1.bin", "bark.png"};
  in.level_inputs = {{"lod0.gltf", "lod0.bin", "bark.png"}, {"lod1.gltf", "lod1.bin", "bark.png"}};
  return in;
}

TEST(PackCore, WritesTheChainTheLevelsAndLodJson) {
  test::TempDir dir;
  write_chain(dir.path());
  const SpeciesInput in = read_input(dir.path());
  const std::vector<PackedFile> files = pack_species(in, {});
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files[0].name, "oak.glb");
  EXPECT_EQ(files[1].name, "oak_lod0.glb");
  EXPECT_EQ(files[2].name, "oak_lod1.glb");
  EXPECT_EQ(files[3].name, "oak.lod.json");
  EXPECT_EQ(files[1].inputs, in.level_inputs[0]);
  // Deterministic.
  const std::vector<PackedFile> again = pack_species(in, {});
  for (std::size_t i = 0; i < files.size(); ++i)
    EXPECT_TRUE(files[i].bytes == again[i].bytes) << files[i].name;
  // Every GLB is validator-clean, the chain keeps MSFT_lod and the screen coverage.
  for (std::size_t i = 0; i < 3; ++i) {
    test::write_file(dir / files[i].name, files[i].bytes);
    SYLVA_EXPECT_VALID_GLTF(dir / files[i].name);
  }
  const std::string& glb = files[0].bytes;
  EXPECT_NE(glb.find("\"MSFT_lod\":{\"ids\":[1]}"), std::string::npos);
  EXPECT_NE(glb.find("\"MSFT_screencoverage\":[1.0,0.05]"), std::string::npos);
  EXPECT_NE(glb.find("\"EXT_meshopt_compression\""), std::string::npos);
  const nlohmann::json lod = nlohmann::json::parse(files[3].bytes);
  EXPECT_EQ(lod["chain"], "oak.glb");
  ASSERT_EQ(lod["levels"].size(), 2u);
  EXPECT_EQ(lod["levels"][1]["file"], "oak_lod1.glb");
  EXPECT_EQ(lod["levels"][1]["switch_distance_m"], 25.0);
  EXPECT_EQ(lod["levels"][1]["epsilon_m"], 0.01);
  EXPECT_EQ(lod["levels"][1]["screen_coverage"], 0.05);
  EXPECT_EQ(lod["levels"][0]["triangles"], 40u * 12u * 2u);
  EXPECT_EQ(lod["levels"][1]["triangles"], 10u * 4u * 2u);
  EXPECT_EQ(lod["levels"][1]["bytes"], files[2].bytes.size());
}

TEST(PackCore, CompressionChoices) {
  test::TempDir dir;
  write_chain(dir.path());
  const SpeciesInput in = read_input(dir.path());
  PackOptions none;
  none.compression = Compression::kNone;
  PackOptions draco;
  draco.compression = Compression::kDraco;
  const auto plain = pack_species(in, none);
  const auto meshopt = pack_species(in, {});
  const auto drc = pack_species(in, draco);
  EXPECT_LT(meshopt[1].bytes.size(), plain[1].bytes.size());
  EXPECT_EQ(plain[1].bytes.find("EXT_meshopt_compression"), std::string::npos);
  EXPECT_NE(drc[1].bytes.find("KHR_draco_mesh_compression"), std::string::npos);
  for (const auto* set : {&plain, &drc}) {
    test::write_file(dir / "x.glb", (*set)[0].bytes);
    SYLVA_EXPECT_VALID_GLTF(dir / "x.glb");
  }
}

// sylva's renderer reads the meshopt files (libs/render/meshopt_decode.h) to the same geometry as
// the uncompressed ones.
TEST(PackCore, MeshoptFilesLoadInSylvasRendererAsTheUncompressedOnes) {
  test::TempDir dir;
  write_chain(dir.path());
  const SpeciesInput in = read_input(dir.path());
  PackOptions none;
  none.compression = Compression::kNone;
  const auto plain = pack_species(in, none);
  const auto packed = pack_species(in, {});
  for (std::size_t i = 0; i < 3; ++i) {
    const render::Scene a = render::load_gltf_scene_from_memory(plain[i].bytes, plain[i].name);
    const render::Scene b = render::load_gltf_scene_from_memory(packed[i].bytes, packed[i].name);
    EXPECT_EQ(a.triangle_count(), b.triangle_count()) << i;
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    for (std::size_t m = 0; m < a.meshes.size(); ++m)
      for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p)
        EXPECT_EQ(a.meshes[m].primitives[p].positions, b.meshes[m].primitives[p].positions) << i;
    EXPECT_EQ(a.bounds().min, b.bounds().min);
    EXPECT_EQ(a.bounds().max, b.bounds().max);
  }
}

TEST(PackCore, RefusesAChainThatDoesNotMatchItsLevels) {
  test::TempDir dir;
  write_chain(dir.path());
  SpeciesInput in = read_input(dir.path());
  in.levels.pop_back();
  try {
    pack_species(in, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the lod chain's MSFT_lod names 2 levels, but 1 level files were given");
  }
}

}  // namespace
}  // namespace sylva::pack
