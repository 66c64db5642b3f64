// Tests of the lod output: the stage adapter end to end, MSFT_lod linking, per-level files,
// extras and the glTF-Validator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>

#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/tree/default_colors.h"
#include "libs/tree/sylt_format.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/lod_stage.h"
#include "stages/lod/tests/test_trees.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

struct FakeContext : sylva::test::FakeStageContext {
  FakeContext(const Stage& stage, const fs::path& input_dir, fs::path out,
              const Value::Object& overrides = {})
      : FakeStageContext(stage, {{"gen", "tree", input_dir}}, std::move(out), overrides) {
    name = "lod_node";
  }
};

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(sylva::test::read_file(p)); }

// The float / index data of an accessor of an external .gltf in `dir` (no Draco, tight views).
template <typename T>
std::vector<T> accessor(const fs::path& dir, const nlohmann::json& j, int index) {
  const auto& a = j["accessors"][index];
  const auto& v = j["bufferViews"][a["bufferView"].get<int>()];
  const std::string bin =
      sylva::test::read_file(dir / j["buffers"][v["buffer"].get<int>()]["uri"].get<std::string>());
  const std::size_t comps = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC2" ? 2 : a["type"] == "VEC3" ? 3 : 4;
  std::vector<T> out(a["count"].get<std::size_t>() * comps);
  std::memcpy(out.data(), bin.data() + v.value("byteOffset", 0), out.size() * sizeof(T));
  return out;
}

std::vector<std::uint32_t> indices(const fs::path& dir, const nlohmann::json& j, int index) {
  if (j["accessors"][index]["componentType"] == 5123) {
    const auto s = accessor<std::uint16_t>(dir, j, index);
    return {s.begin(), s.end()};
  }
  return accessor<std::uint32_t>(dir, j, index);
}

// Checks of the stage's outputs for one species, in the order the test below runs them. A helper
// with an ASSERT is called through ASSERT_NO_FATAL_FAILURE, so a fatal failure stops the test.

// The declared outputs include lod.gltf, lod.json, full.glb and lod<i>.gltf/.bin for the 4
// levels; returns the others.
std::set<std::string> declared_beyond_levels(const std::set<std::string>& declared) {
  std::set<std::string> expected = {"lod.gltf", "lod.json", "full.glb"};
  for (int i = 0; i < 4; ++i)
    for (const char* ext : {".gltf", ".bin"}) expected.insert("lod" + std::to_string(i) + ext);
  std::set<std::string> extra;
  std::set_difference(declared.begin(), declared.end(), expected.begin(), expected.end(),
                      std::inserter(extra, extra.end()));
  for (const auto& e : expected) EXPECT_TRUE(declared.count(e)) << e;
  return extra;
}

// The ribbons files lod.json names, each with its .bin.
std::set<std::string> ribbon_files_of(const nlohmann::json& summary) {
  std::set<std::string> ribbon_files;
  for (const auto& l : summary["levels"])
    if (l.contains("ribbons_file")) {
      const std::string f = l["ribbons_file"];
      ribbon_files.insert(f);
      ribbon_files.insert(f.substr(0, f.size() - 5) + ".bin");
    }
  return ribbon_files;
}

// full.glb, the full-detail model, is a GLB with more triangles than level 0.
void expect_full_detail(const fs::path& out, std::vector<fs::path>& to_validate) {
  const std::string full = sylva::test::read_file(out / "full.glb");
  ASSERT_EQ(full.compare(0, 4, "glTF"), 0);
  auto triangles = [](const gltf::Scene& scene) {
    std::size_t n = 0;
    for (const auto& m : scene.meshes)
      for (const auto& p : m.primitives)
        if (p.mode == gltf::PrimitiveMode::kTriangles) n += p.indices.size() / 3;
    return n;
  };
  EXPECT_GT(triangles(gltf::read_scene(out / "full.glb")), triangles(gltf::read_scene(out / "lod0.gltf")));
  to_validate.push_back(out / "full.glb");
}

