// Stage `pack`'s core on a two-level chain written as the lod stage writes it (lod.gltf with
// MSFT_lod over lod0/lod1.gltf sharing .bin files and a PNG): the files and their names, the
// chain's MSFT_lod and screen coverage kept, lod.json's numbers, determinism, compression, the
// validator, and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"
#include "stages/pack/pack_core.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::pack {
namespace {

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
  m.extras = {{"counts", {{"triangles", p.indices.size() / 3}}}};
  return m;
}

gltf::Node level_node(int i, double eps, double d) {
  gltf::Node n;
  n.name = "lod" + std::to_string(i);
  n.mesh = i;
  // As the lod stage writes them: the level's numbers and its diagnostics.
  n.extras = {{"epsilon_m", eps}, {"pixel_error_px", 0.5}, {"switch_distance_m", d}, {"E1_m", 0.25 * eps}};
  return n;
}

// The lod stage's screen coverage at distance d for the chain's camera (45 deg): the bounding
// sphere of level 0 (tube(40, 12): 0.2 x 8 x 0.2 m) over the screen.
const double kRadius = 0.5 * std::sqrt(0.2 * 0.2 + 8.0 * 8.0 + 0.2 * 0.2);
double coverage_at(double d) {
  const double t = std::tan(0.785398163397448 / 2);
  return std::min(1.0, 3.141592653589793 * kRadius * kRadius / ((2 * d * t) * (2 * d * t)));
}

// Writes lod.gltf, lod0.gltf, lod1.gltf, lod0.bin, lod1.bin, bark.png into dir.
void write_chain(const std::filesystem::path& dir) {
  gltf::Scene s;
  s.images.push_back({"bark.png", "image/png", test::tiny_png(), "bark.png"});
  gltf::Material bark;
  bark.name = "bark";
  bark.base_color_texture.image = 0;
  s.materials.push_back(bark);
  s.meshes = {tube(40, 12, 0), tube(10, 4, 1)};
  s.buffer_uris = {"lod0.bin", "lod1.bin"};
  s.nodes = {level_node(0, 0.001, 2.5), level_node(1, 0.01, 25)};
  s.nodes[0].extensions = {{"MSFT_lod", {{"ids", {1}}}}};
  s.nodes[0].extras["MSFT_screencoverage"] = {coverage_at(25), 0.0};
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
  EXPECT_NE(glb.find("\"MSFT_screencoverage\":[" + nlohmann::json(coverage_at(25)).dump() + ",0.0]"),
            std::string::npos);
  EXPECT_NE(glb.find("\"EXT_meshopt_compression\""), std::string::npos);
  const nlohmann::json lod = nlohmann::json::parse(files[3].bytes);
  EXPECT_EQ(lod["chain"], "oak.glb");
  ASSERT_EQ(lod["levels"].size(), 2u);
  EXPECT_EQ(lod["levels"][1]["file"], "oak_lod1.glb");
  EXPECT_EQ(lod["levels"][1]["switch_distance_m"], 25.0);
  EXPECT_EQ(lod["levels"][1]["epsilon_m"], 0.01);
  EXPECT_EQ(lod["levels"][0]["screen_coverage"], coverage_at(25));
  EXPECT_EQ(lod["levels"][1]["screen_coverage"], 0.0);
  EXPECT_EQ(lod["levels"][1]["kind"], "mesh");
  EXPECT_EQ(lod["levels"][1]["source_level"], 1);
  EXPECT_TRUE(lod["dropped"].empty());
  EXPECT_EQ(lod["levels"][0]["triangles"], 40u * 12u * 2u);
  EXPECT_EQ(lod["levels"][1]["triangles"], 10u * 4u * 2u);
  EXPECT_EQ(lod["levels"][1]["bytes"], files[2].bytes.size());
}

