// Stage pack merging other packs (docs/stages/pack.md, "Merging packs"): the files and the
// manifest entries of each pack input, byte for byte, and clear errors for inputs that do not
// agree with their own manifests or that collide.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "libs/pack/manifest.h"
#include "stages/pack/pack_stage.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::FakeStageContext;

// A sub-pack directory as a pack node writes it: species `name`'s chain, one level and its
// lod.json, and its manifest (levels carry their numbers: version 3).
pack::Manifest write_species_pack(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  const pack::Producer producer{"pack", 6, {{"lod/lod0.gltf", std::string(64, 'c')}}};
  pack::Manifest m;
  for (const auto& [file, bytes] : {std::pair<std::string, std::string>{name + ".glb", "chain of " + name},
                                    {name + "_lod0.glb", "level zero of " + name},
                                    {name + ".lod.json", "{\"species\": \"" + name + "\"}"}}) {
    test::write_file(dir / file, bytes);
    m.files.push_back(pack::describe_file(file, bytes, producer));
  }
  pack::LodLevel level;
  level.file = name + "_lod0.glb";
  level.epsilon_m = 0.001;
  level.pixel_error_px = 0.5;
  level.switch_distance_m = 2.5;
  level.primitives = 12;
  level.bytes = m.file(level.file)->size;
  m.species.push_back({name, name + ".glb", name + ".lod.json", {level}, ""});
  test::write_file(dir / "manifest.json", pack::write_manifest(m));
  return m;
}

pack::Manifest write_forest_pack(const fs::path& dir) {
  fs::create_directories(dir);
  pack::Manifest m;
  for (const std::string file : {"tileset.json", "instances.json", "tile_0_0_lod0.gltf"}) {
    test::write_file(dir / file, file + " bytes");
    m.files.push_back(pack::describe_file(file, file + " bytes", {"pack", 6, {}}));
  }
  m.forests.push_back({"forest",
                       "tileset.json",
                       "instances.json",
                       {"tile_0_0_lod0.gltf"},
                       {"instances.json", "tile_0_0_lod0.gltf", "tileset.json"}});
  test::write_file(dir / "manifest.json", pack::write_manifest(m));
  return m;
}

std::string run_error(const std::vector<FakeStageContext::Input>& inputs, const fs::path& out) {
  const auto stage = make_pack_stage();
  FakeStageContext ctx(*stage, inputs, out);
  try {
    stage->run(ctx);
  } catch (const StageError& e) {
    return e.what();
  }
  return "";
}

TEST(PackMerge, CopiesEveryFileAndEntryOfEachPackInput) {
  test::TempDir tmp;
  const pack::Manifest oak = write_species_pack(tmp.path() / "oak", "oak");
  const pack::Manifest birch = write_species_pack(tmp.path() / "birch", "birch");
  const pack::Manifest forest = write_forest_pack(tmp.path() / "forest");
  const fs::path out = tmp.path() / "out";
  fs::create_directories(out);
  const auto stage = make_pack_stage();
  FakeStageContext ctx(*stage,
                       {{"pack_oak", "pack", tmp.path() / "oak"},
                        {"pack_birch", "pack", tmp.path() / "birch"},
                        {"pack_forest", "pack", tmp.path() / "forest"}},
                       out);
  stage->run(ctx);
  const pack::Manifest merged = pack::read_manifest(out / "manifest.json");
  ASSERT_EQ(merged.files.size(), 9u);
  for (const pack::Manifest* sub : {&oak, &birch, &forest})
    for (const pack::FileEntry& f : sub->files) {
      const pack::FileEntry* got = merged.file(f.path);
      ASSERT_NE(got, nullptr) << f.path;
      EXPECT_EQ(*got, f) << f.path;  // producer included: the node that made the file
      EXPECT_EQ(test::read_file(out / f.path).size(), f.size) << f.path;
    }
  EXPECT_EQ(test::read_file(out / "oak_lod0.glb"), "level zero of oak");
  ASSERT_EQ(merged.species.size(), 2u);
  EXPECT_EQ(merged.species[0].name, "birch");  // sorted by name
  EXPECT_EQ(merged.species[1].levels, oak.species[0].levels);
  ASSERT_EQ(merged.forests.size(), 1u);
  EXPECT_EQ(merged.forests[0], forest.forests[0]);
  EXPECT_EQ(ctx.declared.size(), 10u);  // the nine files and manifest.json
}

TEST(PackMerge, RefusesPacksThatDisagreeWithTheirManifestsOrCollide) {
  test::TempDir tmp;
  write_species_pack(tmp.path() / "oak", "oak");
  write_species_pack(tmp.path() / "oak2", "oak");
  const fs::path out = tmp.path() / "out";
  fs::create_directories(out);
  EXPECT_EQ(
      run_error({{"pack_oak", "pack", tmp.path() / "oak"}, {"pack_oak2", "pack", tmp.path() / "oak2"}}, out),
      "two files of the pack are named 'oak.glb': pack 'pack_oak' and pack 'pack_oak2'");

  write_species_pack(tmp.path() / "tampered", "elm");
  test::write_file(tmp.path() / "tampered" / "elm_lod0.glb", "level zero of elk");  // same size
  EXPECT_EQ(
      run_error({{"pack_elm", "pack", tmp.path() / "tampered"}}, out),
      "input 'pack_elm': 'elm_lod0.glb' is not the file its manifest describes (size or SHA-256 differs)");

  write_species_pack(tmp.path() / "extra", "ash");
  test::write_file(tmp.path() / "extra" / "stray.png", "x");
  EXPECT_EQ(run_error({{"pack_ash", "pack", tmp.path() / "extra"}}, out),
            "input 'pack_ash' has 'stray.png', which its manifest does not list");

  write_species_pack(tmp.path() / "missing", "yew");
  fs::remove(tmp.path() / "missing" / "yew.lod.json");
  EXPECT_EQ(run_error({{"pack_yew", "pack", tmp.path() / "missing"}}, out),
            "input 'pack_yew': its manifest lists 'yew.lod.json', which it does not have");

  fs::create_directories(tmp.path() / "empty");
  EXPECT_EQ(run_error({{"pack_x", "pack", tmp.path() / "empty"}}, out),
            "input 'pack_x' has no manifest.json (is it a pack node?)");
}

}  // namespace
}  // namespace sylva
