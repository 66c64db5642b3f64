// meshopt_files.h: .gltf files sharing .bin buffers (a forest's level file and the tiles that
// instance it) compressed together: every view of every file decodes (meshoptimizer's decoders,
// as three.js's MeshoptDecoder runs them) to the bytes it viewed before (triangles up to a
// rotation of their corners), files viewing the same bytes point at the same compressed bytes,
// the .bin files shrink, the files stay validator-clean, and files that cannot take part are left
// byte for byte.
#include "libs/gltf/meshopt_files.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <array>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "libs/gltf/scene.h"
#include "libs/gltf/testing/rotated_triangles.h"
#include "libs/gltf/testing/shared_buffer_files.h"
#include "libs/gltf/writer.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::gltf {
namespace {

using nlohmann::json;

using testing::rotated_triangles;

GltfFileSet sample_set(int instances = 3) { return testing::level_and_tile(instances); }

// Every view of `name` in `out` holds what the same view held in `in`; returns the modes seen.
std::set<std::string> expect_same_views(const GltfFileSet& in, const GltfFileSet& out,
                                        const std::string& name) {
  const json a = json::parse(in.gltf.at(name)), b = json::parse(out.gltf.at(name));
  EXPECT_EQ(a["accessors"], b["accessors"]);  // only views and buffers change
  EXPECT_EQ(a["meshes"], b["meshes"]);
  EXPECT_EQ(a["nodes"], b["nodes"]);
  std::set<std::string> modes;
  for (std::size_t v = 0; v < a["bufferViews"].size(); ++v) {
    SCOPED_TRACE(name + " view " + std::to_string(v));
    const json& va = a["bufferViews"][v];
    const json& vb = b["bufferViews"][v];
    const std::string before_uri = a["buffers"][std::size_t(va["buffer"])]["uri"];
    const std::size_t length = va["byteLength"];
    const std::string expected =
        in.bins.at(before_uri).substr(va.value("byteOffset", std::size_t(0)), length);
    if (!vb.contains("extensions")) {
      const std::string uri = b["buffers"][std::size_t(vb["buffer"])]["uri"];
      EXPECT_TRUE(out.bins.at(uri).substr(vb.value("byteOffset", std::size_t(0)), length) == expected);
      modes.insert("raw");
      continue;
    }
    const json& e = vb["extensions"]["EXT_meshopt_compression"];
    const json& fb = b["buffers"][std::size_t(vb["buffer"])];
    EXPECT_FALSE(fb.contains("uri"));
    EXPECT_EQ(fb["extensions"]["EXT_meshopt_compression"]["fallback"], true);
    EXPECT_EQ(vb["byteLength"], length);
    const std::string uri = b["buffers"][std::size_t(e["buffer"])]["uri"];
    EXPECT_EQ(uri, before_uri);
    const std::string& bin = out.bins.at(uri);
    EXPECT_EQ(b["buffers"][std::size_t(e["buffer"])]["byteLength"], bin.size());
    const std::size_t count = e["count"], stride = e["byteStride"], size = e["byteLength"];
    EXPECT_EQ(count * stride, length);
    const auto* src = reinterpret_cast<const unsigned char*>(bin.data()) + std::size_t(e["byteOffset"]);
    std::string decoded(length, '\0');
    const std::string mode = e["mode"];
    modes.insert(mode);
    int rc = -1;
    if (mode == "ATTRIBUTES") rc = meshopt_decodeVertexBuffer(decoded.data(), count, stride, src, size);
    if (mode == "TRIANGLES") rc = meshopt_decodeIndexBuffer(decoded.data(), count, stride, src, size);
    if (mode == "INDICES") rc = meshopt_decodeIndexSequence(decoded.data(), count, stride, src, size);
    EXPECT_EQ(rc, 0) << mode;
    if (mode == "TRIANGLES")
      EXPECT_EQ(rotated_triangles(decoded, stride), rotated_triangles(expected, stride));
    else
      EXPECT_TRUE(decoded == expected) << mode << ": decoded bytes differ";
  }
  return modes;
}

TEST(GltfMeshoptFiles, SharedBuffersDecodeToTheSameBytes) {
  const GltfFileSet in = sample_set();
  MeshoptFilesStats stats;
  const GltfFileSet out = meshopt_compress_files(in, &stats);
  EXPECT_EQ(meshopt_compress_files(in).gltf, out.gltf);  // deterministic
  EXPECT_EQ(meshopt_compress_files(in).bins, out.bins);
  ASSERT_EQ(out.gltf.size(), 2u);
  ASSERT_EQ(out.bins.size(), 2u);
  EXPECT_EQ(expect_same_views(in, out, "level.gltf"),
            (std::set<std::string>{"ATTRIBUTES", "TRIANGLES", "INDICES"}));
  EXPECT_EQ(expect_same_views(in, out, "tile.gltf"),
            (std::set<std::string>{"raw", "ATTRIBUTES", "TRIANGLES", "INDICES"}));
  // The level and the tile view the level's bytes through the same compressed ranges.
  const json lv = json::parse(out.gltf.at("level.gltf")), tv = json::parse(out.gltf.at("tile.gltf"));
  for (std::size_t v = 0; v < lv["bufferViews"].size(); ++v)
    EXPECT_EQ(lv["bufferViews"][v]["extensions"], tv["bufferViews"][v]["extensions"]) << v;
  // The tile's 3 instance translations (36 bytes) would grow through the codec: stored raw.
  EXPECT_FALSE(tv["bufferViews"].back().contains("extensions"));
  EXPECT_EQ(out.bins.at("tile.bin"), in.bins.at("tile.bin"));
  EXPECT_EQ(tv["extensionsRequired"], json({"EXT_mesh_gpu_instancing", "EXT_meshopt_compression"}));
  EXPECT_EQ(stats.views_compressed, lv["bufferViews"].size());
  EXPECT_EQ(stats.views_raw, 1u);
  EXPECT_EQ(stats.bin_bytes_before, in.bins.at("level.bin").size() + in.bins.at("tile.bin").size());
  EXPECT_LT(out.bins.at("level.bin").size(), in.bins.at("level.bin").size() * 3 / 4);
  EXPECT_EQ(stats.bin_bytes_after, out.bins.at("level.bin").size() + out.bins.at("tile.bin").size());

  test::TempDir dir;
  for (const auto& [name, text] : out.gltf) test::write_file(dir / name, text);
  for (const auto& [name, bytes] : out.bins) test::write_file(dir / name, bytes);
  SYLVA_EXPECT_VALID_GLTF(dir / "level.gltf");
  SYLVA_EXPECT_VALID_GLTF(dir / "tile.gltf");
}

// A tile of 500 instances: its instancing attribute goes through the vertex codec too.
TEST(GltfMeshoptFiles, InstancingAttributesAreCompressed) {
  const GltfFileSet in = sample_set(500);
  const GltfFileSet out = meshopt_compress_files(in);
  EXPECT_EQ(expect_same_views(in, out, "tile.gltf"),
            (std::set<std::string>{"ATTRIBUTES", "TRIANGLES", "INDICES"}));
  const json tv = json::parse(out.gltf.at("tile.gltf"));
  EXPECT_EQ(tv["bufferViews"].back()["extensions"]["EXT_meshopt_compression"]["mode"], "ATTRIBUTES");
  EXPECT_LT(out.bins.at("tile.bin").size(), in.bins.at("tile.bin").size());
  test::TempDir dir;
  for (const auto& [name, text] : out.gltf) test::write_file(dir / name, text);
  for (const auto& [name, bytes] : out.bins) test::write_file(dir / name, bytes);
  SYLVA_EXPECT_VALID_GLTF(dir / "tile.gltf");
}

// Views used otherwise (two accessors over one view, an image) are copied raw at their new offset.
TEST(GltfMeshoptFiles, OtherViewsAreCopiedRaw) {
  GltfFileSet in = sample_set();
  json g = json::parse(in.gltf.at("level.gltf"));
  g["accessors"].push_back(g["accessors"][0]);  // a second accessor over the positions' view
  in.gltf["level.gltf"] = g.dump(1) + "\n";
  const GltfFileSet out = meshopt_compress_files(in);
  EXPECT_EQ(expect_same_views(in, out, "level.gltf"),
            (std::set<std::string>{"raw", "ATTRIBUTES", "TRIANGLES", "INDICES"}));
  // The tile views the same bytes as plain positions: viewed two ways, they stay raw for both.
  const json tv = json::parse(out.gltf.at("tile.gltf"));
  EXPECT_FALSE(tv["bufferViews"][std::size_t(g["accessors"][0]["bufferView"])].contains("extensions"));
  expect_same_views(in, out, "tile.gltf");
}

// A file with a data: uri keeps its bytes, and so does every .bin it shares and every file naming
// one of those.
TEST(GltfMeshoptFiles, FilesThatCannotTakePartAreLeftAsTheyAre) {
  GltfFileSet in = sample_set();
  json g = json::parse(in.gltf.at("tile.gltf"));
  g["buffers"].push_back({{"uri", "data:application/octet-stream;base64,AAAA"}, {"byteLength", 3}});
  in.gltf["tile.gltf"] = g.dump(1) + "\n";
  const GltfFileSet out = meshopt_compress_files(in);
  EXPECT_EQ(out.gltf, in.gltf);
  EXPECT_EQ(out.bins, in.bins);
}

TEST(GltfMeshoptFiles, ErrorsNameTheFile) {
  GltfFileSet in = sample_set();
  in.bins.erase("tile.bin");
  try {
    meshopt_compress_files(in);
    FAIL();
  } catch (const GltfError& e) {
    EXPECT_STREQ(e.what(), "tile.gltf: buffer 'tile.bin' is not among the files");
  }
  in = sample_set();
  in.bins["tile.bin"].resize(8);
  try {
    meshopt_compress_files(in);
    FAIL();
  } catch (const GltfError& e) {
    const std::size_t last = json::parse(in.gltf.at("tile.gltf"))["bufferViews"].size() - 1;
    EXPECT_EQ(std::string(e.what()),
              "tile.gltf: bufferViews[" + std::to_string(last) + "] lies outside 'tile.bin'");
  }
  // A number no double holds is the file's error too, not nlohmann's out_of_range escaping.
  in = sample_set();
  in.gltf["tile.gltf"] = "{\"asset\": {\"version\": 1e999}}";
  try {
    meshopt_compress_files(in);
    FAIL();
  } catch (const GltfError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("tile.gltf: not valid JSON (", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace sylva::gltf
