// The lod artifact's glTF metadata (libs/lodchain/chain_gltf.h): what the writer puts on nodes,
// that the reader gets it back, and one exact message per class of bad chain or level file.
#include "libs/lodchain/chain_gltf.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

namespace sylva::lodchain {
namespace {

using Json = nlohmann::json;

Level level(std::uint64_t i, double epsilon) {
  Level l;
  l.sylva_lod_level = i;
  l.epsilon_m = epsilon;
  l.pixel_error_px = 0.5;
  l.switch_distance_m = epsilon * 2607.5;
  l.e1_m = epsilon / 4;
  l.line_alpha = 0.375;
  l.counts = {10, 20, 30, 40, 0, 0, 500, 60};
  l.file = level_file(i);
  l.screen_coverage = 0.25;
  return l;
}

TEST(ChainGltf, FileNames) {
  EXPECT_EQ(level_name(3), "lod3");
  EXPECT_EQ(level_file(3), "lod3.gltf");
  EXPECT_EQ(level_bin(0), "lod0.bin");
  EXPECT_EQ(ribbons_file(5), "lod5_ribbons.gltf");
  EXPECT_EQ(ribbons_bin(5), "lod5_ribbons.bin");
  EXPECT_STREQ(kSummaryFile, "lod.json");
  EXPECT_STREQ(kChainFile, "lod.gltf");
  EXPECT_STREQ(kFullDetailFile, "full.glb");
  EXPECT_STREQ(kLeafImageFile, "leaves.png");
  EXPECT_EQ(LodChain().chain_file, "lod.gltf");
}

// The level's numbers, without its files, coverage or cards; integers stay integers.
TEST(ChainGltf, LevelExtrasAreTheNumbersOfTheLevel) {
  const Json j = level_extras(level(2, 0.004));
  EXPECT_EQ(j.size(), 15u);
  EXPECT_TRUE(j["sylva_lod_level"].is_number_unsigned());
  EXPECT_EQ(j["sylva_lod_level"], 2);
  EXPECT_EQ(j["epsilon_m"], 0.004);
  EXPECT_EQ(j["switch_distance_m"], 0.004 * 2607.5);
  EXPECT_EQ(j["E1_m"], 0.001);
  EXPECT_EQ(j["line_alpha"], 0.375);
  EXPECT_EQ(j["counts"]["internodes"], 500);
  EXPECT_FALSE(j.contains("file"));
  EXPECT_FALSE(j.contains("screen_coverage"));
}

// Three nodes: 0 the root, 1 and 2 the coarser levels.
struct Chain {
  std::vector<Json> extras, extensions;
  std::vector<int> roots = {0};
  std::vector<ChainLevelNumbers> read(std::size_t levels) const {
    return read_chain_levels(roots, extras.size(), levels, [&](std::size_t n) {
      return ChainNode{&extras[n], &extensions[n]};
    });
  }
};

Chain linked_chain() {
  Chain c;
  for (std::uint64_t i = 0; i < 3; ++i) {
    c.extras.push_back(level_extras(level(i, 0.001 * double(i + 1))));
    c.extensions.push_back(nullptr);
  }
  link_levels(c.extras[0], c.extensions[0], {0, 1, 2}, {1.0, 0.5, 0.0});
  return c;
}

TEST(ChainGltf, LinkThenReadBack) {
  const Chain c = linked_chain();
  EXPECT_EQ(c.extensions[0], Json::parse(R"({"MSFT_lod": {"ids": [1, 2]}})"));
  EXPECT_EQ(c.extras[0]["MSFT_screencoverage"], Json::parse("[1.0, 0.5, 0.0]"));
  const std::vector<ChainLevelNumbers> l = c.read(3);
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[2].node, 2);
  EXPECT_EQ(l[1].epsilon_m, 0.002);
  EXPECT_EQ(l[1].pixel_error_px, 0.5);
  EXPECT_EQ(l[1].switch_distance_m, 0.002 * 2607.5);
  EXPECT_EQ(l[1].screen_coverage, 0.5);
  // One level: coverage only, no MSFT_lod.
  Json extras = Json::object(), extensions;
  link_levels(extras, extensions, {0}, {0.0});
  EXPECT_TRUE(extensions.is_null());
  EXPECT_EQ(extras["MSFT_screencoverage"], Json::parse("[0.0]"));
}

// The message read_chain_levels gives for the linked chain after `edit`, or "(no error)".
std::string error_after(const std::function<void(Chain&)>& edit, std::size_t levels = 3) {
  Chain c = linked_chain();
  edit(c);
  try {
    c.read(levels);
  } catch (const ChainGltfError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ChainGltf, OneMessagePerBadChain) {
  EXPECT_EQ(error_after([](Chain&) {}), "(no error)");
  EXPECT_EQ(error_after([](Chain& c) { c.roots = {0, 1}; }), "the lod chain has not exactly one root node");
  EXPECT_EQ(error_after([](Chain& c) { c.roots = {3}; }), "the lod chain has not exactly one root node");
  EXPECT_EQ(error_after([](Chain&) {}, 2),
            "the lod chain's MSFT_lod names 3 levels, but 2 level files were given");
  EXPECT_EQ(error_after([](Chain& c) { c.extensions[0] = nullptr; }),
            "the lod chain's MSFT_lod names 1 levels, but 3 level files were given");
  EXPECT_EQ(error_after([](Chain& c) { c.extras[0].erase("MSFT_screencoverage"); }),
            "the lod chain's root has no MSFT_screencoverage for every level");
  EXPECT_EQ(error_after([](Chain& c) { c.extensions[0]["MSFT_lod"]["ids"][1] = 7; }),
            "MSFT_lod names node 7, which does not exist");
  EXPECT_EQ(error_after([](Chain& c) { c.extensions[0]["MSFT_lod"]["ids"][0] = "one"; }),
            "MSFT_lod names node -1, which does not exist");
  EXPECT_EQ(error_after([](Chain& c) { c.extras[0]["MSFT_screencoverage"][1] = "half"; }),
            "MSFT_screencoverage[1] is not a number");
  EXPECT_EQ(error_after([](Chain& c) { c.extras[2].erase("switch_distance_m"); }),
            "level 2 (node 2) has no numeric extras.switch_distance_m");
  EXPECT_EQ(error_after([](Chain& c) { c.extras[1]["epsilon_m"] = "small"; }),
            "level 1 (node 1) has no numeric extras.epsilon_m");
}

TEST(ChainGltf, PackedLevelExtrasKeepTheLevelsNumbers) {
  const Json full = level_extras(level(4, 0.01));
  const Json kept = level_number_extras(full);
  EXPECT_EQ(kept, Json({{"sylva_lod_level", 4u},
                        {"epsilon_m", 0.01},
                        {"pixel_error_px", 0.5},
                        {"switch_distance_m", 0.01 * 2607.5}}));
  EXPECT_EQ(level_number_extras(full, 12.5)["switch_distance_m"], 12.5);
  EXPECT_EQ(level_number_extras(Json::object({{"epsilon_m", 1}}), 12.5), Json({{"epsilon_m", 1}}));
  EXPECT_EQ(level_number_extras(nullptr), Json::object());
  EXPECT_EQ(impostor_level_extras(3, "billboards", 0.2, 0.5, 600), Json({{"sylva_lod_level", 3u},
                                                                         {"kind", "impostor"},
                                                                         {"impostor_kind", "billboards"},
                                                                         {"epsilon_m", 0.2},
                                                                         {"pixel_error_px", 0.5},
                                                                         {"switch_distance_m", 600}}));
}

TEST(ChainGltf, LevelFileNamesItsBufferThenItsImages) {
  const std::string text =
      R"({"buffers": [{"uri": "lod1.bin", "byteLength": 96}],
          "images": [{"uri": "leaves.png"}, {"bufferView": 0}, {"uri": "bark.png"}]})";
  std::vector<std::string> asked;
  const LevelFile f = parse_level_file(text, "lod1.gltf", [&](const std::string& uri, LevelResource kind) {
    asked.push_back((kind == LevelResource::kBuffer ? "buffer " : "image ") + uri);
  });
  EXPECT_EQ(asked, (std::vector<std::string>{"buffer lod1.bin", "image leaves.png", "image bark.png"}));
  EXPECT_EQ(f.buffer_uri, "lod1.bin");
  EXPECT_EQ(f.buffer_bytes, 96u);
  EXPECT_EQ(f.image_uris, (std::vector<std::string>{"leaves.png", "bark.png"}));
  EXPECT_EQ(f.gltf["buffers"][0]["byteLength"], 96);
}

