// The adapter (impostor_stage.h) end to end: a young oak's lod chain (written by the lod stage)
// in, the four outputs out, each valid; a mesh in; and the errors a bad input gets.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "libs/gltf/writer.h"
#include "libs/image/image_io.h"
#include "libs/impostor/impostor_json.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/tree/sylt_format.h"
#include "stages/impostor/impostor_stage.h"
#include "stages/lod/lod_stage.h"
#include "stages/lod/tests/test_trees.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::FakeStageContext;

// The lod stage's outputs for a young oak, in `dir`.
void write_lod_chain(const fs::path& dir, const fs::path& scratch) {
  fs::create_directories(dir);
  fs::create_directories(scratch);
  tree::Tree t = lod::test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml", "young");
  t.materials.leaf_texture.clear();
  t.materials.bark_texture.clear();
  tree::write_sylt(scratch / "tree.sylt", t);
  const auto lod = make_lod_stage();
  FakeStageContext ctx(*lod, {{"tree", "tree", scratch}}, dir);
  lod->run(ctx);
}

TEST(ImpostorStage, BakesFromTheCoarsestLevelWithinATexelAndWritesValidFiles) {
  test::TempDir tmp;
  write_lod_chain(tmp / "lod", tmp / "tree");
  const auto stage = make_impostor_stage();
  for (const std::string kind : {"hemi_octahedral", "billboards"}) {
    const fs::path out = tmp / kind;
    fs::create_directories(out);
    FakeStageContext ctx(*stage, {{"lod_oak", "lod", tmp / "lod"}}, out,
                         {{"kind", Value(kind)},
                          {"frame_px", Value(std::int64_t(64))},
                          {"mip_levels", Value(std::int64_t(2))}});
    stage->run(ctx);
    EXPECT_EQ(ctx.declared, (std::set<std::string>{"impostor.glb", "impostor.json", "impostor_color.png",
                                                   "impostor_normal.png"}));
    const impostor::ImpostorInfo info = impostor::read_impostor_json((out / "impostor.json").string());
    EXPECT_EQ(impostor::kind_name(info.kind), kind);
    EXPECT_EQ(info.source_type, "lod");
    // The level: the coarsest whose epsilon is within one texel.
    const auto summary = nlohmann::json::parse(test::read_file(tmp / "lod" / "lod.json"));
    const auto& levels = summary.at("levels");
    ASSERT_GE(info.source_level, 0);
    EXPECT_EQ(info.source_file, levels[std::size_t(info.source_level)].at("file").get<std::string>());
    EXPECT_LE(info.error.source_m, info.error.texel_m);
    if (std::size_t(info.source_level) + 1 < levels.size()) {
      EXPECT_GT(levels[std::size_t(info.source_level) + 1].at("epsilon_m").get<double>(), info.error.texel_m);
    }
    EXPECT_GT(info.switch_distance_m, 0);
    const image::Image color = image::read_image(out / "impostor_color.png");
    EXPECT_EQ(color.width(), info.atlas_width_px);
    SYLVA_EXPECT_VALID_GLTF(out / "impostor.glb");
  }
}

TEST(ImpostorStage, BakesAMeshAndRefusesBadInputs) {
  test::TempDir tmp;
  // A mesh artifact: one quad.
  gltf::Scene s;
  gltf::Primitive p;
  p.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  p.indices = {0, 1, 2, 0, 2, 3};
  gltf::Mesh m;
  m.primitives.push_back(p);
  s.meshes.push_back(m);
  gltf::Node n;
  n.mesh = 0;
  s.nodes.push_back(n);
  s.roots = {0};
  fs::create_directories(tmp / "mesh");
  gltf::write_file(s, tmp / "mesh" / "tree.glb");
  const auto stage = make_impostor_stage();
  fs::create_directories(tmp / "out");
  FakeStageContext ctx(*stage, {{"mesh_quad", "mesh", tmp / "mesh"}}, tmp / "out",
                       {{"frames", Value(std::int64_t(4))},
                        {"frame_px", Value(std::int64_t(32))},
                        {"mip_levels", Value(std::int64_t(1))}});
  stage->run(ctx);
  const impostor::ImpostorInfo info = impostor::read_impostor_json((tmp / "out" / "impostor.json").string());
  EXPECT_EQ(info.source_type, "mesh");
  EXPECT_EQ(info.source_file, "tree.glb");
  EXPECT_EQ(info.source_level, -1);
  EXPECT_DOUBLE_EQ(info.error.source_m, 0);
  EXPECT_GT(info.switch_distance_m, 0);
  {  // A recorded (proven) switch distance replaces the model's; the error terms stay.
    fs::create_directories(tmp / "out_proven");
    FakeStageContext proven(*stage, {{"mesh_quad", "mesh", tmp / "mesh"}}, tmp / "out_proven",
                            {{"frames", Value(std::int64_t(4))},
                             {"frame_px", Value(std::int64_t(32))},
                             {"mip_levels", Value(std::int64_t(1))},
                             {"switch_distance_m", Value(12.5)}});
    stage->run(proven);
    const impostor::ImpostorInfo proven_info =
        impostor::read_impostor_json((tmp / "out_proven" / "impostor.json").string());
    EXPECT_DOUBLE_EQ(proven_info.switch_distance_m, 12.5);
    EXPECT_EQ(proven_info.error, info.error);
  }

  auto error = [&](const fs::path& in, const std::string& type, const Value::Object& over = {}) {
    fs::create_directories(tmp / "bad_out");
    FakeStageContext c(*stage, {{"input", type, in}}, tmp / "bad_out", over);
    try {
      stage->run(c);
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  fs::create_directories(tmp / "empty");
  EXPECT_EQ(error(tmp / "empty", "lod"), "input 'input' (lod) has no lod.json");
  EXPECT_EQ(error(tmp / "empty", "mesh"),
            "input 'input' (mesh) must hold exactly one .glb or .gltf file, has 0");
  // lod.json is read with libs/lodchain: a bad one is its one-line error.
  test::write_file(tmp / "empty" / "lod.json", R"({"levels": [{"file": "lod0.glb", "epsilon_m": 0.01}]})");
  EXPECT_EQ(error(tmp / "empty", "lod"), (tmp / "empty" / "lod.json").string() + ": error: missing 'tree'");
  lodchain::LodChain chain;
  chain.tree = "t";
  lodchain::Level level;
  level.epsilon_m = 0.01;
  level.pixel_error_px = 0.5;
  level.file = "lod0.glb";
  chain.levels = {level};
  test::write_file(tmp / "empty" / "lod.json", lodchain::write_lod_chain(chain));
  EXPECT_EQ(error(tmp / "empty", "lod"), "input 'input': lod.json lists lod0.glb, which the artifact lacks");
  EXPECT_EQ(error(tmp / "mesh", "mesh", {{"mip_levels", Value(std::int64_t(7))}}),
            "mip_levels 7 needs a padding of 128 texels, more than a quarter of frame_px 256");
}

}  // namespace
}  // namespace sylva
