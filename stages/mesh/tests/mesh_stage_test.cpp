// The adapter: declaration, tree.sylt + textures in, one valid GLB (or .gltf) out with the sylva
// extras, Draco within the quantisation error, deterministic bytes; bad input is a StageError.
#include "stages/mesh/mesh_stage.h"

#include <draco/compression/decode.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "libs/image/image.h"
#include "libs/image/image_io.h"
#include "libs/tree/sylt_format.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/mesh/tests/test_trees.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// A StageContext with one upstream "tree" artifact made of the files in `input_dir`.
struct FakeContext : test::FakeStageContext {
  FakeContext(const Stage& stage, const fs::path& input_dir, fs::path out,
              const Value::Object& overrides = {})
      : FakeStageContext(stage, {{"gen", "tree", input_dir}}, std::move(out), overrides) {
    name = "mesh_node";
  }
};

void write_png(const generate::Rgba8& px, const fs::path& path) {
  image::Image img(px.width, px.height);
  img.bytes() = px.pixels;
  image::write_png(img, path);
}

// The generate stage's artifact for a young preset: tree.sylt, bark.png, leaves.png.
void write_tree_artifact(const fs::path& dir, const std::string& species = "oak") {
  const fs::path preset = fs::path(SYLVA_SOURCE_DIR) / "configs/species" / (species + ".yaml");
  const generate::SpeciesPreset sp = generate::load_species_preset(preset);
  tree::Tree t = mesh::test::species_tree(preset, "young");
  t.materials.bark_texture = "bark.png";
  t.materials.leaf_texture = "leaves.png";
  tree::write_sylt(dir / "tree.sylt", t);
  Rng b(1, "bark"), l(1, "leaves");
  write_png(generate::make_bark_texture(sp.bark, 64, b), dir / "bark.png");
  write_png(generate::make_leaf_atlas(sp.leaf, 64, l), dir / "leaves.png");
}

nlohmann::json glb_json(const std::string& b) {
  std::uint32_t len = 0;
  std::memcpy(&len, b.data() + 12, 4);
  return nlohmann::json::parse(b.substr(20, len));
}

std::string glb_bin(const std::string& b) {
  std::uint32_t json_len = 0, bin_len = 0;
  std::memcpy(&json_len, b.data() + 12, 4);
  std::memcpy(&bin_len, b.data() + 20 + json_len, 4);
  return b.substr(20 + json_len + 8, bin_len);
}

// The declaration: name, output type, one tree input, every parameter documented.
TEST(MeshStage, Declaration) {
  const auto stage = make_mesh_stage();
  const StageInfo& info = stage->info();
  EXPECT_EQ(info.name, "mesh");
  EXPECT_EQ(info.output_type, "mesh");
  EXPECT_EQ(info.inputs.types, std::vector<std::string>{"tree"});
  EXPECT_EQ(info.inputs.min, 1);
  EXPECT_EQ(info.inputs.max, 1);
  std::set<std::string> names;
  for (const auto& p : info.params) {
    EXPECT_FALSE(p.doc.empty()) << p.name;
    EXPECT_FALSE(p.required()) << p.name;
    names.insert(p.name);
  }
  for (const char* n :
       {"max_level", "subdivision", "open_base", "foliage", "draco", "draco_position_bits", "format"})
    EXPECT_EQ(names.count(n), 1u) << n;
}

