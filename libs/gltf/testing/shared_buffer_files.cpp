// The shared-buffer test files (shared_buffer_files.h).
#include "libs/gltf/testing/shared_buffer_files.h"

#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "libs/gltf/scene.h"
#include "libs/gltf/testing/sample_geometry.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf::testing {
namespace {

using nlohmann::json;

// A wavy grid of triangles with normals and uvs, and a polyline, in "level.bin".
EncodedFiles level(int n) {
  Scene s;
  Mesh m;
  m.primitives.push_back(wavy_grid(n));
  Primitive l;
  l.mode = PrimitiveMode::kLines;
  for (int i = 0; i < 40; ++i) {
    l.positions.insert(l.positions.end(), {0, 0.05f * float(i), 0});
    if (i) l.indices.insert(l.indices.end(), {std::uint32_t(i - 1), std::uint32_t(i)});
  }
  m.primitives.push_back(l);
  s.meshes.push_back(m);
  s.buffer_uris = {"level.bin"};
  Node node;
  node.mesh = 0;
  s.nodes.push_back(node);
  s.roots = {0};
  return encode_external(s);
}

void put_f32(std::string& out, float f) {
  char b[4];
  std::memcpy(b, &f, 4);
  out.append(b, 4);
}

// The level's JSON with a node instancing its mesh three times (TRANSLATION from "tile.bin", its
// buffer 1), as the forest's tile files are made.
std::pair<std::string, std::string> tile(const std::string& level_json, int instances = 3) {
  json g = json::parse(level_json);
  std::string bin;
  for (int i = 0; i < instances; ++i)
    for (float c : {float(i) * 10, 0.0f, float(i) * 3}) put_f32(bin, c);
  g["buffers"].push_back({{"uri", "tile.bin"}, {"byteLength", bin.size()}});
  g["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", bin.size()}});
  g["accessors"].push_back({{"bufferView", g["bufferViews"].size() - 1},
                            {"componentType", 5126},
                            {"count", instances},
                            {"type", "VEC3"},
                            {"min", {0, 0, 0}},
                            {"max", {10 * (instances - 1), 0, 3 * (instances - 1)}}});
  g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] =
      g["accessors"].size() - 1;
  g["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  return {g.dump(1) + "\n", bin};
}

}  // namespace

GltfFileSet level_and_tile(int instances) {
  const EncodedFiles l = level(30);
  GltfFileSet in;
  in.gltf["level.gltf"] = l.gltf;
  in.bins["level.bin"] = l.resources.at(0).bytes;
  auto [tile_json, tile_bin] = tile(l.gltf, instances);
  in.gltf["tile.gltf"] = tile_json;
  in.bins["tile.bin"] = tile_bin;
  return in;
}

}  // namespace sylva::gltf::testing