// impostor.glb as the impostor stage writes it: cards in one unlit BLEND material over one image.
ImpostorLevelInput impostor(double switch_distance) {
  ImpostorLevelInput im;
  gltf::Scene& s = im.scene;
  s.images.push_back({"impostor.png", "image/png", test::tiny_png(), ""});
  gltf::Material m;
  m.name = "impostor";
  m.base_color_texture.image = 0;
  m.alpha_mode = gltf::AlphaMode::kBlend;
  m.unlit = true;
  m.double_sided = true;
  s.materials.push_back(m);
  gltf::Mesh mesh;
  gltf::Primitive p;
  p.positions = {-0.1f, 0, 0,     0.1f, 0, 0,    0.1f, 8, 0,    -0.1f, 8, 0,
                 0,     0, -0.1f, 0,    0, 0.1f, 0,    8, 0.1f, 0,     8, -0.1f};
  p.texcoords = {0, 1, 0.5f, 1, 0.5f, 0, 0, 0, 0.5f, 1, 1, 1, 1, 0, 0.5f, 0};
  p.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  p.material = 0;
  mesh.primitives.push_back(p);
  s.meshes.push_back(mesh);
  gltf::Node n;
  n.mesh = 0;
  s.nodes.push_back(n);
  s.roots = {0};
  im.kind = "billboards";
  im.epsilon_m = 0.5;
  im.pixel_error_px = 0.5;
  im.switch_distance_m = switch_distance;
  im.camera.fov_y_rad = 0.785398163397448;
  im.inputs = {"impostor/impostor.json", "impostor/impostor.glb"};
  return im;
}

TEST(PackCore, TheImpostorEndsTheChain) {
  test::TempDir dir;
  write_chain(dir.path());
  SpeciesInput in = read_input(dir.path());
  in.impostor = impostor(400);
  const std::vector<PackedFile> files = pack_species(in, {});
  ASSERT_EQ(files.size(), 5u);
  EXPECT_EQ(files[3].name, "oak_impostor.glb");
  EXPECT_EQ(files[3].inputs, in.impostor->inputs);
  EXPECT_EQ(files[0].inputs.back(), "impostor/impostor.glb");
  for (std::size_t i = 0; i < 4; ++i) {
    test::write_file(dir / files[i].name, files[i].bytes);
    SYLVA_EXPECT_VALID_GLTF(dir / files[i].name);
  }
  // The chain: three level nodes, the root naming the other two, coverage at each next switch
  // distance (the impostor's from its camera), the impostor node's extras.
  const nlohmann::json chain = test::parse_glb(files[0].bytes).json;
  ASSERT_EQ(chain["scenes"][0]["nodes"].size(), 1u);
  const nlohmann::json& root = chain["nodes"][chain["scenes"][0]["nodes"][0].get<std::size_t>()];
  ASSERT_EQ(root["extensions"]["MSFT_lod"]["ids"].size(), 2u);
  const std::vector<double> coverage = root["extras"]["MSFT_screencoverage"];
  ASSERT_EQ(coverage.size(), 3u);
  EXPECT_EQ(coverage[0], coverage_at(25));
  EXPECT_NEAR(coverage[1], coverage_at(400), 1e-7 * coverage_at(400));  // radius from float positions
  EXPECT_EQ(coverage[2], 0.0);
  const nlohmann::json& last = chain["nodes"][root["extensions"]["MSFT_lod"]["ids"][1].get<std::size_t>()];
  EXPECT_EQ(last["extras"]["kind"], "impostor");
  EXPECT_EQ(last["extras"]["switch_distance_m"], 400.0);
  EXPECT_EQ(chain["images"].size(), 2u);  // bark once (shared by both mesh levels), the impostor's
  const nlohmann::json lod = nlohmann::json::parse(files[4].bytes);
  ASSERT_EQ(lod["levels"].size(), 3u);
  EXPECT_EQ(lod["levels"][2]["kind"], "impostor");
  EXPECT_EQ(lod["levels"][2]["impostor_kind"], "billboards");
  EXPECT_EQ(lod["levels"][2]["source_level"], -1);
  EXPECT_EQ(lod["levels"][2]["primitives"], 4u);
  EXPECT_EQ(lod["levels"][2]["epsilon_m"], 0.5);
  EXPECT_EQ(lod["levels"][2]["bytes"], files[3].bytes.size());
}