// A generated tree with its textures: one GLB, valid, textured bark and alpha-masked
// double-sided leaves, sylva extras (no node name: it is not part of the action key), stable bytes.
TEST(MeshStage, WritesAValidTexturedGlb) {
  sylva::test::TempDir in, out1, out2;
  write_tree_artifact(in.path());
  const auto stage = make_mesh_stage();
  FakeContext ctx(*stage, in.path(), out1.path());
  stage->run(ctx);
  EXPECT_EQ(ctx.declared, (std::set<std::string>{"tree.glb"}));
  const fs::path glb = out1 / "tree.glb";
  const std::string bytes = sylva::test::read_file(glb);
  const nlohmann::json j = glb_json(bytes);
  ASSERT_EQ(j["images"].size(), 2u);
  ASSERT_EQ(j["materials"].size(), 2u);
  EXPECT_EQ(j["materials"][0]["name"], "bark");
  EXPECT_TRUE(j["materials"][0]["pbrMetallicRoughness"].contains("baseColorTexture"));
  EXPECT_EQ(j["materials"][1]["name"], "leaves");
  EXPECT_EQ(j["materials"][1]["alphaMode"], "MASK");
  EXPECT_EQ(j["materials"][1]["doubleSided"], true);
  const nlohmann::json& sylva = j["asset"]["extras"]["sylva"];
  EXPECT_EQ(sylva["stage"], "mesh");
  EXPECT_EQ(sylva["stage_version"], stage->info().version);
  EXPECT_EQ(sylva["source"], "oak/young seed 1");
  EXPECT_EQ(sylva["parameters"]["subdivision"], 1);
  EXPECT_GT(sylva["statistics"]["quads"].get<int>(), 0);
  EXPECT_EQ(sylva["statistics"]["euler_characteristic"], 2);
  EXPECT_EQ(bytes.find("mesh_node"), std::string::npos);
  // The PNGs are embedded byte for byte.
  EXPECT_NE(bytes.find(sylva::test::read_file(in / "bark.png")), std::string::npos);

  FakeContext again(*stage, in.path(), out2.path());
  stage->run(again);
  EXPECT_EQ(sylva::test::read_file(out2 / "tree.glb"), bytes);
  SYLVA_EXPECT_VALID_GLTF(glb);
}

// format: gltf writes one self-contained tree.gltf that validates.
TEST(MeshStage, GltfFormat) {
  sylva::test::TempDir in, out;
  write_tree_artifact(in.path(), "scots_pine");
  const auto stage = make_mesh_stage();
  FakeContext ctx(*stage, in.path(), out.path(), {{"format", "gltf"}, {"subdivision", 0}, {"max_level", 1}});
  stage->run(ctx);
  EXPECT_EQ(ctx.declared, (std::set<std::string>{"tree.gltf"}));
  SYLVA_EXPECT_VALID_GLTF(out / "tree.gltf");
}

