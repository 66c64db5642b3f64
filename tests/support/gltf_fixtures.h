// glTF test fixtures shared by the libs/gltf, pack and clients tests: a tiny valid PNG to embed,
// and the two chunks of a GLB (to check the JSON a writer produced without a reader that would
// refuse compressed buffers).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace sylva::test {

// A 2x2 RGBA PNG, 75 bytes: the image of every textured test scene.
const std::string& tiny_png();

struct Glb {
  nlohmann::json json;
  std::string bin;  // empty when the file has no BIN chunk
};
// Splits GLB bytes into their JSON and BIN chunks; adds a gtest failure (and returns what it
// could read) when the magic or the declared total length is wrong.
Glb parse_glb(const std::string& bytes);

}  // namespace sylva::test
