// libs/pack manifest: canonical bytes, a lossless round trip, precise errors, and the diff.
#include "libs/pack/manifest.h"

#include <gtest/gtest.h>

#include <string>

namespace sylva::pack {
namespace {

const std::string kDigestA(64, 'a');

LodLevel named(std::string file) {
  LodLevel l;
  l.file = std::move(file);
  return l;
}

// A level with every number set (bytes: the size of "level zero").
LodLevel level0() {
  LodLevel l;
  l.file = "oak_lod0.glb";
  l.epsilon_m = 0.001;
  l.pixel_error_px = 0.5;
  l.switch_distance_m = 2.5;
  l.screen_coverage = 0.75;
  l.primitives = 1234;
  l.triangles = 1200;
  l.lines = 34;
  l.bytes = 10;
  l.position_bits = 15;
  l.position_error_m = 0.0002;
  return l;
}

Manifest sample() {
  Manifest m;
  Producer p{"pack", 1, {{"lod/lod0.gltf", kDigestA}}};
  m.files.push_back(describe_file("oak_lod0.glb", "level zero", p));
  m.files.push_back(describe_file("oak.glb", "chain", p));
  m.files.push_back(describe_file("oak.lod.json", "{}", p));
  m.species.push_back({"oak", "oak.glb", "oak.lod.json", {level0()}, ""});
  return m;
}

TEST(PackManifest, DescribesAFile) {
  const FileEntry e = describe_file("a/b.glb", "abc", {});
  EXPECT_EQ(e.sha256,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");  // FIPS 180-2 "abc"
  EXPECT_EQ(e.size, 3u);
  EXPECT_EQ(e.media_type, "model/gltf-binary");
  EXPECT_EQ(media_type_for("x.gltf"), "model/gltf+json");
  EXPECT_EQ(media_type_for("oak.lod.json"), "application/json");
  EXPECT_EQ(media_type_for("leaves.png"), "image/png");
  EXPECT_EQ(media_type_for("source0.jpg"), "image/jpeg");  // an imported tree's level 0 image
  EXPECT_EQ(media_type_for("lod0.bin"), "application/octet-stream");
}

TEST(PackManifest, BytesAreCanonicalAndRoundTrip) {
  Manifest m = sample();
  const std::string text = write_manifest(m);
  // Files sorted by path whatever their order in memory; keys sorted; a final newline.
  Manifest shuffled = m;
  std::swap(shuffled.files[0], shuffled.files[2]);
  EXPECT_EQ(write_manifest(shuffled), text);
  EXPECT_LT(text.find("\"oak.glb\""), text.find("\"oak.lod.json\""));
  EXPECT_LT(text.find("\"oak.lod.json\""), text.find("\"oak_lod0.glb\""));
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text.find("\"total_bytes\": 17"), std::string::npos) << text;
  const Manifest back = parse_manifest(text, "m.json");
  EXPECT_EQ(write_manifest(back), text);
  ASSERT_EQ(back.files.size(), 3u);
  const FileEntry* f = back.file("oak_lod0.glb");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->producer.stage, "pack");
  EXPECT_EQ(f->producer.stage_version, 1);
  EXPECT_EQ(f->producer.inputs.at("lod/lod0.gltf"), kDigestA);
  EXPECT_EQ(back.species, m.species);
}

TEST(PackManifest, WriteRefusesDuplicatesAndUnlistedChainFiles) {
  Manifest m = sample();
  m.files.push_back(m.files[0]);
  EXPECT_THROW(write_manifest(m), ManifestError);
  m = sample();
  m.species[0].levels.push_back(named("oak_lod1.glb"));
  try {
    write_manifest(m);
    FAIL();
  } catch (const ManifestError& e) {
    EXPECT_STREQ(e.what(), "manifest: species 'oak' names 'oak_lod1.glb', which is not in the pack");
  }
}

std::string error_of(const std::string& text) {
  try {
    parse_manifest(text, "m.json");
  } catch (const ManifestError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PackManifest, ReadErrorsNameTheElement) {
  const std::string good = write_manifest(sample());
  EXPECT_EQ(error_of("{\n  \"format\": 1,\n  x"), "m.json:3:3: not valid JSON");
  EXPECT_EQ(error_of("{\"format\": 1e999}"), "m.json: not valid JSON (a number out of range)");
  EXPECT_EQ(error_of("[]"), "m.json: (root): expected an object");
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  EXPECT_EQ(error_of(replaced("\"version\": 4", "\"version\": 7")),
            "m.json: version: 7 is not supported (this sylva reads versions 1 to 4)");
  EXPECT_EQ(error_of(replaced("\"path\": \"oak.glb\"", "\"path\": \"../oak.glb\"")),
            "m.json: files[0].path: '../oak.glb' is not a plain relative path");
  EXPECT_EQ(error_of(replaced("\"size\": 5", "\"size\": -5")),
            "m.json: files[0].size: expected a non-negative integer");
  EXPECT_EQ(error_of(replaced("\"total_bytes\": 17", "\"total_bytes\": 23")),
            "m.json: total_bytes: 23 is not the sum of the files' sizes (17)");
  const std::string first_digest = sample().file("oak.glb")->sha256;
  EXPECT_EQ(error_of(replaced(first_digest, "ABC")),
            "m.json: files[0].sha256: expected 64 lowercase hex digits");
  EXPECT_EQ(error_of(replaced("\"chain\": \"oak.glb\"", "\"chain\": \"pine.glb\"")),
            "m.json: species[0].chain: 'pine.glb' is not in files");
}

Manifest with_forest() {
  Manifest m = sample();
  Producer p{"pack", 4, {{"forest/tileset.json", kDigestA}}};
  for (const char* name : {"tileset.json", "instances.json", "tile_0_0_lod0.gltf", "tile_0_0.bin"})
    m.files.push_back(describe_file(name, name, p));
  m.files.push_back(describe_file("oak_impostor.glb", "cards", p));
  LodLevel impostor = named("oak_impostor.glb");
  impostor.kind = "impostor";
  impostor.impostor_kind = "billboards";
  impostor.source_level = -1;
  impostor.bytes = 5;  // "cards"
  m.species[0].levels.push_back(impostor);
  m.species[0].impostor = "oak_impostor.glb";
  m.forests.push_back({"forest",
                       "tileset.json",
                       "instances.json",
                       {"tile_0_0_lod0.gltf"},
                       {"instances.json", "tile_0_0.bin", "tile_0_0_lod0.gltf", "tileset.json"}});
  return m;
}

TEST(PackManifest, ForestsAndImpostorsRoundTrip) {
  const Manifest m = with_forest();
  const std::string text = write_manifest(m);
  EXPECT_NE(text.find("\"forests\": [\n    {\n      \"files\": [\n        \"instances.json\""),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\"impostor\": \"oak_impostor.glb\""), std::string::npos);
  const Manifest back = parse_manifest(text, "m.json");
  EXPECT_EQ(back.forests, m.forests);
  EXPECT_EQ(back.species, m.species);
  EXPECT_EQ(back.file("tile_0_0.bin")->media_type, "application/octet-stream");
  EXPECT_EQ(media_type_for("cameras.yaml"), "application/yaml");
  // A forest naming an unlisted file is refused on write and on read.
  Manifest bad = m;
  bad.forests[0].tiles.push_back("tile_9_9_lod0.gltf");
  try {
    write_manifest(bad);
    FAIL();
  } catch (const ManifestError& e) {
    EXPECT_STREQ(e.what(), "manifest: forest 'forest' names 'tile_9_9_lod0.gltf', which is not in the pack");
  }
  std::string t = text;
  const std::string from = "\"tileset\": \"tileset.json\"";
  t.replace(t.find(from), from.size(), "\"tileset\": \"tiles.json\"");
  EXPECT_EQ(error_of(t), "m.json: forests[0].tileset: 'tiles.json' is not in files");
}

// Version 3 states every level's numbers, as lod.json does; they round-trip exactly, a level whose
// bytes are not its file's size is refused, and a missing number is named.
TEST(PackManifest, LevelsCarryTheirNumbers) {
  const std::string text = write_manifest(sample());
  EXPECT_NE(
      text.find("\"levels\": [\n        {\n          \"bytes\": 10,\n          \"epsilon_m\": 0.001,\n"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("\"switch_distance_m\": 2.5"), std::string::npos);
  EXPECT_NE(text.find("\"position_bits\": 15"), std::string::npos);
  const Manifest back = parse_manifest(text, "m.json");
  ASSERT_EQ(back.species[0].levels.size(), 1u);
  EXPECT_EQ(back.species[0].levels[0], level0());
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  EXPECT_EQ(error_of(replaced("\"bytes\": 10", "\"bytes\": 11")),
            "m.json: species[0].levels[0].bytes: 11 is not the size of 'oak_lod0.glb' (10)");
  EXPECT_EQ(error_of(replaced("\"epsilon_m\": 0.001,\n", "")),
            "m.json: species[0].levels[0]: missing \"epsilon_m\"");
  EXPECT_EQ(error_of(replaced("\"switch_distance_m\": 2.5", "\"switch_distance_m\": \"far\"")),
            "m.json: species[0].levels[0].switch_distance_m: expected a number");
  EXPECT_EQ(error_of(replaced("\"kind\": \"mesh\"", "\"kind\": \"cloud\"")),
            "m.json: species[0].levels[0].kind: expected \"mesh\" or \"impostor\"");
}

// Version 4: a level may carry the image error the pack measured; it round-trips exactly and its
// fields are checked like the others.
TEST(PackManifest, LevelsCarryTheirMeasuredError) {
  Manifest m = sample();
  m.species[0].levels[0].measured = MeasuredError{0.00015, 0.0019, true};
  const std::string text = write_manifest(m);
  EXPECT_NE(text.find("\"measured\": {\n            \"coverage_mean_error\": 0.0019,\n            "
                      "\"failing_fraction\": 0.00015,\n            \"passed\": true\n          }"),
            std::string::npos)
      << text;
  const Manifest back = parse_manifest(text, "m.json");
  EXPECT_EQ(back.species[0].levels[0], m.species[0].levels[0]);
  std::string t = text;
  const std::string from = "\"passed\": true";
  t.replace(t.find(from), from.size(), "\"passed\": 1");
  EXPECT_EQ(error_of(t), "m.json: species[0].levels[0].measured.passed: expected true or false");
}

// Version 2: levels are file names; read as levels with the file only.
TEST(PackManifest, ReadsVersionTwoLevelNames) {
  std::string text = write_manifest(sample());
  const std::string v = "\"version\": 4";
  text.replace(text.find(v), v.size(), "\"version\": 2");
  const std::size_t from = text.find("\"levels\": [");
  const std::size_t to = text.find("]", from);
  text.replace(from, to + 1 - from, "\"levels\": [\"oak_lod0.glb\"]");
  const Manifest back = parse_manifest(text, "m.json");
  EXPECT_EQ(back.version, 2);
  ASSERT_EQ(back.species[0].levels.size(), 1u);
  EXPECT_EQ(back.species[0].levels[0], named("oak_lod0.glb"));
  // Written back, it is a version 4 manifest.
  EXPECT_NE(write_manifest(back).find("\"version\": 4"), std::string::npos);
}

TEST(PackManifest, ReadsVersionOneWithoutForests) {
  std::string text = write_manifest(sample());
  const std::string v = "\"version\": 4", forests = "\"forests\": [],\n";
  text.replace(text.find(v), v.size(), "\"version\": 1");
  ASSERT_NE(text.find(forests), std::string::npos) << text;
  text.erase(text.find(forests), forests.size());
  const std::size_t from = text.find("\"levels\": [");
  text.replace(from, text.find("]", from) + 1 - from, "\"levels\": [\"oak_lod0.glb\"]");
  const Manifest back = parse_manifest(text, "m.json");
  EXPECT_EQ(back.version, 1);
  EXPECT_TRUE(back.forests.empty());
  ASSERT_EQ(back.species.size(), 1u);
  EXPECT_EQ(back.species[0].levels, std::vector<LodLevel>{named("oak_lod0.glb")});
}

TEST(PackManifest, DiffListsAddedChangedRemoved) {
  const Manifest old_m = sample();
  Manifest new_m = sample();
  new_m.files[0] = describe_file("oak_lod0.glb", "level zero, again", {});     // changed
  new_m.files.erase(new_m.files.begin() + 2);                                  // oak.lod.json removed
  new_m.files.push_back(describe_file("pine.glb", "p", {}));                   // added
  new_m.files.push_back(describe_file("oak.glb", "chain", {"other", 9, {}}));  // same bytes: unchanged
  new_m.files.erase(new_m.files.begin() + 1);
  const ManifestDiff d = diff_manifests(old_m, new_m);
  EXPECT_EQ(d.added, std::vector<std::string>{"pine.glb"});
  EXPECT_EQ(d.changed, std::vector<std::string>{"oak_lod0.glb"});
  EXPECT_EQ(d.removed, std::vector<std::string>{"oak.lod.json"});
  EXPECT_TRUE(diff_manifests(old_m, old_m).empty());
}

}  // namespace
}  // namespace sylva::pack
