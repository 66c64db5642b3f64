// EXT_meshopt_compression over external buffers (a pack's forest tiles and level files,
// libs/gltf/meshopt_files.h) in load_gltf_scene: the compressed .gltf loads to the scene the
// uncompressed one gives (meshopt_decode.h meshopt_gltf_as_glb), and a missing or short buffer
// file is a one-line error naming the .gltf and the buffer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "libs/gltf/meshopt_files.h"
#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/meshopt_decode.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

using nlohmann::json;

// A level (a wavy grid of triangles and a polyline, "level.bin") and a tile instancing its mesh
// three times from "tile.bin", as the forest stage writes them.
gltf::GltfFileSet level_and_tile() {
  gltf::Scene s;
  gltf::Mesh m;
  gltf::Primitive t;
  const int n = 24;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), z = float(j) / float(n);
      t.positions.insert(t.positions.end(), {x, 0.1f * std::sin(7 * x) * std::cos(5 * z), z});
      t.normals.insert(t.normals.end(), {0, 1, 0});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [n](int a, int b) { return std::uint32_t(b * (n + 1) + a); };
      t.indices.insert(t.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      t.indices.insert(t.indices.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  m.primitives.push_back(t);
  gltf::Primitive l;
  l.mode = gltf::PrimitiveMode::kLines;
  for (int i = 0; i < 40; ++i) {
    l.positions.insert(l.positions.end(), {0, 0.05f * float(i), 0});
    if (i) l.indices.insert(l.indices.end(), {std::uint32_t(i - 1), std::uint32_t(i)});
  }
  m.primitives.push_back(l);
  s.meshes.push_back(m);
  s.buffer_uris = {"level.bin"};
  gltf::Node node;
  node.mesh = 0;
  s.nodes.push_back(node);
  s.roots = {0};
  const gltf::EncodedFiles e = gltf::encode_external(s);

  json g = json::parse(e.gltf);
  std::string bin;
  for (int k = 0; k < 3; ++k)
    for (float c : {float(k) * 10, 0.0f, float(k) * 3}) {
      char b[4];
      std::memcpy(b, &c, 4);
      bin.append(b, 4);
    }
  g["buffers"].push_back({{"uri", "tile.bin"}, {"byteLength", bin.size()}});
  g["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", bin.size()}});
  g["accessors"].push_back({{"bufferView", g["bufferViews"].size() - 1},
                            {"componentType", 5126},
                            {"count", 3},
                            {"type", "VEC3"},
                            {"min", {0, 0, 0}},
                            {"max", {20, 0, 6}}});
  g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] =
      g["accessors"].size() - 1;
  g["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  gltf::GltfFileSet set;
  set.gltf["level.gltf"] = e.gltf;
  set.gltf["tile.gltf"] = g.dump(1) + "\n";
  set.bins["level.bin"] = e.resources.at(0).bytes;
  set.bins["tile.bin"] = bin;
  return set;
}

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
  const gltf::GltfFileSet plain = level_and_tile();
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
  write_set(gltf::meshopt_compress_files(level_and_tile()), dir.path());
  std::filesystem::resize_file(dir / "level.bin", 10);
  const std::string tile = (dir / "tile.gltf").string();
  try {
    load_gltf_scene(dir / "tile.gltf");
    FAIL() << "loaded";
  } catch (const SceneLoadError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what, tile + ": error: buffer 0 ('level.bin') has 10 bytes, byteLength says 6420") << what;
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