TEST(PackCore, DropsLevelsTheImpostorOrTheSavingRuleMakeUseless) {
  test::TempDir dir;
  write_chain(dir.path());
  SpeciesInput in = read_input(dir.path());
  // The impostor is proven from 20 m, before level 1's 25 m: level 1 is never drawn.
  in.impostor = impostor(20);
  std::vector<LevelChoice> c = select_levels(in, {});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_TRUE(c[0].kept);
  EXPECT_FALSE(c[1].kept);
  EXPECT_EQ(c[1].reason, "the impostor is proven from 20 m, before this level's switch distance 25 m");
  EXPECT_TRUE(c[2].kept);
  std::vector<PackedFile> files = pack_species(in, {});
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files[1].name, "oak_lod0.glb");
  EXPECT_EQ(files[2].name, "oak_impostor.glb");
  nlohmann::json lod = nlohmann::json::parse(files[3].bytes);
  ASSERT_EQ(lod["dropped"].size(), 1u);
  EXPECT_EQ(lod["dropped"][0]["source_level"], 1);
  EXPECT_EQ(lod["dropped"][0]["primitives"], 80u);
  // Level 1 (80 triangles) saves 1 - 80/960 = 0.917 of level 0's: kept at min_saving 0.9, dropped at 0.95.
  in.impostor.reset();
  PackOptions o;
  o.min_saving = 0.9;
  EXPECT_TRUE(select_levels(in, o)[1].kept);
  o.min_saving = 0.95;
  c = select_levels(in, o);
  EXPECT_FALSE(c[1].kept);
  EXPECT_EQ(c[1].reason,
            "saves 0.917 of the primitives of the level before it (960 -> 80), less than min_saving 0.95");
  files = pack_species(in, o);
  ASSERT_EQ(files.size(), 3u);
  const nlohmann::json one = test::parse_glb(files[0].bytes).json;
  ASSERT_EQ(one["nodes"].size(), 1u);
  EXPECT_EQ(one["nodes"][0]["extras"]["MSFT_screencoverage"], nlohmann::json::array({0.0}));
  EXPECT_FALSE(one["nodes"][0].contains("extensions"));
}

