// The forest stage end to end on synthetic lod artifacts (two "species", two levels each, written
// by libs/gltf as the lod stage writes them): instances.json, the tiles' glTF (validator, and
// loaded back by libs/render: every instance where instances.json puts it), tileset.json, cameras.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "libs/forest/instances.h"
#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "libs/impostor/impostor_json.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/camera.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "stages/forest/forest_info.h"
#include "stages/forest/forest_stage.h"
#include "stages/forest/tests/card_glb.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

struct FakeContext : sylva::test::FakeStageContext {
  FakeContext(const Stage& stage, std::vector<InputArtifact> inputs, fs::path out,
              const Value::Object& overrides = {})
      : FakeStageContext(stage, {}, std::move(out), overrides) {
    name = "forest";
    for (auto& in : inputs) add_input(std::move(in));
  }
};

// A box tree of half width w and height h, two levels (the second a coarser "level": a flat card;
// with `twig_lines`, also one blended twig drawn as three coincident lines, as the lod stage
// draws a sub-pixel internode).
InputArtifact fake_lod(const fs::path& dir, double w, double h, const std::string& node,
                       bool twig_lines = false) {
  fs::create_directories(dir);
  lodchain::LodChain lod;  // lod.json as the lod stage writes it (libs/lodchain)
  lod.tree = node + " tree";
  lod.pixel_error_px = 0.5;
  lod.camera_fov_y_deg = 45.0;
  lod.camera_height_px = 1080;
  for (int l = 0; l < 2; ++l) {
    gltf::Scene s;
    gltf::Material m;
    m.name = l == 0 ? "bark" : "card";
    m.base_color = {0.3f, 0.5f, 0.2f, 1};
    s.materials.push_back(m);
    gltf::Primitive p;
    const float fw = float(w), fh = float(h);
    if (l == 0) {
      p.positions = {-fw, 0,  -fw, fw, 0,  -fw, fw, 0,  fw, -fw, 0,  fw,
                     -fw, fh, -fw, fw, fh, -fw, fw, fh, fw, -fw, fh, fw};
      p.indices = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1,
                   1, 5, 6, 1, 6, 2, 2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0};
    } else {
      p.positions = {-fw, 0, 0, fw, 0, 0, fw, fh, 0, -fw, fh, 0};
      p.indices = {0, 1, 2, 0, 2, 3};
    }
    p.material = 0;
    gltf::Mesh mesh;
    mesh.name = "lod" + std::to_string(l);
    mesh.primitives.push_back(p);
    if (twig_lines && l == 1) {
      gltf::Material twigs;
      twigs.name = "twigs";
      twigs.base_color = {0.4f, 0.3f, 0.2f, 1};
      twigs.alpha_mode = gltf::AlphaMode::kBlend;
      s.materials.push_back(twigs);
      gltf::Primitive lines;
      lines.mode = gltf::PrimitiveMode::kLines;
      for (int copy = 0; copy < 3; ++copy) {
        lines.positions.insert(lines.positions.end(), {0, fh, 0, fw, fh + 1, 0});
        const float n[3] = {copy == 0 ? 1.f : 0.f, copy == 1 ? 1.f : 0.f, copy == 2 ? 1.f : 0.f};
        lines.normals.insert(lines.normals.end(), {n[0], n[1], n[2], n[0], n[1], n[2]});
        lines.colors.insert(lines.colors.end(), {1, 1, 1, 0.3f, 1, 1, 1, 0.3f});
        const auto b = std::uint32_t(2 * copy);
        lines.indices.insert(lines.indices.end(), {b, b + 1});
      }
      lines.material = 1;
      mesh.primitives.push_back(lines);
    }
    s.meshes.push_back(mesh);
    gltf::Node n;
    n.name = mesh.name;
    n.mesh = 0;
    s.nodes.push_back(n);
    s.roots = {0};
    s.buffer_uris = {"lod" + std::to_string(l) + ".bin"};
    const gltf::EncodedFiles e = gltf::encode_external(s);
    sylva::test::write_file(dir / ("lod" + std::to_string(l) + ".gltf"), e.gltf);
    for (const auto& r : e.resources) sylva::test::write_file(dir / r.name, r.bytes);
    lodchain::Level level;
    level.sylva_lod_level = std::uint64_t(l);
    level.file = "lod" + std::to_string(l) + ".gltf";
    level.epsilon_m = l == 0 ? 0.001 : 0.2;
    level.pixel_error_px = 0.5;
    level.switch_distance_m = l == 0 ? 2.6 : 520.0;
    lod.levels.push_back(level);
  }
  sylva::test::write_file(dir / "lod.json", lodchain::write_lod_chain(lod));
  InputArtifact in;
  in.node = node;
  in.type = "lod";
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  for (const auto& n : names) in.files.push_back({n, dir / n, "0"});
  return in;
}

Value::Object species(const std::string& name, double density) {
  return {{"name", Value(name)},
          {"density_per_ha", Value(density)},
          {"scale_x", Value(Value::List{0.9, 1.1})},
          {"scale_y", Value(Value::List{0.8, 1.2})},
          {"scale_z", Value(Value::List{0.9, 1.1})},
          {"base_rotation_deg", Value(Value::List{0.0, 0.0, 0.0})},
          {"base_translation_y_m", Value(0.0)},
          {"random_yaw", Value(true)},
          {"max_slope_deg", Value(90.0)},
          {"min_altitude_m", Value(-1e9)},
          {"max_altitude_m", Value(1e9)},
          {"min_spacing_m", Value(0.0)},
          {"impostor_parallax", Value(Value::List{})}};
}