// lod.gltf (`j`) links every level with MSFT_lod and reads the levels' own lod<i>.bin.
void expect_levels_linked(const nlohmann::json& j, const fs::path& out) {
  EXPECT_EQ(j["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json({1, 2, 3}));
  EXPECT_EQ(j["scene"], 0);
  EXPECT_EQ(j["scenes"][0]["nodes"], nlohmann::json({0}));
  EXPECT_NE(std::find(j["extensionsUsed"].begin(), j["extensionsUsed"].end(), "MSFT_lod"),
            j["extensionsUsed"].end());
  ASSERT_EQ(j["buffers"].size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const std::string bin = "lod" + std::to_string(i) + ".bin";
    EXPECT_EQ(j["buffers"][i]["uri"], bin);
    EXPECT_EQ(j["buffers"][i]["byteLength"].get<std::size_t>(), fs::file_size(out / bin));
    EXPECT_EQ(read_json(out / ("lod" + std::to_string(i) + ".gltf"))["buffers"][0]["uri"], bin);
  }
}

// Screen coverages are screen fractions: non-increasing, in [0, 1], last 0, as lod.json says;
// unclamped ones invert (coverage_distance()) to the next level's switch distance.
void expect_screen_coverages(const nlohmann::json& j, const nlohmann::json& summary) {
  const auto cov = j["nodes"][0]["extras"]["MSFT_screencoverage"];
  ASSERT_EQ(cov.size(), 4u);
  for (std::size_t i = 0; i < cov.size(); ++i) {
    EXPECT_LE(cov[i].get<double>(), 1.0);
    EXPECT_GE(cov[i].get<double>(), 0.0);
    if (i + 1 < cov.size()) {
      EXPECT_GE(cov[i].get<double>(), cov[i + 1].get<double>());
    }
    EXPECT_EQ(summary["levels"][i]["screen_coverage"], cov[i]);
  }
  EXPECT_EQ(cov[3].get<double>(), 0.0);
  // Unclamped coverages invert to the next level's switch distance.
  lodmodel::Camera cam;
  cam.fov_y_rad = 45 * M_PI / 180;
  cam.height_px = 1080;
  const double radius = summary["bounding_radius_m"];
  for (std::size_t i = 0; i + 1 < cov.size(); ++i)
    if (cov[i].get<double>() < 1) {
      EXPECT_NEAR(lodmodel::coverage_distance(cam, radius, cov[i]),
                  summary["levels"][i + 1]["switch_distance_m"].get<double>(), 1e-9);
    }
}

// Each level's node extras carry its numbers, the ones of its lod.json entry; lod.json reads
// back through libs/lodchain.
void expect_level_extras(const nlohmann::json& j, const nlohmann::json& summary, const fs::path& out) {
  for (int i = 0; i < 4; ++i) {
    const auto& ex = j["nodes"][i]["extras"];
    EXPECT_GT(ex["epsilon_m"].get<double>(), 0);
    EXPECT_EQ(ex["pixel_error_px"].get<double>(), 0.5);
    EXPECT_GT(ex["switch_distance_m"].get<double>(), 0);
    EXPECT_TRUE(ex["counts"].contains("lines"));
  }
  // lod.json reads back through libs/lodchain (its one reader), and each level's node extras
  // (level_extras(), written beside it) carry the numbers of its lod.json entry.
  const lodchain::LodChain chain = lodchain::read_lod_chain((out / "lod.json").string());
  EXPECT_EQ(chain.levels.size(), 4u);
  for (int i = 0; i < 4; ++i)
    for (const auto& [key, value] : j["nodes"][i]["extras"].items()) {
      if (key != "MSFT_screencoverage") {
        EXPECT_EQ(summary["levels"][i][key], value) << i << " " << key;
      }
    }
}

// Line primitives use a BLEND material whose alpha is the level's; no tangents anywhere; every
// material is used; the species' foliage is counted.
void expect_materials(const nlohmann::json& j, const nlohmann::json& summary, const std::string& species) {
  bool saw_lines = false;
  std::set<int> used;
  for (const auto& mesh : j["meshes"])
    for (const auto& p : mesh["primitives"]) {
      used.insert(p["material"].get<int>());
      EXPECT_FALSE(p["attributes"].contains("TANGENT"));
      if (p.value("mode", 4) == 1) {
        saw_lines = true;
        EXPECT_EQ(j["materials"][p["material"].get<int>()]["alphaMode"], "BLEND");
      }
    }
  EXPECT_TRUE(saw_lines);
  EXPECT_EQ(used.size(), j["materials"].size());
  EXPECT_FALSE(j.contains("images"));  // no atlas in this test
  EXPECT_NEAR(summary["levels"][3]["epsilon_m"].get<double>(), 0.22, 1e-12);
  if (species == "oak")
    EXPECT_GT(summary["levels"][0]["counts"]["leaves"].get<int>(), 0);
  else
    EXPECT_GT(summary["levels"][0]["counts"]["needle_lines"].get<int>() +
                  summary["levels"][0]["counts"]["needle_quads"].get<int>(),
              0);
}

// Leaf winding: (b - a) x (c - a) points along the vertex normal, for every leaf triangle of
// every level.
void expect_leaf_winding(const fs::path& out, const std::string& species) {
  std::size_t leaf_triangles = 0, against = 0;
  for (int i = 0; i < 4; ++i) {
    const nlohmann::json lj = read_json(out / ("lod" + std::to_string(i) + ".gltf"));
    for (const auto& p : lj["meshes"][0]["primitives"]) {
      if (lj["materials"][p["material"].get<int>()]["name"] != "leaves") continue;
      const auto pos = accessor<float>(out, lj, p["attributes"]["POSITION"]);
      const auto nrm = accessor<float>(out, lj, p["attributes"]["NORMAL"]);
      const auto idx = indices(out, lj, p["indices"]);
      for (std::size_t k = 0; k + 2 < idx.size(); k += 3) {
        auto at = [&](std::size_t v, int c) { return double(pos[3 * idx[k + v] + c]); };
        const double e1[3] = {at(1, 0) - at(0, 0), at(1, 1) - at(0, 1), at(1, 2) - at(0, 2)};
        const double e2[3] = {at(2, 0) - at(0, 0), at(2, 1) - at(0, 1), at(2, 2) - at(0, 2)};
        const double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        const float* n = &nrm[3 * idx[k]];
        ++leaf_triangles;
        if (g[0] * n[0] + g[1] * n[1] + g[2] * n[2] <= 0) ++against;
      }
    }
  }
  if (species == "oak") {
    EXPECT_GT(leaf_triangles, 1000u);
  }
  EXPECT_EQ(against, 0u) << species << ": " << against << " of " << leaf_triangles << " leaf triangles";
}

// Ribbons: no LINES; buffer 0 is the level's .bin, the ribbons in their own .bin.
void expect_ribbons(const nlohmann::json& summary, const fs::path& out, std::vector<fs::path>& to_validate) {
  for (const auto& l : summary["levels"]) {
    if (!l.contains("ribbons_file")) continue;
    const nlohmann::json rj = read_json(out / l["ribbons_file"].get<std::string>());
    const std::string level_bin = l["file"].get<std::string>().substr(0, 4) + ".bin";
    const std::string ribbon_bin = l["ribbons_file"].get<std::string>().substr(0, 12) + ".bin";
    EXPECT_TRUE(rj["buffers"][0]["uri"] == level_bin ||
                (rj["buffers"].size() == 1 && rj["buffers"][0]["uri"] == ribbon_bin))
        << rj["buffers"];
    for (const auto& p : rj["meshes"][0]["primitives"]) EXPECT_EQ(p.value("mode", 4), 4);
    to_validate.push_back(out / l["ribbons_file"].get<std::string>());
  }
}

// The stage on a young oak (leaves) and a young Scots pine (needles). Files: lod.gltf links
// every level with MSFT_lod and reads the levels' own lod<i>.bin (bytes stored once); lod<i>.gltf
// and lod.json exist; levels with lines have a ribbons variant without LINES whose buffer 0 is
// lod<i>.bin. Screen coverages are screen fractions: non-increasing, in [0, 1], last 0, and
// coverage_distance() inverts them; full.glb, the full-detail model, is a GLB with more triangles
// than level 0. No tangents, no unused material or image; every leaf
// triangle is wound counter-clockwise around its own normal (the issue-10 defect: all of them
// were clockwise). Every file passes the glTF-Validator.
TEST(LodStage, WritesLinkedChainPerLevelFilesAndSummary) {
  const auto stage = make_lod_stage();
  std::vector<fs::path> to_validate;
  sylva::test::TempDir tmp;
  for (const std::string species : {"oak", "scots_pine"}) {
    const fs::path in = tmp / (species + "_in"), out = tmp / (species + "_out");
    fs::create_directories(in);
    fs::create_directories(out);
    tree::Tree t = lod::test::species_tree(
        fs::path(SYLVA_SOURCE_DIR) / "configs/species" / (species + ".yaml"), "young");
    t.materials.leaf_texture.clear();
    t.materials.bark_texture.clear();
    tree::write_sylt(in / "tree.sylt", t);
    FakeContext ctx(*stage, in, out, {{"levels", Value(4)}, {"ribbons", Value(true)}});
    stage->run(ctx);
    const std::set<std::string> extra = declared_beyond_levels(ctx.declared);
    const nlohmann::json summary = read_json(out / "lod.json");
    ASSERT_EQ(summary["levels"].size(), 4u);
    const std::set<std::string> ribbon_files = ribbon_files_of(summary);
    EXPECT_EQ(extra, ribbon_files);
    ASSERT_NO_FATAL_FAILURE(expect_full_detail(out, to_validate));
    EXPECT_FALSE(ribbon_files.empty());  // the coarse levels have lines

    const nlohmann::json j = read_json(out / "lod.gltf");
    ASSERT_NO_FATAL_FAILURE(expect_levels_linked(j, out));
    ASSERT_NO_FATAL_FAILURE(expect_screen_coverages(j, summary));
    expect_level_extras(j, summary, out);
    expect_materials(j, summary, species);
    expect_leaf_winding(out, species);
    expect_ribbons(summary, out, to_validate);
    for (const char* f : {"lod.gltf", "lod0.gltf", "lod3.gltf"}) to_validate.push_back(out / f);
  }
  const auto results = sylva::test::validate_gltf(to_validate);
  for (const auto& v : results) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << "\n" << v.report;
    EXPECT_EQ(v.warnings, 0) << v.file << "\n" << v.report;
  }
}

// A tree without colours (an imported TreeQSM tree): the levels' bark and leaves get the mesh
// stage's defaults, not black (issue 10: every LOD of the QSM coffee tree had [0, 0, 0, 1] bark).
TEST(LodStage, TreeWithoutColoursGetsTheMeshStageDefaults) {
  const tree::Tree t = lod::test::helix(1, 2, 1, 16, 0.05);
  ASSERT_EQ(t.materials.bark_color, tree::Color{});
  lod::ChainOptions o;
  o.levels = 2;
  const std::vector<lod::Level> levels = lod::build_chain(t, o);
  const gltf::Scene s = lod::level_scene(t, levels[0], 0, {});
  ASSERT_FALSE(s.materials.empty());
  EXPECT_EQ(s.materials[0].name, "bark");
  EXPECT_EQ(s.materials[0].base_color, tree::kDefaultBarkColor);
}

// Bad input: a missing tree.sylt and a decreasing explicit ladder are StageErrors.
TEST(LodStage, RejectsBadInput) {
  const auto stage = make_lod_stage();
  sylva::test::TempDir tmp;
  fs::create_directories(tmp / "in");
  fs::create_directories(tmp / "out");
  FakeContext empty(*stage, tmp / "in", tmp / "out");
  EXPECT_THROW(stage->run(empty), StageError);
  tree::write_sylt(tmp / "in" / "tree.sylt", lod::test::helix(1, 2, 1, 16, 0.05));
  FakeContext bad(*stage, tmp / "in", tmp / "out",
                  {{"errors_m", Value(Value::List{Value(0.1), Value(0.05)})}});
  EXPECT_THROW(stage->run(bad), StageError);
}

}  // namespace
}  // namespace sylva