TEST(PackCore, RefusesAnImpostorForAnotherCamera) {
  test::TempDir dir;
  write_chain(dir.path());
  SpeciesInput in = read_input(dir.path());
  in.impostor = impostor(400);
  in.impostor->camera.fov_y_rad = 0.5;
  try {
    pack_species(in, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "the impostor's camera (vertical fov 28.6479 deg) is not the lod chain's (45 deg): its "
                 "switch distance is for another view");
  }
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

// The position rule (docs/stages/pack.md "Quantisation and image error"): the fewest bits within
// position_error x epsilon; a level that would need more than 16 bits gets 16 when they round
// within position_error_max x epsilon, else float positions.
TEST(PackCore, PositionGridFallsBackToSixteenBitsWithinEpsilon) {
  gltf::Mesh m;
  gltf::Primitive p;
  p.positions = {0, 0, 0, 3, 48, 2};  // an adult tree's extent: 48 m
  m.primitives.push_back(p);
  const double step16 = 48.0 / 65535;
  // epsilon 1 mm, half of it: 17 bits would be needed.
  PositionGrid g = position_grid(m, 0.001, 0.5);
  EXPECT_EQ(g.bits, 0);
  g = position_grid(m, 0.001, 0.5, 1.0);
  EXPECT_EQ(g.bits, 16);
  EXPECT_TRUE(g.relaxed);
  EXPECT_DOUBLE_EQ(g.max_error_m, std::sqrt(3.0) / 2 * step16);  // 0.634 mm
  EXPECT_EQ(position_grid(m, 0.001, 0.5, 0.6).bits, 0);          // 0.634 mm > 0.6 mm: float
  // epsilon 2.94 mm (lod1): 15 bits within half (1.27 mm), not relaxed; a quarter needs 16.
  g = position_grid(m, 0.00294, 0.5, 1.0);
  EXPECT_EQ(g.bits, 15);
  EXPECT_FALSE(g.relaxed);
  EXPECT_EQ(position_grid(m, 0.00294, 0.25, 1.0).bits, 16);
  // The young oak's lod0 (7.7 m, epsilon 1 mm): 14 bits within half, 15 within a quarter.
  m.primitives[0].positions = {0, 0, 0, 1, 7.7f, 1};
  g = position_grid(m, 0.001, 0.5, 1.0);
  EXPECT_EQ(g.bits, 14);
  EXPECT_FALSE(g.relaxed);
  EXPECT_EQ(position_grid(m, 0.001, 0.25, 1.0).bits, 15);
  // The pack's defaults.
  EXPECT_EQ(PackOptions{}.position_error, 0.25);
  EXPECT_EQ(PackOptions{}.position_error_max, 1.0);
}

// Meshopt files hold one view per attribute kind (gltfpack's layout), not one per accessor: the
// chain of two levels has 5 views (positions, normals, uvs and indices of both meshes, the PNG)
// and every accessor sits at its offset in its view.
TEST(PackCore, OneViewPerAttributeKind) {
  test::TempDir dir;
  write_chain(dir.path());
  const SpeciesInput in = read_input(dir.path());
  const std::vector<PackedFile> files = pack_species(in, {});
  const nlohmann::json chain = test::parse_glb(files[0].bytes).json;
  ASSERT_EQ(chain["bufferViews"].size(), 5u);
  ASSERT_EQ(chain["meshes"].size(), 2u);
  const auto& a0 = chain["meshes"][0]["primitives"][0];
  const auto& a1 = chain["meshes"][1]["primitives"][0];
  for (const char* attr : {"POSITION", "NORMAL", "TEXCOORD_0"}) {
    const auto& x = chain["accessors"][a0["attributes"][attr].get<std::size_t>()];
    const auto& y = chain["accessors"][a1["attributes"][attr].get<std::size_t>()];
    SCOPED_TRACE(attr);
    EXPECT_EQ(x["bufferView"], y["bufferView"]);
    EXPECT_EQ(x.value("byteOffset", 0u), 0u);
    const std::size_t stride = chain["bufferViews"][x["bufferView"].get<std::size_t>()]["byteStride"];
    EXPECT_EQ(y["byteOffset"], x["count"].get<std::size_t>() * stride);  // 41 x 12 vertices of lod0 first
  }
  const auto& i0 = chain["accessors"][a0["indices"].get<std::size_t>()];
  const auto& i1 = chain["accessors"][a1["indices"].get<std::size_t>()];
  EXPECT_EQ(i0["bufferView"], i1["bufferView"]);
  EXPECT_EQ(i1["byteOffset"], 2u * 40 * 12 * 6);  // after lod0's 2880 UNSIGNED_SHORT indices
  EXPECT_EQ(chain["bufferViews"][i0["bufferView"].get<std::size_t>()]["extensions"]["EXT_meshopt_compression"]
                 ["mode"],
            "TRIANGLES");
  // A level file: one mesh, so still one view per attribute.
  EXPECT_EQ(test::parse_glb(files[1].bytes).json["bufferViews"].size(), 5u);
  // The bytes of this fixed input (pack version 10: merged views, strip-friendly order, the
  // level extras trimmed in the chain and none in a level's file, numbers as short as their
  // floats; 15 and 11 bits). Version 9: 8352, 7116 and 3056 bytes.
  EXPECT_EQ(files[0].bytes.size(), 8192u);
  EXPECT_EQ(files[1].bytes.size(), 6952u);
  EXPECT_EQ(files[2].bytes.size(), 2892u);
  // A level's file carries no extras on its node or mesh (lod.json has its numbers); in the
  // chain, only the level's numbers stay in its node's extras and its mesh carries none.
  const nlohmann::json level = test::parse_glb(files[1].bytes).json;
  EXPECT_FALSE(level["nodes"][0].contains("extras"));
  EXPECT_FALSE(level["meshes"][0].contains("extras"));
  EXPECT_EQ(level["asset"]["extras"], (nlohmann::json{{"species", "oak"}, {"sylva_stage", "pack"}}));
  const nlohmann::json& root = chain["nodes"][chain["scenes"][0]["nodes"][0].get<std::size_t>()];
  const std::size_t lod1 = root["extensions"]["MSFT_lod"]["ids"][0];
  EXPECT_EQ(chain["nodes"][lod1]["extras"],
            (nlohmann::json{{"epsilon_m", 0.01}, {"pixel_error_px", 0.5}, {"switch_distance_m", 25.0}}));
  EXPECT_FALSE(chain["meshes"][1].contains("extras"));
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

// A meshopt GLB whose decoded views end off a 4-byte boundary (one triangle: 6 bytes of 16-bit
// indices, the last view) loads in sylva's renderer (libs/render pads the decoded BIN chunk), as
// the measured level choice loads every candidate level.
TEST(PackCore, AMeshoptLevelWithAnOddTriangleCountLoadsInTheRenderer) {
  gltf::Scene s;
  s.materials.push_back({});
  gltf::Mesh m;
  gltf::Primitive p;
  p.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  p.indices = {0, 1, 2};
  p.material = 0;
  m.primitives.push_back(p);
  s.meshes.push_back(m);
  gltf::Node n;
  n.mesh = 0;
  s.nodes.push_back(n);
  s.roots = {0};
  gltf::WriteOptions w;
  w.meshopt = true;
  const render::Scene back = render::load_gltf_scene_from_memory(gltf::encode(s, w), "one triangle");
  EXPECT_EQ(back.triangle_count(), 1u);
}

}  // namespace
}  // namespace sylva::pack