// The checks the recipe loader runs (StageInfo::check) find every problem, each with the path of
// its value, so a recipe error points at it (the stage itself reports the first: ForestOutput).
TEST(ForestParams, EveryProblemWithThePathOfItsValue) {
  const StageInfo info = forest_stage_info();
  ASSERT_TRUE(info.check);
  Value::Object p;  // as the loader completes a node: schema defaults, then the recipe's values
  for (const ParamSpec& s : info.params)
    if (!s.required()) p[s.name] = s.default_value;
  Value::Object a = species("a", 10), b = species("tile_b", 10), c = species("a", 10);
  a["scale_y"] = Value(Value::List{1.2, 0.8});
  a["min_altitude_m"] = Value(5.0);
  a["max_altitude_m"] = Value(4.0);
  c["impostor_parallax"] = Value(Value::List{100.0, 8.0, 90.0, 65.0});
  p["species"] = Value(Value::List{Value(a), Value(b), Value(c)});
  p["exclusions"] = Value(
      Value::List{Value(Value::Object{{"points", Value(Value::List{0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 2.0})}})});
  p["rows"] = Value(Value::List{Value(Value::Object{{"species", Value("elm")},
                                                    {"points", Value(Value::List{0.0, 0.0, 10.0, 0.0})},
                                                    {"spacing_m", Value(5.0)},
                                                    {"jitter_m", Value(0.0)}})});
  p["terrain_extent_m"] = Value(Value::List{0.0, 0.0, -1.0, 10.0});
  std::vector<std::string> got;
  for (const ParamProblem& pr : info.check(p)) got.push_back(param_problem_text(pr));
  const std::vector<std::string> want = {
      "parameter 'species'[0].scale_y: must be [min, max] with min <= max, got [1.2, 0.8]",
      "parameter 'species'[0].max_altitude_m: must be at least min_altitude_m (5), got 4",
      "parameter 'species'[1].name: 'tile_b' must not begin with 'tile_' (the tile files' names)",
      "parameter 'species'[2].name: 'a' is the name of species[0] too",
      "parameter 'species'[2].impostor_parallax: steps must be integers 0..64, got 65",
      "parameter 'species'[2].impostor_parallax: distances must increase, got 90 after 100",
      "parameter 'exclusions'[0].points: must be x, z pairs (an even count), got 7 numbers",
      "parameter 'rows'[0].species: 'elm' is not in 'species'",
      "parameter 'terrain_extent_m': must be [x0, z0, x1, z1] with x1 > x0 and z1 > z0"};
  EXPECT_EQ(got, want);
  p["species"] = Value(Value::List{Value(species("a", 10)), Value(species("elm", 10))});
  p["exclusions"] = Value(Value::List{});
  p["terrain_extent_m"] = Value(Value::List{});
  EXPECT_TRUE(info.check(p).empty());
  p["terrain_extent_m"] = Value(Value::List{0.0, 0.0, 10.0, 10.0});  // but no height_map
  ASSERT_EQ(info.check(p).size(), 1u);
  EXPECT_EQ(param_problem_text(info.check(p)[0]),
            "parameter 'terrain_extent_m': places the height map, but there is no height_map");
}

class ForestOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tmp_.path();
    inputs_ = {fake_lod(dir_ / "lod_a", 2, 8, "lod_a"), fake_lod(dir_ / "lod_b", 1, 5, "lod_b")};
  }

  forest::Forest run(const fs::path& out, Value::Object overrides) {
    fs::create_directories(out);
    const auto stage = make_forest_stage();
    FakeContext ctx(*stage, inputs_, out, std::move(overrides));
    stage->run(ctx);
    declared_ = ctx.declared;
    return forest::read_instances(out / "instances.json");
  }

  sylva::test::TempDir tmp_;
  fs::path dir_;
  std::vector<InputArtifact> inputs_;
  std::set<std::string> declared_;
};

