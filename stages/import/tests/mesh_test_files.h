// Test helper: an in-memory fileio::FileSource (a model's sidecar files by path) and small
// glTF scenes built with libs/gltf's writer, for the mesh readers' tests.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "libs/fileio/file_source.h"
#include "libs/gltf/scene.h"

namespace sylva::import::testing {

class MapFiles final : public fileio::FileSource {
 public:
  std::map<std::string, std::string> files;  // lexically normal path -> bytes
  std::string read(const std::filesystem::path& path) const override {
    auto it = files.find(path.lexically_normal().string());
    if (it == files.end()) throw fileio::FileReadError(path.string(), "no such file");
    return it->second;
  }
  bool exists(const std::filesystem::path& path) const override {
    return files.count(path.lexically_normal().string()) > 0;
  }
};

// A unit square in x-y (two triangles, normals +z, uvs = xy), material `material`.
inline gltf::Primitive square(int material = -1) {
  gltf::Primitive p;
  p.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  p.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  p.texcoords = {0, 0, 1, 0, 1, 1, 0, 1};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = material;
  return p;
}

// The 8-byte PNG signature and an IHDR of a 1x1 RGBA image (colour type 6): enough for the
// import, which never decodes an image.
inline std::string tiny_png() {
  return std::string("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x01\0\0\0\x01\x08\x06\0\0\0", 29) +
         std::string(8, 'x');
}

}  // namespace sylva::import::testing