TEST(ChainGltf, OneMessagePerBadLevelFile) {
  auto message = [](const std::string& text) {
    try {
      parse_level_file(text, "lod1.gltf", [](const std::string&, LevelResource) {});
    } catch (const ChainGltfError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message(R"({"buffers": [{"uri": "a.bin"}, {"uri": "b.bin"}]})"),
            "lod1.gltf must have exactly one external buffer");
  EXPECT_EQ(message(R"({"buffers": [{"byteLength": 4}]})"),
            "lod1.gltf must have exactly one external buffer");
  EXPECT_EQ(message("{").rfind("unreadable lod output: [json.exception.parse_error", 0), 0u);
  EXPECT_EQ(message(R"({"asset": {}})").rfind("unreadable lod output: [json.exception.out_of_range", 0), 0u);
  EXPECT_EQ(message(R"({"buffers": [{"uri": "a.bin"}]})").rfind("unreadable lod output: ", 0), 0u);
  // What the reader's check throws passes through.
  EXPECT_THROW(
      parse_level_file(R"({"buffers": [{"uri": "a.bin", "byteLength": 4}]})", "lod1.gltf",
                       [](const std::string&, LevelResource) { throw std::runtime_error("absent"); }),
      std::runtime_error);
}

}  // namespace
}  // namespace sylva::lodchain