TEST_F(ForestOutput, InstancesTilesTilesetAndCameras) {
  const Value::Object params = {
      {"size_m", Value(Value::List{100.0, 60.0})},
      {"tile_size_m", Value(50.0)},
      {"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 40))})},
      {"nodes_per_node", Value(std::int64_t(4))}};
  const fs::path out = dir_ / "out";
  const forest::Forest f = run(out, params);
  ASSERT_EQ(f.species.size(), 2u);
  EXPECT_EQ(f.stats[0].requested, 12u);  // 20 per ha x 0.6 ha
  EXPECT_EQ(f.stats[1].requested, 24u);
  EXPECT_EQ(f.instances.size(), f.stats[0].placed + f.stats[1].placed);
  EXPECT_EQ(f.species[0].bounds.max[1], 8.0);
  ASSERT_EQ(f.species[0].levels.size(), 2u);
  EXPECT_EQ(f.species[0].levels[1].file, "a_lod1.gltf");
  EXPECT_EQ(f.species[0].levels[1].switch_distance_m, 520.0);
  EXPECT_EQ(f.species[0].levels[0].primitives, 12u);
  EXPECT_EQ(f.species[0].levels[1].primitives, 2u);
  EXPECT_FALSE(f.binary_table);
  // 100 x 60 m in 50 m tiles: at most 2 x 2 tiles, every instance in the tile holding its position.
  EXPECT_LE(f.tiles.size(), 4u);
  std::size_t in_tiles = 0;
  for (std::size_t t = 0; t < f.tiles.size(); ++t) {
    in_tiles += f.tiles[t].instances.size();
    for (std::uint32_t i : f.tiles[t].instances) EXPECT_EQ(f.instances[i].tile, t);
  }
  EXPECT_EQ(in_tiles, f.instances.size());

  // Every tile at every level: valid glTF whose instances are exactly the forest's trees.
  std::vector<fs::path> gltfs;
  for (const auto& t : f.tiles)
    for (int l = 0; l < 2; ++l) {
      const fs::path p = out / ("tile_" + std::to_string(t.ix) + "_" + std::to_string(t.iz) + "_lod" +
                                std::to_string(l) + ".gltf");
      ASSERT_TRUE(fs::exists(p)) << p;
      gltfs.push_back(p);
      const render::Scene s = render::load_gltf_scene(p);
      std::size_t n = 0;
      for (const auto& m : s.meshes) n += m.instances.size();
      EXPECT_EQ(n, t.instances.size());
      // Each instance's base point lands where instances.json says (float precision).
      for (const auto& m : s.meshes)
        for (const auto& w : m.instances) {
          const render::Vec3 base = (w * render::Vec4(0, 0, 0, 1)).head<3>();
          double best = INFINITY;
          for (std::uint32_t i : t.instances) {
            const auto& pos = f.instances[i].position;
            best = std::min(best, std::hypot(base.x() - pos[0], base.y() - pos[1], base.z() - pos[2]));
          }
          EXPECT_LT(best, 1e-4);
        }
      if (l == 0) {
        EXPECT_EQ(s.triangle_count(), 12 * t.instances.size());
      }
    }
  for (const char* f2 : {"a_lod0.gltf", "a_lod1.gltf", "b_lod0.gltf", "ground.glb"})
    gltfs.push_back(out / f2);
  // The ground: the flat 100 x 60 m quad under the trees.
  ASSERT_EQ(f.ground, "ground.glb");
  const render::Scene ground = render::load_gltf_scene(out / f.ground);
  EXPECT_EQ(ground.triangle_count(), 2u);
  EXPECT_EQ(ground.bounds().min, render::Vec3(-50, 0, -30));
  EXPECT_EQ(ground.bounds().max, render::Vec3(50, 0, 30));
  for (const auto& v : sylva::test::validate_gltf(gltfs)) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << v.report;
  }

  // tileset.json: 3D Tiles 1.1, REPLACE chains whose geometricError is the levels' epsilon.
  const auto ts = nlohmann::json::parse(sylva::test::read_file(out / "tileset.json"));
  EXPECT_EQ(ts["asset"]["version"], "1.1");
  EXPECT_EQ(ts["root"]["transform"].size(), 16u);
  std::size_t grounds = 0;
  std::function<void(const nlohmann::json&)> walk = [&](const nlohmann::json& n) {
    if (n.contains("content") && n["content"]["uri"] == "ground.glb") {
      ++grounds;  // a leaf under the root: drawn wherever trees are
      EXPECT_EQ(n["geometricError"].get<double>(), 0.0);
      EXPECT_FALSE(n.contains("children"));
      return;
    }
    EXPECT_EQ(n["refine"], "REPLACE");
    if (n.contains("content")) {
      const std::string uri = n["content"]["uri"];
      EXPECT_TRUE(fs::exists(out / uri)) << uri;
      const bool coarse = uri.find("_lod1.gltf") != std::string::npos;
      EXPECT_EQ(n["geometricError"].get<double>(), coarse ? 0.2 : 0.001);
      if (coarse) {
        ASSERT_EQ(n["children"].size(), 1u);
        EXPECT_NE(n["children"][0]["content"]["uri"].get<std::string>().find("_lod0.gltf"),
                  std::string::npos);
      }
    } else {
      EXPECT_GE(n["geometricError"].get<double>(), 5.0);  // drawing nothing costs a whole tree
    }
    for (const auto& c : n.value("children", nlohmann::json::array())) walk(c);
  };
  walk(ts["root"]);
  EXPECT_EQ(grounds, 1u);
  bool ground_child = false;
  for (const auto& c : ts["root"]["children"]) ground_child = ground_child || c.contains("content");
  EXPECT_TRUE(ground_child);

  // cameras.yaml is a camera set libs/render reads.
  const render::CameraSet cams = render::load_camera_set(out / "cameras.yaml");
  EXPECT_EQ(cams.width, 960);
  EXPECT_EQ(cams.msaa, 4);
  EXPECT_EQ(cams.supersample, 2);    // meshes 2 x 2 supersampled, impostors 4x MSAA
  EXPECT_EQ(cams.views.size(), 5u);  // 2 walkthrough, 2 fly-over, 1 overview

  // Determinism: the same parameters give the same bytes; another seed another forest.
  const fs::path again = dir_ / "again";
  run(again, params);
  for (const auto& name : declared_)
    EXPECT_EQ(sylva::test::read_file(out / name), sylva::test::read_file(again / name)) << name;
  Value::Object other = params;
  other["seed"] = Value(std::int64_t(2));
  const forest::Forest g = run(dir_ / "other", other);
  EXPECT_NE(g.instances.at(0).position, f.instances.at(0).position);
}