// Draco: the file validates and every decoded bark position lies within the quantisation error
// of a position of the uncompressed file.
TEST(MeshStage, DracoRoundTripWithinQuantisationError) {
  sylva::test::TempDir in, plain_out, draco_out;
  write_tree_artifact(in.path(), "holly");
  const auto stage = make_mesh_stage();
  const Value::Object base = {{"subdivision", 0}, {"max_level", 1}, {"foliage", false}};
  FakeContext plain(*stage, in.path(), plain_out.path(), base);
  stage->run(plain);
  Value::Object with_draco = base;
  with_draco["draco"] = true;
  with_draco["draco_position_bits"] = 12;
  FakeContext compressed(*stage, in.path(), draco_out.path(), with_draco);
  stage->run(compressed);

  const std::string pb = sylva::test::read_file(plain_out / "tree.glb");
  const std::string db = sylva::test::read_file(draco_out / "tree.glb");
  EXPECT_LT(db.size(), pb.size() / 2);
  // Uncompressed positions of the bark primitive.
  const nlohmann::json pj = glb_json(pb);
  const nlohmann::json& pacc =
      pj["accessors"][pj["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<std::size_t>()];
  const nlohmann::json& pview = pj["bufferViews"][pacc["bufferView"].get<std::size_t>()];
  const std::string pbin = glb_bin(pb);
  const std::size_t n = pacc["count"];
  std::vector<float> pos(3 * n);
  std::memcpy(pos.data(), pbin.data() + pview.value("byteOffset", std::size_t{0}), pos.size() * 4);
  double extent = 0;
  for (int c = 0; c < 3; ++c)
    extent = std::max(extent, pacc["max"][static_cast<std::size_t>(c)].get<double>() -
                                  pacc["min"][static_cast<std::size_t>(c)].get<double>());
  const double tolerance = extent / ((1 << 12) - 1) / 2 * 1.001 + 1e-6;
  // A grid of cells one tolerance wide for the nearest-point search.
  std::map<std::array<long long, 3>, std::vector<std::size_t>> grid;
  auto cell = [&](double x, double y, double z) {
    return std::array<long long, 3>{std::llround(std::floor(x / tolerance)),
                                    std::llround(std::floor(y / tolerance)),
                                    std::llround(std::floor(z / tolerance))};
  };
  for (std::size_t i = 0; i < n; ++i) grid[cell(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2])].push_back(i);

  const nlohmann::json dj = glb_json(db);
  const nlohmann::json& ext = dj["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"];
  const nlohmann::json& dview = dj["bufferViews"][ext["bufferView"].get<std::size_t>()];
  const std::string dbin = glb_bin(db);
  draco::DecoderBuffer buffer;
  buffer.Init(dbin.data() + dview.value("byteOffset", std::size_t{0}),
              dview["byteLength"].get<std::size_t>());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  ASSERT_TRUE(decoded.ok()) << decoded.status().error_msg();
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  const draco::PointAttribute* att =
      dm->GetAttributeByUniqueId(ext["attributes"]["POSITION"].get<std::uint32_t>());
  ASSERT_NE(att, nullptr);
  std::size_t outside = 0;
  for (draco::PointIndex i(0); i < dm->num_points(); ++i) {
    std::array<float, 3> q{};
    att->GetMappedValue(i, q.data());
    const auto c = cell(q[0], q[1], q[2]);
    bool found = false;
    for (long long dx = -1; dx <= 1 && !found; ++dx)
      for (long long dy = -1; dy <= 1 && !found; ++dy)
        for (long long dz = -1; dz <= 1 && !found; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (std::size_t k : it->second)
            if (std::abs(q[0] - pos[3 * k]) <= tolerance && std::abs(q[1] - pos[3 * k + 1]) <= tolerance &&
                std::abs(q[2] - pos[3 * k + 2]) <= tolerance) {
              found = true;
              break;
            }
        }
    outside += !found;
  }
  EXPECT_EQ(outside, 0u) << "of " << dm->num_points() << " decoded points";
  EXPECT_EQ(
      dj["accessors"][dj["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<std::size_t>()]["count"],
      dm->num_points());
  SYLVA_EXPECT_VALID_GLTF(draco_out / "tree.glb");
}

// Bad input never crashes: missing files and unmeshable trees are StageErrors naming the file.
TEST(MeshStage, BadInputIsAStageError) {
  const auto stage = make_mesh_stage();
  auto message = [&](const fs::path& in_dir) {
    sylva::test::TempDir out;
    FakeContext ctx(*stage, in_dir, out.path());
    try {
      stage->run(ctx);
    } catch (const StageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  {
    sylva::test::TempDir in;
    sylva::test::write_file(in / "other.txt", "x");
    EXPECT_EQ(message(in.path()), "input 'gen' has no tree.sylt");
  }
  {
    sylva::test::TempDir in;
    sylva::test::write_file(in / "tree.sylt", "not a tree");
    EXPECT_NE(message(in.path()).find("tree.sylt: not a .sylt file"), std::string::npos)
        << message(in.path());
  }
  {
    sylva::test::TempDir in;
    tree::Tree t = mesh::test::straight_trunk(3);
    t.materials.bark_texture = "bark.png";
    tree::write_sylt(in / "tree.sylt", t);
    EXPECT_NE(message(in.path()).find("the tree's bark texture 'bark.png' is not a file of input 'gen'"),
              std::string::npos)
        << message(in.path());
    sylva::test::write_file(in / "bark.png", "GIF89a");
    EXPECT_NE(message(in.path()).find("texture 'bark.png' is neither a PNG nor a JPEG file"),
              std::string::npos)
        << message(in.path());
  }
  {
    sylva::test::TempDir in;
    tree::write_sylt(in / "tree.sylt", tree::Tree{});  // an empty tree is a valid .sylt
    EXPECT_NE(message(in.path()).find("tree.sylt: the tree has no branches: nothing to mesh"),
              std::string::npos)
        << message(in.path());
  }
}

// A branch of zero radius (documented result): meshed at min_radius_m, a valid GLB.
TEST(MeshStage, ZeroRadiusBranchIsMeshedAtMinRadius) {
  sylva::test::TempDir in, out;
  tree::Tree t = mesh::test::straight_trunk(3);
  t.branches.push_back(mesh::test::branch({{0.3, 1.05, 0}, {1.0, 1.4, 0}}, 0.0, 0, 1, 1));
  tree::write_sylt(in / "tree.sylt", t);
  const auto stage = make_mesh_stage();
  FakeContext ctx(*stage, in.path(), out.path());
  stage->run(ctx);
  const nlohmann::json j = glb_json(sylva::test::read_file(out / "tree.glb"));
  EXPECT_EQ(j["asset"]["extras"]["sylva"]["statistics"]["skeleton"]["clamped_radii"], 2);
  SYLVA_EXPECT_VALID_GLTF(out / "tree.glb");
}

}  // namespace
}  // namespace sylva
