// EXT_meshopt_compression over external buffers (a pack's forest tiles and level files,
// libs/gltf/meshopt_files.h) in load_gltf_scene: the compressed .gltf loads to the scene the
// uncompressed one gives (meshopt_decode.h meshopt_gltf_as_glb), and a missing or short buffer
// file is a one-line error naming the .gltf and the buffer.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "libs/gltf/meshopt_files.h"
#include "libs/gltf/testing/shared_buffer_files.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/meshopt_decode.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

void write_set(const gltf::GltfFileSet& set, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (const auto& [name, text] : set.gltf) test::write_file(dir / name, text);
  for (const auto& [name, bytes] : set.bins) test::write_file(dir / name, bytes);
}

// Triangles as sets of corner positions (the index codec may rotate a triangle's corners).
std::multiset<std::vector<float>> triangles(const Primitive& p) {
  std::multiset<std::vector<float>> out;
  for (std::size_t k = 0; k + 2 < p.indices.size(); k += 3) {
    std::vector<std::vector<float>> c;
    for (int i = 0; i < 3; ++i) {
      const Vec3& v = p.positions.at(p.indices[k + std::size_t(i)]);
      c.push_back({v.x(), v.y(), v.z()});
    }
    const std::size_t r = c[0] <= c[1] && c[0] <= c[2] ? 0 : (c[1] <= c[2] ? 1 : 2);
    std::vector<float> t;
    for (int i = 0; i < 3; ++i)
      t.insert(t.end(), c[(r + std::size_t(i)) % 3].begin(), c[(r + std::size_t(i)) % 3].end());
    out.insert(t);
  }
  return out;
}

TEST(MeshoptGltf, CompressedFilesLoadToTheSceneOfTheUncompressedOnes) {
  test::TempDir dir;
  const gltf::GltfFileSet plain = gltf::testing::level_and_tile();
  const gltf::GltfFileSet packed = gltf::meshopt_compress_files(plain);
  ASSERT_NE(packed.gltf.at("tile.gltf").find("\"EXT_meshopt_compression\""), std::string::npos);
  write_set(plain, dir / "plain");
  write_set(packed, dir / "packed");
  for (const char* name : {"level.gltf", "tile.gltf"}) {
    SCOPED_TRACE(name);
    const Scene a = load_gltf_scene(dir / "plain" / name), b = load_gltf_scene(dir / "packed" / name);
    EXPECT_EQ(b.triangle_count(), a.triangle_count());
    EXPECT_EQ(b.line_count(), a.line_count());
    ASSERT_EQ(b.meshes.size(), 1u);
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(b.meshes[0].instances.size(), std::string(name) == "tile.gltf" ? 3u : 1u);
    for (std::size_t i = 0; i < a.meshes[0].instances.size(); ++i)
      EXPECT_EQ(b.meshes[0].instances[i], a.meshes[0].instances[i]) << i;
    ASSERT_EQ(b.meshes[0].primitives.size(), 2u);
    EXPECT_EQ(triangles(b.meshes[0].primitives[0]), triangles(a.meshes[0].primitives[0]));
    EXPECT_EQ(b.meshes[0].primitives[1].positions, a.meshes[0].primitives[1].positions);
    EXPECT_EQ(b.meshes[0].primitives[1].indices, a.meshes[0].primitives[1].indices);
  }
}

TEST(MeshoptGltf, AMissingOrShortBufferFileNamesTheGltfAndTheBuffer) {
  test::TempDir dir;
  const gltf::GltfFileSet packed = gltf::meshopt_compress_files(gltf::testing::level_and_tile());
  write_set(packed, dir.path());
  const std::string length = std::to_string(packed.bins.at("level.bin").size());
  std::filesystem::resize_file(dir / "level.bin", 10);
  const std::string tile = (dir / "tile.gltf").string();
  try {
    load_gltf_scene(dir / "tile.gltf");
    FAIL() << "loaded";
  } catch (const SceneLoadError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what, tile + ": error: buffer 0 ('level.bin') has 10 bytes, byteLength says " + length);
  }
  std::filesystem::remove(dir / "level.bin");
  try {
    load_gltf_scene(dir / "tile.gltf");
    FAIL() << "loaded";
  } catch (const SceneLoadError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(tile + ": error: cannot read buffer 'level.bin' (", 0), 0u) << what;
  }
}

// Text that is not glTF JSON, or does not use the extension, is left to tinygltf (nothing read).
TEST(MeshoptGltf, OtherTextIsNotConverted) {
  int reads = 0;
  const auto read = [&](const std::string&) {
    ++reads;
    return std::string();
  };
  EXPECT_FALSE(meshopt_gltf_as_glb("{\"asset\": {\"version\": \"2.0\"}}", read));
  EXPECT_FALSE(meshopt_gltf_as_glb("not json \"EXT_meshopt_compression\"", read));
  EXPECT_FALSE(meshopt_gltf_as_glb("{\"extensionsUsed\": [\"EXT_meshopt_compression\"]}", read));
  EXPECT_EQ(reads, 0);
}

}  // namespace
}  // namespace sylva::render