TEST_F(ForestOutput, BinaryTableAndClearErrors) {
  Value::Object params = {{"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 10))})},
                          {"binary_table_from", Value(std::int64_t(0))}};
  const forest::Forest f = run(dir_ / "bin", params);
  EXPECT_TRUE(f.binary_table);
  EXPECT_TRUE(fs::exists(dir_ / "bin" / "instances.bin"));
  auto error = [&](Value::Object p) {
    try {
      run(dir_ / "err", std::move(p));
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Value::Object one = params;
  one["species"] = Value(Value::List{Value(species("a", 20))});
  EXPECT_EQ(error(one),
            "parameter 'species': lists 1 entries but the node needs 2 lod inputs (one entry per lod input, "
            "in the order of 'needs')");
  Value::Object dup = params;
  dup["species"] = Value(Value::List{Value(species("a", 20)), Value(species("a", 20))});
  EXPECT_EQ(error(dup), "parameter 'species'[1].name: 'a' is the name of species[0] too");
  // A species named like a tile would have its level files overwritten by the tiles'.
  Value::Object tile = params;
  tile["species"] = Value(Value::List{Value(species("tile_0_0", 20)), Value(species("b", 10))});
  EXPECT_EQ(error(tile),
            "parameter 'species'[0].name: 'tile_0_0' must not begin with 'tile_' (the tile files' names)");
  Value::Object longer = params;
  longer["species"] = Value(Value::List{Value(species("a", 20)), Value(species(std::string(65, 'n'), 10))});
  EXPECT_EQ(error(longer),
            "parameter 'species'[1].name: '" + std::string(64, 'n') + "...' is longer than 64 characters");
  Value::Object row = params;
  row["rows"] = Value(Value::List{Value(Value::Object{{"species", Value("c")},
                                                      {"points", Value(Value::List{0.0, 0.0, 10.0, 0.0})},
                                                      {"spacing_m", Value(5.0)},
                                                      {"jitter_m", Value(0.0)}})});
  EXPECT_EQ(error(row), "parameter 'rows'[0].species: 'c' is not in 'species'");
  Value::Object shear = params;
  Value::Object sp = species("a", 20);
  sp["base_rotation_deg"] = Value(Value::List{30.0, 0.0, 0.0});
  shear["species"] = Value(Value::List{Value(sp), Value(species("b", 10))});
  EXPECT_NE(error(shear).find("glTF instancing cannot express"), std::string::npos);
}

// An impostor artifact as the impostor stage writes one: impostor.glb (one card, embedded image)
// and impostor.json with epsilon 0.005 + 0.02 + 0.01 = 0.035 m and a recorded switch distance of
// 100 m for delta = `pixel_error_px` and the chain's camera (45 deg, 1080 rows); `hemi`: a
// hemi-octahedral one (2 x 2 frames of 64 px) with its two maps.
InputArtifact fake_impostor(const fs::path& dir, double h, const std::string& node, bool hemi = false,
                            double pixel_error_px = 0.5) {
  fs::create_directories(dir);
  sylva::test::write_file(dir / "impostor.glb", forest::testing::card_glb(h, true, true));
  impostor::ImpostorInfo i;
  i.kind = hemi ? impostor::Kind::kHemiOctahedral : impostor::Kind::kBillboards;
  i.hemi = hemi;
  i.frames_per_side = hemi ? 2 : 0;
  i.frame_px = 64;
  i.atlas_width_px = i.atlas_height_px = 128;
  i.padding_px = 8;
  i.mip_levels = 3;
  i.bounds_min = {-1, 0, -1};
  i.bounds_max = {1, h, 1};
  i.sphere_center = {0, 0.5 * h, 0};
  i.sphere_radius = h;
  i.frame_half_extent = h * 64 / 48.0;
  i.color_map = "impostor_color.png";
  i.normal_depth_map = "impostor_normal.png";
  i.pixel_error_px = pixel_error_px;
  i.error = {0.005, 0.02, 0.01};
  i.switch_distance_m = 100;
  i.source_type = "lod";
  i.source_file = "lod1.gltf";
  i.source_level = 1;
  impostor::Card c;
  c.name = "card0";
  c.dir = {0, 0, 1};
  c.right = {1, 0, 0};
  c.up = {0, 1, 0};
  c.center = {0, 0.5 * h, 0};
  c.half_width = c.half_height = h;
  c.x = 0, c.y = 0, c.w = 64, c.h = 64;
  c.cutout = {{0.1, 0.9}, {0.9, 0.9}, {0.8, 0.1}, {0.2, 0.1}};
  i.cards.push_back(c);
  i.glb_triangles = 2;
  sylva::test::write_file(dir / "impostor.json", impostor::write_impostor_json(i));
  InputArtifact in;
  in.node = node;
  in.type = "impostor";
  for (const char* f : {"impostor.glb", "impostor.json"}) in.files.push_back({f, dir / f, "0"});
  if (hemi)
    for (const char* f : {"impostor_color.png", "impostor_normal.png"}) {
      const std::vector<std::uint8_t> png = image::encode_png(
          image::Image(128, 128, image::Rgba8{std::uint8_t(f[9] == 'c' ? 60 : 128), 100, 40, 255}));
      sylva::test::write_file(dir / f, std::string(png.begin(), png.end()));
      in.files.push_back({f, dir / f, "0"});
    }
  return in;
}

// A (hemi-)octahedral impostor input: the fallback cards are the tile level, the impostor itself
// (impostor.json naming the forest's copies of both maps) is what forest views draw.
TEST_F(ForestOutput, OctahedralImpostorIsCopiedForTheShader) {
  inputs_.push_back(fake_impostor(dir_ / "imp_a", 8, "imp_a", true));
  inputs_.push_back(fake_impostor(dir_ / "imp_b", 5, "imp_b"));
  const Value::Object params = {
      {"size_m", Value(Value::List{60.0, 60.0})},
      {"tile_size_m", Value(30.0)},
      {"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 40))})}};
  const fs::path out = dir_ / "oct";
  const forest::Forest f = run(out, params);
  EXPECT_EQ(f.species[0].levels.back().octahedral, "a_impostor.json");
  EXPECT_EQ(f.species[0].levels.back().file, "a_impostor.gltf");
  EXPECT_EQ(f.species[1].levels.back().octahedral, "");  // billboards: the cards are the impostor
  const impostor::ImpostorInfo copy = impostor::read_impostor_json((out / "a_impostor.json").string());
  EXPECT_EQ(copy.color_map, "a_impostor_color.png");
  EXPECT_EQ(copy.normal_depth_map, "a_impostor_normal_depth.png");
  EXPECT_EQ(copy.glb_file, "a_impostor.gltf");  // the cards' file in the forest, not impostor.glb
  EXPECT_TRUE(fs::exists(out / copy.glb_file));
  EXPECT_EQ(sylva::test::read_file(out / copy.color_map),
            sylva::test::read_file(dir_ / "imp_a/impostor_color.png"));
  EXPECT_EQ(sylva::test::read_file(out / copy.normal_depth_map),
            sylva::test::read_file(dir_ / "imp_a/impostor_normal.png"));
  EXPECT_FALSE(fs::exists(out / "b_impostor.json"));
  // A forest view loads it as an impostor of 2 x 2 frames of 64 px (no GL needed to load).
  const render::ForestView view = render::ForestView::load(out / "instances.json");
  EXPECT_EQ(view.forest().species[0].levels.back().octahedral, "a_impostor.json");
  // Maps missing from the input: a clear error naming them.
  InputArtifact broken = fake_impostor(dir_ / "imp_c", 8, "imp_c", true);
  broken.files.pop_back();
  inputs_[2] = broken;
  try {
    run(dir_ / "oct2", params);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(),
                 "input 'imp_c' (impostor) has no impostor_color.png and impostor_normal.png though "
                 "impostor.json names them");
  }
}

TEST_F(ForestOutput, ImpostorIsEachSpeciesLastLevel) {
  inputs_.push_back(fake_impostor(dir_ / "imp_a", 8, "imp_a"));
  inputs_.push_back(fake_impostor(dir_ / "imp_b", 5, "imp_b"));
  const Value::Object params = {
      {"size_m", Value(Value::List{60.0, 60.0})},
      {"tile_size_m", Value(30.0)},
      {"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 40))})}};
  const fs::path out = dir_ / "imp";
  const forest::Forest f = run(out, params);
  ASSERT_EQ(f.species.size(), 2u);
  for (const auto& sp : f.species) {
    ASSERT_EQ(sp.levels.size(), 3u);
    const forest::Level& l = sp.levels.back();
    EXPECT_TRUE(l.impostor);
    EXPECT_EQ(l.file, sp.name + "_impostor.gltf");
    EXPECT_NEAR(l.epsilon_m, 0.035, 1e-12);
    // The distance impostor.json records (a proven one: 100 m), not the error model's
    // d = epsilon / (delta s(1)) = 91.3 m; the impostor's camera and delta are the chain's.
    EXPECT_EQ(l.switch_distance_m, 100.0);
    EXPECT_EQ(l.primitives, 2u);
    EXPECT_TRUE(fs::exists(out / (sp.name + "_impostor.bin")));
  }
  // Forest views take it from there: the impostor from 100 m on, not from the model's 91.3 m.
  {
    const render::ForestView view = render::ForestView::load(out / "instances.json");
    EXPECT_EQ(view.level_for(0, 99.9, {}), 0u);  // level 1 is valid from 520 m
    EXPECT_EQ(view.level_for(0, 100.0, {}), 2u);
  }
  // The top tile level instances the impostors; the tileset's chain errors never grow toward the
  // leaves (the impostor's 0.035 is raised to the coarsest lod level's 0.2).
  std::vector<fs::path> gltfs;
  for (const auto& t : f.tiles) {
    const std::string stem = "tile_" + std::to_string(t.ix) + "_" + std::to_string(t.iz);
    const auto top = nlohmann::json::parse(sylva::test::read_file(out / (stem + "_lod2.gltf")));
    bool uses_impostor = false;
    for (const auto& b : top["buffers"])
      uses_impostor = uses_impostor || b["uri"].get<std::string>().ends_with("_impostor.bin");
    EXPECT_TRUE(uses_impostor) << stem;
    for (int l = 0; l < 3; ++l) gltfs.push_back(out / (stem + "_lod" + std::to_string(l) + ".gltf"));
  }
  const auto ts = nlohmann::json::parse(sylva::test::read_file(out / "tileset.json"));
  std::function<void(const nlohmann::json&, double)> walk = [&](const nlohmann::json& n, double parent) {
    EXPECT_LE(n["geometricError"].get<double>(), parent);
    for (const auto& c : n.value("children", nlohmann::json::array()))
      walk(c, n["geometricError"].get<double>());
  };
  walk(ts["root"], ts["geometricError"].get<double>());
  for (const char* f2 : {"a_impostor.gltf", "b_impostor.gltf"}) gltfs.push_back(out / f2);
  for (const auto& v : sylva::test::validate_gltf(gltfs)) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << v.report;
  }
  // One impostor input for two species is an error that says what to do.
  inputs_.pop_back();
  try {
    run(dir_ / "imp_err", params);
    ADD_FAILURE() << "no error";
  } catch (const StageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "the node needs 2 lod inputs and 1 impostor inputs: give every species an impostor (the i-th "
              "impostor input is the i-th lod input's species) or none");
  }
}

// An impostor recorded for another delta than its chain's: its distance moves to where the chain's
// delta allows the same error (100 m at 1 px = 200 m at the chain's 0.5 px); a recorded 0 is an
// error, not a level valid from the eye on.
TEST_F(ForestOutput, ImpostorSwitchDistanceInTheChainsTerms) {
  inputs_.push_back(fake_impostor(dir_ / "imp_a", 8, "imp_a", false, 1.0));
  inputs_.push_back(fake_impostor(dir_ / "imp_b", 5, "imp_b"));
  const Value::Object params = {
      {"size_m", Value(Value::List{60.0, 60.0})},
      {"tile_size_m", Value(30.0)},
      {"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 40))})}};
  const forest::Forest f = run(dir_ / "delta", params);
  EXPECT_NEAR(f.species[0].levels.back().switch_distance_m, 200.0, 1e-9);
  EXPECT_EQ(f.species[1].levels.back().switch_distance_m, 100.0);
  impostor::ImpostorInfo zero = impostor::read_impostor_json((dir_ / "imp_b/impostor.json").string());
  zero.switch_distance_m = 0;
  sylva::test::write_file(dir_ / "imp_b/impostor.json", impostor::write_impostor_json(zero));
  try {
    run(dir_ / "zero", params);
    ADD_FAILURE() << "no error";
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(),
                 "input 'imp_b' (impostor): impostor.json records no switch distance (switch_distance_m 0)");
  }
}

// A 45-degree camera 2 m above the ground on the z axis at `z`, looking at the origin's column.
render::Camera camera_on_z_axis(float z, float z_far) {
  render::Camera cam;
  cam.eye = render::Vec3(0, 2, z);
  cam.target = render::Vec3(0, 2, 0);
  cam.fov_y_deg = 45;
  cam.z_near = 1;
  cam.z_far = z_far;
  return cam;
}

// ForestViewStats: per species and level, the trees drawn and exactly their level's primitives
// each (the level switches at 520 m: a view from ~540 m sees species a at both levels).
TEST_F(ForestOutput, ViewStatsCountTreesAndPrimitivesPerSpeciesAndLevel) {
  const Value::Object params = {
      {"size_m", Value(Value::List{100.0, 60.0})},
      {"tile_size_m", Value(50.0)},
      {"species", Value(Value::List{Value(species("a", 20)), Value(species("b", 40))})}};
  const fs::path out = dir_ / "stats";
  const forest::Forest f = run(out, params);
  const render::ForestView view = render::ForestView::load(out / "instances.json");
  const render::Camera cam = camera_on_z_axis(530, 1000);
  render::ForestViewOptions all;
  all.cull = false;
  render::ForestViewStats st;
  view.view_scene(cam, 1.f, all, st);
  // Expected from instances.json alone: each tree's box distance against its levels' switch
  // distances, each level's primitives from the file.
  std::vector<std::vector<std::size_t>> trees, prims;
  std::size_t total = 2;  // the ground's quad
  for (const forest::Species& sp : f.species) {
    trees.emplace_back(sp.levels.size(), 0);
    prims.emplace_back(sp.levels.size(), 0);
  }
  for (const forest::Instance& in : f.instances) {
    const forest::Species& sp = f.species[in.species];
    const forest::Box3 box = forest::transform_box(forest::instance_matrix(sp, in), sp.bounds);
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::max({box.min[k] - cam.eye[k], 0.0, cam.eye[k] - box.max[k]});
      d2 += e * e;
    }
    std::size_t l = 0;
    while (l + 1 < sp.levels.size() && sp.levels[l + 1].switch_distance_m <= std::sqrt(d2)) ++l;
    ++trees[in.species][l];
    prims[in.species][l] += sp.levels[l].primitives;
    total += sp.levels[l].primitives;
  }
  EXPECT_GT(trees[0][0], 0u);
  EXPECT_GT(trees[0][1], 0u);  // the view sees species a at both levels
  EXPECT_EQ(st.species_trees, trees);
  EXPECT_EQ(st.species_primitives, prims);
  EXPECT_EQ(st.primitives, total);
  EXPECT_EQ(st.trees_drawn, f.instances.size());
  EXPECT_TRUE(st.impostor_steps.empty());
}

// Records the geometry names and atlases each call is given, and draws nothing.
class RecordingRenderer final : public render::Renderer {
 public:
  std::vector<image::Image> render_views(const render::Scene& scene, std::span<const render::Camera> cameras,
                                         const render::RenderOptions& options) override {
    std::set<const void*> names;
    record(scene, names);
    for (const void* n : names) not_prepared_when_drawn += prepared.count(n) == 0 ? 1 : 0;
    drawn.insert(names.begin(), names.end());
    return std::vector<image::Image>(cameras.size(), image::Image(options.width, options.height, {}));
  }
  void prepare(const render::Scene& scene, const render::RenderOptions&) override { record(scene, prepared); }
  std::string device_description() const override { return "recording"; }

  static void record(const render::Scene& scene, std::set<const void*>& into) {
    for (const render::Mesh& m : scene.meshes)
      if (m.shared_geometry) into.insert(m.shared_geometry.get());
    for (const render::ImpostorSet& s : scene.impostors) into.insert(s.atlas.get());
  }

  std::set<const void*> prepared, drawn;
  std::size_t not_prepared_when_drawn = 0;
};

// ForestView::prepare hands the renderer every (species, level) mesh and impostor atlas its
// cameras' views draw, and render() prepares them all before it draws the first view.
TEST_F(ForestOutput, PrepareHandsTheRendererEverythingTheViewsDraw) {
  inputs_.push_back(fake_impostor(dir_ / "imp_a", 8, "imp_a", true));
  inputs_.push_back(fake_impostor(dir_ / "imp_b", 5, "imp_b", true));
  const Value::Object params = {
      {"size_m", Value(Value::List{60.0, 60.0})},
      {"tile_size_m", Value(30.0)},
      {"species", Value(Value::List{Value(species("a", 40)), Value(species("b", 40))})}};
  const fs::path out = dir_ / "prep";
  run(out, params);
  const render::ForestView view = render::ForestView::load(out / "instances.json");
  // From 160 m every tree is an impostor (from 100 m on); from 40 m none is.
  const std::vector<render::Camera> cams = {camera_on_z_axis(160, 400), camera_on_z_axis(40, 400)};
  render::RenderOptions o;
  o.width = o.height = 16;
  std::set<const void*> want;
  std::size_t atlases = 0;
  for (const render::Camera& c : cams) {
    render::ForestViewStats st;
    const render::Scene s = view.view_scene(c, 1.f, {}, st);
    atlases += s.impostors.empty() ? 0 : 1;
    RecordingRenderer::record(s, want);
  }
  EXPECT_EQ(atlases, 1u) << "one camera sees impostors, the other meshes";
  EXPECT_GE(want.size(), 4u);  // two atlases, levels of both species and the ground
  RecordingRenderer prepared;
  view.prepare(prepared, cams, o);
  EXPECT_EQ(prepared.prepared, want);
  EXPECT_TRUE(prepared.drawn.empty());
  render::ForestView drawn = render::ForestView::load(out / "instances.json");
  RecordingRenderer rendered;
  EXPECT_EQ(drawn.render(rendered, cams, o).size(), 2u);
  EXPECT_EQ(rendered.drawn.size(), want.size());
  EXPECT_EQ(rendered.prepared.size(), want.size());
  EXPECT_EQ(rendered.not_prepared_when_drawn, 0u);
}

// Forest views draw a level's coincident blended lines as one line that counts its copies
// (render::merge_line_copies): the twig's three lines are one, standing for 3.
TEST_F(ForestOutput, ViewsDrawCoincidentLineCopiesAsOneLine) {
  inputs_ = {fake_lod(dir_ / "lod_t", 2, 8, "lod_a", true)};
  const Value::Object params = {{"size_m", Value(Value::List{40.0, 40.0})},
                                {"tile_size_m", Value(40.0)},
                                {"species", Value(Value::List{Value(species("a", 20))})}};
  const fs::path out = dir_ / "twigs";
  run(out, params);
  const render::ForestView view = render::ForestView::load(out / "instances.json");
  render::ForestViewOptions all;
  all.cull = false;
  render::ForestViewStats st;
  const render::Scene scene = view.view_scene(camera_on_z_axis(600, 2000), 1.f, all, st);
  std::size_t line_primitives = 0;
  for (const render::Mesh& m : scene.meshes)
    for (const render::Primitive& p : m.primitives) {
      if (p.topology != render::Topology::kLines) continue;
      ++line_primitives;
      EXPECT_EQ(p.element_count(), 1u);
      EXPECT_EQ(p.copies, (std::vector<float>{3, 3}));
    }
  EXPECT_EQ(line_primitives, 1u);
}

// A tile level with bark lines: clients instance only triangle meshes (three.js draws an instanced
// mesh with lines once), so the tile instances the level's triangles and draws its lines with one
// plain node per tree (children of `<species>_lines`), each placed as the tree's instance.
TEST_F(ForestOutput, TileLinesAreDrawnByOneNodePerTree) {
  inputs_ = {fake_lod(dir_ / "lod_t", 2, 8, "lod_a", true)};
  const Value::Object params = {{"size_m", Value(Value::List{40.0, 40.0})},
                                {"tile_size_m", Value(40.0)},
                                {"species", Value(Value::List{Value(species("a", 20))})}};
  const fs::path out = dir_ / "tile_lines";
  const forest::Forest f = run(out, params);
  ASSERT_EQ(f.tiles.size(), 1u);
  const std::size_t trees = f.tiles[0].instances.size();
  ASSERT_GE(trees, 2u);
  // Level 0 has no lines: one instanced node, no line nodes.
  const auto lod0 = nlohmann::json::parse(sylva::test::read_file(out / "tile_0_0_lod0.gltf"));
  ASSERT_EQ(lod0["nodes"].size(), 1u);
  EXPECT_TRUE(lod0["nodes"][0]["extensions"].contains("EXT_mesh_gpu_instancing"));
  // Level 1: the instanced node's mesh holds the triangles only; the lines are drawn per tree.
  const fs::path tile1 = out / "tile_0_0_lod1.gltf";
  const auto g = nlohmann::json::parse(sylva::test::read_file(tile1));
  ASSERT_EQ(g["nodes"].size(), 2 + trees);
  EXPECT_EQ(g["scenes"][0]["nodes"], nlohmann::json({0, 1}));
  const auto& inst = g["nodes"][0];
  EXPECT_EQ(inst["name"], "a");
  ASSERT_TRUE(inst["extensions"].contains("EXT_mesh_gpu_instancing"));
  for (const auto& p : g["meshes"][inst["mesh"].get<std::size_t>()]["primitives"])
    EXPECT_EQ(p.value("mode", 4), 4);
  const auto& lines = g["nodes"][1];
  EXPECT_EQ(lines["name"], "a_lines");
  EXPECT_EQ(lines["translation"], inst["translation"]);
  EXPECT_FALSE(lines.contains("mesh"));
  ASSERT_EQ(lines["children"].size(), trees);
  for (std::size_t k = 0; k < trees; ++k) {
    const auto& n = g["nodes"][lines["children"][k].get<std::size_t>()];
    EXPECT_EQ(n["extras"]["instance_id"], f.instances[f.tiles[0].instances[k]].id);
    EXPECT_FALSE(n.contains("extensions"));
    for (const auto& p : g["meshes"][n["mesh"].get<std::size_t>()]["primitives"]) EXPECT_EQ(p["mode"], 1);
  }
  // Every tree's triangles and lines stand at the same place, with the same transform.
  const render::Scene s = render::load_gltf_scene(tile1);
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.meshes[0].instances.size(), trees);
  ASSERT_EQ(s.meshes[1].instances.size(), trees);
  for (std::size_t k = 0; k < trees; ++k)
    EXPECT_TRUE(s.meshes[0].instances[k].isApprox(s.meshes[1].instances[k], 1e-6f)) << k;
  EXPECT_EQ(s.line_count(), 3 * trees);  // the twig's three coincident lines per tree
  EXPECT_EQ(s.triangle_count(), 2 * trees);
  for (const auto& v : sylva::test::validate_gltf({tile1, out / "tile_0_0_lod0.gltf"})) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << v.report;
  }
}

// tile_instancing: nodes — no extension: each tree one plain node drawing its species' whole
// level mesh, placed as gpu instancing places it; the same primitives; no tile .bin.
TEST_F(ForestOutput, NodeTilesDrawTheSameTreesWithoutTheExtension) {
  inputs_ = {fake_lod(dir_ / "lod_t", 2, 8, "lod_a", true)};
  Value::Object params = {{"size_m", Value(Value::List{40.0, 40.0})},
                          {"tile_size_m", Value(40.0)},
                          {"species", Value(Value::List{Value(species("a", 20))})}};
  const fs::path gpu_out = dir_ / "gpu", nodes_out = dir_ / "nodes";
  const forest::Forest f = run(gpu_out, params);
  params["tile_instancing"] = Value(std::string("nodes"));
  EXPECT_EQ(run(nodes_out, params), f);  // the same forest
  ASSERT_EQ(f.tiles.size(), 1u);
  const std::size_t trees = f.tiles[0].instances.size();
  EXPECT_TRUE(fs::exists(gpu_out / "tile_0_0.bin"));
  EXPECT_FALSE(fs::exists(nodes_out / "tile_0_0.bin"));
  std::vector<fs::path> files;
  for (int l = 0; l < 2; ++l) {
    SCOPED_TRACE(l);
    const std::string name = "tile_0_0_lod" + std::to_string(l) + ".gltf";
    const fs::path p = nodes_out / name;
    files.push_back(p);
    const auto g = nlohmann::json::parse(sylva::test::read_file(p));
    EXPECT_FALSE(g.contains("extensionsUsed"));
    EXPECT_FALSE(g.contains("extensionsRequired"));
    ASSERT_EQ(g["nodes"].size(), 1 + trees);
    EXPECT_EQ(g["nodes"][0]["name"], "a");
    EXPECT_EQ(g["meshes"].size(), 1u);
    for (std::size_t k = 0; k < trees; ++k) {
      const auto& n = g["nodes"][g["nodes"][0]["children"][k].get<std::size_t>()];
      EXPECT_EQ(n["mesh"], 0);
      EXPECT_EQ(n["extras"]["instance_id"], f.instances[f.tiles[0].instances[k]].id);
    }
    const render::Scene a = render::load_gltf_scene(gpu_out / name), b = render::load_gltf_scene(p);
    EXPECT_EQ(b.triangle_count(), a.triangle_count());
    EXPECT_EQ(b.line_count(), a.line_count());
    ASSERT_EQ(b.meshes.size(), 1u);
    ASSERT_EQ(b.meshes[0].instances.size(), trees);
    for (std::size_t k = 0; k < trees; ++k)
      EXPECT_TRUE(b.meshes[0].instances[k].isApprox(a.meshes[0].instances[k], 1e-6f)) << k;
  }
  for (const auto& v : sylva::test::validate_gltf(files)) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << v.report;
  }
}

// species[i].impostor_parallax: from each proven distance on, the octahedral impostor is drawn
// with fewer parallax steps (16 nearer); forest views group the impostors by steps.
TEST_F(ForestOutput, ImpostorParallaxTableSetsTheStepsByDistance) {
  inputs_.push_back(fake_impostor(dir_ / "imp_a", 8, "imp_a", true));
  inputs_.push_back(fake_impostor(dir_ / "imp_b", 5, "imp_b", true));
  Value::Object a = species("a", 40), b = species("b", 40);
  a["impostor_parallax"] = Value(Value::List{140.0, 4.0, 170.0, 0.0});
  const Value::Object params = {{"size_m", Value(Value::List{60.0, 60.0})},
                                {"tile_size_m", Value(30.0)},
                                {"species", Value(Value::List{Value(a), Value(b)})}};
  const fs::path out = dir_ / "par";
  const forest::Forest f = run(out, params);
  const std::vector<forest::ParallaxStep> want = {{140, 4}, {170, 0}};
  EXPECT_EQ(f.species[0].levels.back().parallax, want);
  EXPECT_TRUE(f.species[1].levels.back().parallax.empty());
  const render::ForestView view = render::ForestView::load(out / "instances.json");
  EXPECT_EQ(view.parallax_steps_for(0, 139.9, {}), 16);
  EXPECT_EQ(view.parallax_steps_for(0, 140, {}), 4);
  EXPECT_EQ(view.parallax_steps_for(0, 169.9, {}), 4);
  EXPECT_EQ(view.parallax_steps_for(0, 170, {}), 0);
  EXPECT_EQ(view.parallax_steps_for(1, 1e6, {}), 16);
  render::ForestViewOptions coarse;
  coarse.pixel_error_px = 1.0;  // twice the chain's delta: every distance halves
  EXPECT_EQ(view.parallax_steps_for(0, 70, coarse), 4);
  // A view from 160 m: every tree an impostor (from 100 m), species a's split by the table.
  const render::Camera cam = camera_on_z_axis(160, 400);
  render::ForestViewStats st;
  const render::Scene scene = view.view_scene(cam, 1.f, {}, st);
  std::map<int, std::size_t> expect;
  std::size_t a_trees = 0;
  for (const forest::Instance& in : f.instances) {
    const auto m = forest::instance_matrix(f.species[in.species], in);
    const forest::Box3 box = forest::transform_box(m, f.species[in.species].bounds);
    double d2 = 0;
    const double eye[3] = {0, 2, 160};
    for (int k = 0; k < 3; ++k) {
      const double e = std::max({box.min[k] - eye[k], 0.0, eye[k] - box.max[k]});
      d2 += e * e;
    }
    ASSERT_GE(std::sqrt(d2), 100.0);
    ++expect[in.species == 0 ? view.parallax_steps_for(0, std::sqrt(d2), {}) : 16];
    a_trees += in.species == 0;
  }
  EXPECT_EQ(st.trees_drawn, f.instances.size());  // all in view
  EXPECT_EQ(st.impostors, f.instances.size());
  EXPECT_EQ(st.impostor_steps, expect);
  EXPECT_EQ(expect.size(), 3u) << "the table splits species a's impostors three ways";
  EXPECT_EQ(st.species_trees[0].back(), a_trees);
  EXPECT_EQ(st.species_primitives[0].back(), 2 * a_trees);
  std::size_t in_sets = 0;
  for (const render::ImpostorSet& set : scene.impostors) {
    EXPECT_EQ(expect.count(set.parallax_steps), 1u);
    in_sets += set.instances.size();
  }
  EXPECT_EQ(in_sets, f.instances.size());
  // Loading reads the files in parallel; a failure is reported for the first file in order.
  fs::remove(out / "b_lod0.gltf");
  fs::remove(out / "a_lod1.gltf");
  try {
    render::ForestView::load(out / "instances.json");
    ADD_FAILURE() << "no error";
  } catch (const render::SceneLoadError& e) {
    EXPECT_NE(std::string(e.what()).find("a_lod1.gltf"), std::string::npos) << e.what();
  }
  // Bad tables are errors that say what is wrong.
  auto error_of = [&](Value::List table, bool on_b) {
    Value::Object sa = species("a", 40), sb = species("b", 40);
    (on_b ? sb : sa)["impostor_parallax"] = Value(std::move(table));
    Value::Object p = params;
    p["species"] = Value(Value::List{Value(sa), Value(sb)});
    try {
      run(dir_ / "bad", p);
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of({140.0, 4.0, 170.0}, false),
            "parameter 'species'[0].impostor_parallax: must be pairs [from_m, steps, ...], got 3 numbers");
  EXPECT_EQ(error_of({140.0, 4.5}, false),
            "parameter 'species'[0].impostor_parallax: steps must be integers 0..64, got 4.5");
  EXPECT_EQ(error_of({140.0, 4.0, 140.0, 0.0}, false),
            "parameter 'species'[0].impostor_parallax: distances must increase, got 140 after 140");
  inputs_[3] = fake_impostor(dir_ / "imp_b2", 5, "imp_b");  // billboards
  EXPECT_EQ(error_of({140.0, 4.0}, true),
            "species 'b': impostor_parallax needs a (hemi-)octahedral impostor input for the species");
}

}  // namespace
}  // namespace sylva
